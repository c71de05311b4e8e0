//! Validating an instance file into an Instance: every field checked, named in errors, units converted.

use super::*;

/// The dotted field path of a deserialisation error: the serde path, completed with the name of a
/// missing field (serde reports those at the enclosing table); `<syntax>` for JSON syntax errors
/// that have no meaningful path, `<root>` for errors about the document as a whole. Blank or
/// odd keys (an unknown key `"  "`) are quoted so that the path is never empty.
pub(super) fn serde_field(path: &str, reason: &str, syntax: bool) -> String {
    let root = path == ".";
    if syntax && (root || path.contains('?')) {
        return "<syntax>".to_string();
    }
    let base = (!root).then(|| tidy_path(path));
    if let Some(rest) = reason.strip_prefix("missing field `") {
        if let Some(name) = rest.split('`').next().filter(|n| !n.is_empty()) {
            return match base {
                Some(b) => format!("{b}.{name}"),
                None => name.to_string(),
            };
        }
    }
    base.unwrap_or_else(|| "<root>".to_string())
}

/// Quote the segments of a dotted path that are empty or contain blanks or control characters.
pub(super) fn tidy_path(path: &str) -> String {
    path.split('.')
        .map(|s| {
            if s.is_empty() || s.chars().any(|c| c.is_whitespace() || c.is_control()) {
                format!("{s:?}")
            } else {
                s.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join(".")
}

/// Field-error helper bound to one source file.
pub(super) struct Check<'a> {
    pub(super) file: &'a str,
}

impl Check<'_> {
    pub(super) fn err(&self, field: impl Into<String>, reason: impl Into<String>) -> Error {
        Error::input(self.file, field, reason)
    }
    pub(super) fn finite(&self, field: &str, v: f64) -> Result<f64> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.err(field, format!("must be a finite number, got {v}")))
        }
    }
    pub(super) fn positive(&self, field: &str, v: f64) -> Result<f64> {
        self.finite(field, v)?;
        if v > 0.0 {
            Ok(v)
        } else {
            Err(self.err(field, format!("must be > 0, got {v}")))
        }
    }
    /// `v` > 0 and at most `max` (`shown` formats the numbers and their unit for the message).
    pub(super) fn positive_at_most(&self, field: &str, v: f64, max: f64, shown: impl Fn(f64) -> String) -> Result<f64> {
        let v = self.positive(field, v)?;
        if v > max {
            return Err(self.err(field, format!("must be at most {}, got {}", shown(max), shown(v))));
        }
        Ok(v)
    }
    pub(super) fn non_negative(&self, field: &str, v: f64) -> Result<f64> {
        self.finite(field, v)?;
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(self.err(field, format!("must be >= 0, got {v}")))
        }
    }
}

/// A length for messages: six decimals without trailing zeros, or scientific when very large or small.
pub(super) fn num(v: f64) -> String {
    if v == 0.0 || (1e-4..1e6).contains(&v.abs()) {
        let s = format!("{v:.6}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.4e}")
    }
}

/// `[a, b, c]` as `a x b x c`.
pub(super) fn fmt3(v: [f64; 3]) -> String {
    format!("{} x {} x {}", num(v[0]), num(v[1]), num(v[2]))
}

/// Distance from a point to a convex quadrilateral (0 inside).
pub(super) fn point_polygon_distance(p: [f64; 2], poly: &[[f64; 2]; 4]) -> f64 {
    let mut inside = true;
    let mut sign = 0.0;
    let mut best = f64::INFINITY;
    for k in 0..4 {
        let a = poly[k];
        let b = poly[(k + 1) % 4];
        let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
        let (px, py) = (p[0] - a[0], p[1] - a[1]);
        let cross = ex * py - ey * px;
        if cross != 0.0 {
            if sign == 0.0 {
                sign = cross.signum();
            } else if cross.signum() != sign {
                inside = false;
            }
        }
        let len2 = ex * ex + ey * ey;
        let t = if len2 > 0.0 {
            ((px * ex + py * ey) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (dx, dy) = (px - t * ex, py - t * ey);
        best = best.min((dx * dx + dy * dy).sqrt());
    }
    if inside {
        0.0
    } else {
        best
    }
}

pub(super) fn parse_axis(c: &Check, field: &str, s: Option<&str>) -> Result<BodyAxis> {
    match s.unwrap_or("z") {
        "x" | "+x" | "-x" => Ok(BodyAxis::X),
        "y" | "+y" | "-y" => Ok(BodyAxis::Y),
        "z" | "+z" | "-z" => Ok(BodyAxis::Z),
        other => Err(c.err(field, format!("must be one of x, y, z, got {other:?}"))),
    }
}

pub(super) fn resolve_model(c: &Check, rel: &str, base_dir: Option<&Path>) -> Result<PathBuf> {
    let p = Path::new(rel);
    let mut tried = Vec::new();
    if p.is_absolute() {
        tried.push(p.to_path_buf());
    } else {
        if let Some(b) = base_dir {
            tried.push(b.join(p));
        }
        tried.push(p.to_path_buf());
    }
    tried.iter().find(|t| t.is_file()).cloned().ok_or_else(|| {
        let list: Vec<String> = tried.iter().map(|t| t.display().to_string()).collect();
        c.err(
            "robot.model",
            format!("model file not found (looked at {})", list.join(", ")),
        )
    })
}

/// Validate an instance file into an [`Instance`]. The robot, planner and table-pose checks are
/// functions of their own; the container, friction, gripper, kinds and objects sections stay
/// inline for now (about 250 lines). They are straight runs of field checks in file order,
/// so the first bad field in the file is the one an error names, and later sections read
/// the values of earlier ones.
pub(super) fn validate(f: InstanceFile, source: &str, base_dir: Option<&Path>, digest: String) -> Result<Instance> {
    let c = Check { file: source };
    if f.format_version != 1 {
        return Err(c.err(
            "format_version",
            format!("only version 1 exists, got {}", f.format_version),
        ));
    }
    let scale = match f.units.as_deref().unwrap_or("m") {
        "m" => 1.0,
        "cm" => 0.01,
        "mm" => 0.001,
        other => return Err(c.err("units", format!("must be \"m\", \"cm\" or \"mm\", got {other:?}"))),
    };
    let l = |v: f64| v * scale;

    // Container.
    let cf = &f.container;
    let container = Container {
        width: l(c.positive("container.width", cf.width)?),
        depth: l(c.positive("container.depth", cf.depth)?),
        wall_height: l(c.positive("container.wall_height", cf.wall_height)?),
        wall_thickness: l(c.positive("container.wall_thickness", cf.wall_thickness)?),
        center: [
            l(c.finite("container.center[0]", cf.center[0])?),
            l(c.finite("container.center[1]", cf.center[1])?),
        ],
        yaw: c.finite("container.yaw", cf.yaw)?,
        floor_z: 0.0,
    };

    // Friction.
    let fr = &f.friction;
    let mu_floor = c.non_negative("friction.mu_floor", fr.mu_floor)?;
    let mu_obj = c.non_negative("friction.mu_obj", fr.mu_obj)?;
    let mu_finger = c.non_negative("friction.mu_finger", fr.mu_finger)?;

    // Gripper.
    let g = &f.gripper;
    let finger_thickness = l(c.positive("gripper.finger_thickness", g.finger_thickness)?);
    let release_clearance = l(c.non_negative("gripper.release_clearance", g.release_clearance)?);
    let min_offset_floor = finger_thickness + release_clearance;
    let min_offset = match g.min_offset {
        Some(v) => {
            let v = l(c.positive("gripper.min_offset", v)?);
            if v < min_offset_floor - 1e-12 {
                return Err(c.err(
                    "gripper.min_offset",
                    format!("must be >= finger_thickness + release_clearance = {min_offset_floor:.4} m, got {v:.4} m"),
                ));
            }
            v
        }
        None => min_offset_floor,
    };
    let gripper = Gripper {
        finger_thickness,
        finger_width: l(c.positive("gripper.finger_width", g.finger_width)?),
        finger_length: l(c.positive("gripper.finger_length", g.finger_length)?),
        max_opening: l(c.positive("gripper.max_opening", g.max_opening)?),
        grasp_depth: l(c.positive("gripper.grasp_depth", g.grasp_depth)?),
        release_clearance,
        min_offset,
        push_height: match g.push_height {
            Some(v) => l(c.non_negative("gripper.push_height", v)?),
            None => 0.005,
        },
        squeeze: match g.squeeze {
            Some(v) => l(c.non_negative("gripper.squeeze", v)?),
            None => Gripper::DEFAULT_SQUEEZE,
        },
        max_effort: match g.max_effort {
            Some(v) => c.positive("gripper.max_effort", v)?,
            None => Gripper::DEFAULT_MAX_EFFORT,
        },
    };

    if gripper.grasp_depth > gripper.finger_length + 1e-9 {
        return Err(c.err(
            "gripper.grasp_depth",
            format!(
                "must be at most finger_length = {:.4} m (the fingers cannot reach deeper), got {:.4} m",
                gripper.finger_length, gripper.grasp_depth
            ),
        ));
    }

    // Robot.
    let r = &f.robot;
    let table_z = match r.table_z {
        Some(v) => l(c.finite("robot.table_z", v)?),
        None => crate::robot::DEFAULT_TABLE_Z,
    };
    let mut container = container;
    container.floor_z = match cf.floor_z {
        Some(v) => l(c.finite("container.floor_z", v)?),
        None => table_z,
    };
    let robot = robot_cell(&c, r, scale, base_dir, table_z)?;
    // The fingers hang below the hand housing: a TCP inside or just below the housing would put
    // the housing on the objects it holds and pushes (the stock hand reaches 0.20 m down).
    for arm in [Arm::Left, Arm::Right] {
        let hand = robot.model.hand_bottom(arm);
        let below = Vector3::from(robot.tcp_offset).norm() - hand;
        if below < gripper.finger_length - 1e-9 {
            return Err(c.err(
                "robot.tcp_offset",
                format!(
                    "the TCP is {below:.4} m below the {} hand, which reaches {hand:.4} m below the wrist flange; \
                     the fingers (gripper.finger_length = {:.4} m) must fit between them: put the TCP at least \
                     {:.4} m from the flange",
                    arm.name(),
                    gripper.finger_length,
                    hand + gripper.finger_length
                ),
            ));
        }
    }

    // Planner settings.
    let settings = planner_settings(&c, &f.planner, scale)?;

    // Kinds.
    if f.kinds.is_empty() {
        return Err(c.err("kinds", "at least one kind is needed"));
    }
    let mut kinds = Vec::new();
    let mut kind_mu = Vec::new();
    for (i, k) in f.kinds.iter().enumerate() {
        let fld = |s: &str| format!("kinds[{i}].{s}");
        if k.name.trim().is_empty() {
            return Err(c.err(fld("name"), "must not be empty"));
        }
        if kinds.iter().any(|o: &Kind| o.name == k.name) {
            return Err(c.err(fld("name"), format!("duplicate kind name {:?}", k.name)));
        }
        let mut size = [0.0; 3];
        for (j, s) in size.iter_mut().enumerate() {
            let field = fld(&format!("size[{j}]"));
            *s = l(c.positive(&field, k.size[j])?);
            if *s < MIN_EDGE {
                return Err(c.err(
                    field,
                    format!(
                        "must be at least {MIN_EDGE} m (100 x the geometric tolerance), got {:e} m",
                        *s
                    ),
                ));
            }
        }
        let mass = c.positive(&fld("mass"), k.mass)?;
        let mf = match k.mu_floor {
            Some(v) => c.non_negative(&fld("mu_floor"), v)?,
            None => mu_floor,
        };
        let mo = match k.mu_obj {
            Some(v) => c.non_negative(&fld("mu_obj"), v)?,
            None => mu_obj,
        };
        let mg = match k.mu_finger {
            Some(v) => c.non_negative(&fld("mu_finger"), v)?,
            None => mu_finger,
        };
        kinds.push(Kind {
            name: k.name.clone(),
            size,
            mass,
        });
        kind_mu.push([mf, mo, mg]);
    }

    // Objects.
    if f.objects.is_empty() {
        return Err(c.err("objects", "at least one object is needed"));
    }
    let floor_area = container.width * container.depth;
    let mut objects: Vec<Object> = Vec::new();
    let mut min_area_sum = 0.0;
    for (i, o) in f.objects.iter().enumerate() {
        let fld = |s: &str| format!("objects[{i}].{s}");
        if o.id.trim().is_empty() {
            return Err(c.err(fld("id"), "must not be empty"));
        }
        if objects.iter().any(|p| p.id == o.id) {
            return Err(c.err(fld("id"), format!("duplicate object id {:?}", o.id)));
        }
        let kind = kinds
            .iter()
            .position(|k| k.name == o.kind)
            .ok_or_else(|| c.err(fld("kind"), format!("unknown kind {:?}", o.kind)))?;
        let up = parse_axis(&c, &fld("up"), o.up.as_deref())?;
        let table = TablePose {
            x: l(c.finite(&fld("x"), o.x)?),
            y: l(c.finite(&fld("y"), o.y)?),
            yaw: c.finite(&fld("yaw"), o.yaw)?,
            up,
        };
        let size = kinds[kind].size;
        // The default follows the gripper: a top-down two-finger pick cannot turn a box over,
        // so without a regrasp the face it stands on stays down and every plan stays
        // executable. `any` remains for packing-only studies (docs/formats.md).
        let default_rule = if robot.regrasp { "any" } else { "upright" };
        let candidates: Vec<Orientation> = match o.orientations.as_deref().unwrap_or(default_rule) {
            "any" => Orientation::all().to_vec(),
            "upright" => vec![Orientation { up, yaw90: false }, Orientation { up, yaw90: true }],
            other => {
                return Err(c.err(
                    fld("orientations"),
                    format!("must be \"any\" or \"upright\", got {other:?}"),
                ))
            }
        };
        let mut orientations: Vec<Orientation> = Vec::new();
        for ori in candidates {
            let (fp, h) = ori.dims(size);
            let fits =
                h <= container.wall_height + 1e-9 && fp[0] <= container.width + 1e-9 && fp[1] <= container.depth + 1e-9;
            let graspable = (fp[0] + 2.0 * gripper.release_clearance <= gripper.max_opening + 1e-9
                || fp[1] + 2.0 * gripper.release_clearance <= gripper.max_opening + 1e-9)
                && h > gripper.grasp_depth + 1e-9;
            let pushable = h > gripper.push_height + 1e-9;
            if fits && graspable && pushable && !orientations.iter().any(|q| q.dims(size) == ori.dims(size)) {
                orientations.push(ori);
            }
        }
        if orientations.is_empty() {
            return Err(c.err(
                fld("kind"),
                format!(
                    "object {:?} (size {} m) fits in none of its allowed orientations: it must fit the container \
                     ({} m), leave release_clearance on both sides within max_opening ({} m), and stand taller \
                     than grasp_depth ({} m) and push_height ({} m)",
                    o.id,
                    fmt3(size),
                    fmt3([container.width, container.depth, container.wall_height]),
                    num(gripper.max_opening),
                    num(gripper.grasp_depth),
                    num(gripper.push_height)
                ),
            ));
        }
        min_area_sum += orientations
            .iter()
            .map(|q| q.dims(size).0[0] * q.dims(size).0[1])
            .fold(f64::INFINITY, f64::min);
        let [mf, mo, mg] = kind_mu[kind];
        objects.push(Object {
            id: o.id.clone(),
            kind,
            size,
            mass: kinds[kind].mass,
            mu_floor: mf,
            mu_obj: mo,
            mu_finger: mg,
            table,
            orientations,
        });
    }
    if min_area_sum > floor_area + 1e-12 {
        return Err(c.err(
            "objects",
            format!("total footprint area {min_area_sum:.5} m² exceeds the container floor {floor_area:.5} m²"),
        ));
    }
    check_table_poses(&c, &objects, &container, &gripper, &robot, table_z)?;
    let name = f.name.clone().unwrap_or_else(|| {
        Path::new(source)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("instance")
            .to_string()
    });
    Ok(Instance {
        name,
        source: source.to_string(),
        digest,
        container,
        kinds,
        objects,
        gripper,
        robot,
        settings,
        file: f,
    })
}

/// The `[planner]` table, with the documented defaults.
fn planner_settings(c: &Check, p: &super::file::PlannerFile, scale: f64) -> Result<Settings> {
    let l = |v: f64| v * scale;
    let d = Settings::default();
    Ok(Settings {
        seed: p.seed.unwrap_or(d.seed),
        bl_orders: match p.bl_orders {
            Some(0) => return Err(c.err("planner.bl_orders", "must be >= 1")),
            Some(v) => v,
            None => d.bl_orders,
        },
        time_limit: match p.time_limit {
            Some(v) => c.positive_at_most("planner.time_limit", v, MAX_TIME_LIMIT, |x| format!("{x:e} s"))?,
            None => d.time_limit,
        },
        max_nodes: match p.max_nodes {
            Some(0) => return Err(c.err("planner.max_nodes", "must be >= 1")),
            Some(v) => v,
            None => d.max_nodes,
        },
        min_push_margin: match p.min_push_margin {
            Some(v) => l(c.non_negative("planner.min_push_margin", v)?),
            None => d.min_push_margin,
        },
        max_push_rotation: match p.max_push_rotation_deg {
            Some(v) => c
                .positive_at_most("planner.max_push_rotation_deg", v, MAX_PUSH_ROTATION_DEG, |x| {
                    format!("{x} degrees")
                })?
                .to_radians(),
            None => d.max_push_rotation,
        },
        max_push_drift: match p.max_push_drift {
            // Positive as written in the file (its units), at most the limit in metres.
            Some(v) => c.positive_at_most(
                "planner.max_push_drift",
                l(c.positive("planner.max_push_drift", v)?),
                MAX_PUSH_DRIFT,
                |x| format!("{} m", num(x)),
            )?,
            None => d.max_push_drift,
        },
        side_clearance: match p.side_clearance {
            Some(v) => {
                let m = l(c.non_negative("planner.side_clearance", v)?);
                if m > MAX_SIDE_CLEARANCE {
                    return Err(c.err(
                        "planner.side_clearance",
                        format!("must be at most {} m, got {} m", num(MAX_SIDE_CLEARANCE), num(m)),
                    ));
                }
                m
            }
            None => d.side_clearance,
        },
        side_contacts: p.side_contacts.unwrap_or(d.side_contacts),
        forbid_slots: p.forbid_slots.unwrap_or(d.forbid_slots),
        no_direct: p.no_direct.unwrap_or(false),
        no_multi_push: p.no_multi_push.unwrap_or(false),
        packing_only: p.packing_only.unwrap_or(false),
        max_offset_steps: match p.max_offset_steps {
            Some(v) if v == 0 || v > MAX_OFFSET_STEPS => {
                return Err(c.err(
                    "planner.max_offset_steps",
                    format!("must be 1..={MAX_OFFSET_STEPS}, got {v}"),
                ))
            }
            v => v,
        },
        dive_nodes: p.dive_nodes,
        joint_acceleration: match p.joint_acceleration {
            Some(v) => Some(c.positive("planner.joint_acceleration", v)?),
            None => None,
        },
        sample_dt: p
            .sample_dt
            .map(|v| c.positive_at_most("planner.sample_dt", v, MAX_SAMPLE_DT, |x| format!("{x} s")))
            .transpose()?,
    })
}

/// Table poses: no overlap with each other or with the container, tall enough to grasp, clear of
/// the hands at home, and reachable by an allowed arm.
fn check_table_poses(
    c: &Check,
    objects: &[Object],
    container: &Container,
    gripper: &Gripper,
    robot: &RobotCell,
    table_z: f64,
) -> Result<()> {
    let walls = container.outer_corners_world();
    for i in 0..objects.len() {
        let (fi, hi) = objects[i].table_footprint();
        for j in 0..i {
            let (fj, _) = objects[j].table_footprint();
            if convex_overlap(&fi, &fj) {
                return Err(c.err(
                    format!("objects[{i}]"),
                    format!(
                        "object {:?} overlaps object {:?} on the table",
                        objects[i].id, objects[j].id
                    ),
                ));
            }
        }
        if convex_overlap(&fi, &walls) {
            return Err(c.err(
                format!("objects[{i}]"),
                format!("object {:?} starts on top of the container", objects[i].id),
            ));
        }
        if hi <= gripper.grasp_depth + 1e-9 {
            return Err(c.err(
                format!("objects[{i}]"),
                format!(
                    "object {:?} is {:.4} m tall on the table, not taller than grasp_depth = {:.4} m: it cannot be picked up",
                    objects[i].id, hi, gripper.grasp_depth
                ),
            ));
        }
        // The hands hang at their home pose over the table: nothing may reach up into them.
        let hand_radius = gripper.max_opening / 2.0 + gripper.finger_thickness;
        for arm in [Arm::Left, Arm::Right] {
            let tcp = robot.home_tcp(arm);
            if table_z + hi > tcp.z && point_polygon_distance([tcp.x, tcp.y], &fi) < hand_radius {
                return Err(c.err(
                    format!("objects[{i}]"),
                    format!(
                        "object {:?} is {:.4} m tall but lies under the {} hand, whose fingertips hang {:.4} m above \
                         the table at the home pose: lower it or move it away from ({:.3}, {:.3})",
                        objects[i].id,
                        hi,
                        arm.name(),
                        tcp.z - table_z,
                        tcp.x,
                        tcp.y
                    ),
                ));
            }
        }
        let grasp = Vector3::new(
            objects[i].table.x,
            objects[i].table.y,
            table_z + hi - gripper.grasp_depth,
        );
        if !robot
            .arms
            .iter()
            .any(|a| robot.model.reachable_top_down(*a, &grasp, &robot.tcp_offset))
        {
            return Err(c.err(
                format!("objects[{i}]"),
                format!(
                    "object {:?} at ({:.3}, {:.3}) is out of reach of every allowed arm for a top-down grasp",
                    objects[i].id, objects[i].table.x, objects[i].table.y
                ),
            ));
        }
    }
    Ok(())
}

/// The `[robot]` table: the model (bundled or a URDF file), TCP, arms, home pose and clearances.
fn robot_cell(
    c: &Check,
    r: &super::file::RobotFile,
    scale: f64,
    base_dir: Option<&Path>,
    table_z: f64,
) -> Result<RobotCell> {
    let l = |v: f64| v * scale;
    let (model, model_path) = match &r.model {
        None => (RobotModel::bundled(), "<bundled>".to_string()),
        Some(rel) => {
            let path = resolve_model(c, rel, base_dir)?;
            let text =
                std::fs::read_to_string(&path).map_err(|e| c.err("robot.model", format!("{}: {e}", path.display())))?;
            let m = RobotModel::from_urdf_str(&text)
                .map_err(|e| c.err("robot.model", format!("{}: {e}", path.display())))?;
            (m, path.display().to_string())
        }
    };
    let tcp_offset = match r.tcp_offset {
        Some(t) => {
            for (i, v) in t.iter().enumerate() {
                c.finite(&format!("robot.tcp_offset[{i}]"), *v)?;
            }
            t.map(l)
        }
        None => crate::robot::DEFAULT_TCP_OFFSET,
    };
    let arms = match &r.arms {
        None => vec![Arm::Left, Arm::Right],
        Some(list) => {
            let mut arms = Vec::new();
            for (i, a) in list.iter().enumerate() {
                let arm = match a.as_str() {
                    "left" => Arm::Left,
                    "right" => Arm::Right,
                    other => {
                        return Err(c.err(
                            format!("robot.arms[{i}]"),
                            format!("must be \"left\" or \"right\", got {other:?}"),
                        ))
                    }
                };
                if !arms.contains(&arm) {
                    arms.push(arm);
                }
            }
            if arms.is_empty() {
                return Err(c.err("robot.arms", "at least one arm is needed"));
            }
            arms
        }
    };
    let home = match &r.home {
        None => NEXTAGE_INITIAL_POSE_DEG.map(|a| a.map(f64::to_radians)),
        Some(h) => {
            for (name, q) in [("left", &h.left), ("right", &h.right)] {
                for (i, v) in q.iter().enumerate() {
                    c.finite(&format!("robot.home.{name}[{i}]"), *v)?;
                }
            }
            [h.left, h.right]
        }
    };
    for arm in [Arm::Left, Arm::Right] {
        if let Err(e) = model.check_joint_limits(arm, &home[arm.index()]) {
            return Err(c.err(format!("robot.home.{}", arm.name()), e));
        }
    }
    let transfer_clearance = match r.transfer_clearance {
        Some(v) => l(c.non_negative("robot.transfer_clearance", v)?),
        None => 0.08,
    };
    let speed_scale = match r.speed_scale {
        Some(v) if !(v > 0.0 && v <= 1.0) => {
            return Err(c.err("robot.speed_scale", format!("must be in (0, 1], got {v}")));
        }
        Some(v) => v,
        None => super::DEFAULT_SPEED_SCALE,
    };
    Ok(RobotCell {
        model,
        model_path,
        tcp_offset,
        arms,
        home,
        table_z,
        transfer_clearance,
        regrasp: r.regrasp.unwrap_or(false),
        speed_scale,
    })
}
