//! Building an instance in code, with typed values, validated by the same rules as a file.
//!
//! The builder fills the file schema ([`super::file`]) and hands it to the one validator, so an
//! instance built in code and the same instance written as a file are identical, digest
//! included (the digest is taken over the builder's canonical JSON form).

use super::file::{ContainerFile, FrictionFile, GripperFile, InstanceFile, KindFile, ObjectFile, PlannerFile};
use super::Instance;
use crate::error::{Error, Result};
use crate::geometry::{Arm, BodyAxis};
use sha2::{Digest, Sha256};

/// Length unit of every length given to the builder.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Units {
    /// Metres (the default).
    #[default]
    Metres,
    /// Centimetres.
    Centimetres,
    /// Millimetres.
    Millimetres,
}

/// Which orientations an object may take in the container.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Orientations {
    /// Any of the six faces down, either way round: for packing-only studies (a top-down
    /// two-finger pick cannot turn a box over, docs/robot.md).
    Any,
    /// The face it stands on at the table stays down; only the 90° turn is free.
    Upright,
}

/// The gripper, in the builder's units. [`Default`] is the bundled gripper in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GripperSpec {
    /// Finger thickness along the closing direction.
    pub finger_thickness: f64,
    /// Finger width across the closing direction.
    pub finger_width: f64,
    /// How far the fingers reach down beside a box (they hang from the hand housing to the TCP).
    pub finger_length: f64,
    /// Largest opening between the fingers.
    pub max_opening: f64,
    /// How deep the fingers reach down a box when they grasp it.
    pub grasp_depth: f64,
    /// Gap left between a released box and the fingers, on each side.
    pub release_clearance: f64,
}

impl Default for GripperSpec {
    fn default() -> Self {
        GripperSpec {
            finger_thickness: 0.01,
            finger_width: 0.02,
            finger_length: 0.06,
            max_opening: 0.09,
            grasp_depth: 0.015,
            release_clearance: 0.005,
        }
    }
}

/// Builds an [`Instance`] in code. Required: [`container`](Self::container),
/// [`friction`](Self::friction), at least one [`kind`](Self::kind) and one
/// [`object`](Self::object); [`build`](Self::build) reports what is missing or invalid with the
/// field's name, exactly as the file loader would.
///
/// ```
/// use pushpack::instance::{InstanceBuilder, Orientations, Units};
/// let inst = InstanceBuilder::new("two-boxes")
///     .units(Units::Millimetres)
///     .container(300.0, 200.0, 100.0, 10.0, [300.0, 0.0])
///     .friction(0.35, 0.4, 0.6)
///     .gripper_mm_default()
///     .kind("block", [60.0, 40.0, 30.0], 0.05)
///     .object("a", "block", [250.0, 280.0], Orientations::Upright)
///     .object("b", "block", [250.0, -280.0], Orientations::Upright)
///     .build()?;
/// assert_eq!(inst.n(), 2);
/// # Ok::<(), pushpack::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct InstanceBuilder {
    name: String,
    units: Units,
    container: Option<ContainerFile>,
    friction: Option<FrictionFile>,
    gripper: GripperSpec,
    kinds: Vec<KindFile>,
    objects: Vec<ObjectFile>,
    planner: PlannerFile,
    arms: Option<Vec<Arm>>,
    regrasp: Option<bool>,
}

impl InstanceBuilder {
    /// A builder for an instance called `name`, in metres, with the bundled gripper.
    pub fn new(name: impl Into<String>) -> Self {
        InstanceBuilder {
            name: name.into(),
            units: Units::Metres,
            container: None,
            friction: None,
            gripper: GripperSpec::default(),
            kinds: Vec::new(),
            objects: Vec::new(),
            planner: PlannerFile::default(),
            arms: None,
            regrasp: None,
        }
    }

    /// The unit of every length given to the builder (gripper included).
    pub fn units(mut self, units: Units) -> Self {
        self.units = units;
        self
    }

    /// The open container: inner width (x) and depth (y), wall height and thickness, and the
    /// world (x, y) of the inner floor's centre.
    pub fn container(
        mut self,
        width: f64,
        depth: f64,
        wall_height: f64,
        wall_thickness: f64,
        center: [f64; 2],
    ) -> Self {
        self.container = Some(ContainerFile {
            width,
            depth,
            wall_height,
            wall_thickness,
            center,
            yaw: 0.0,
            floor_z: None,
        });
        self
    }

    /// Coulomb friction coefficients: box–floor, box–box, finger–box.
    pub fn friction(mut self, mu_floor: f64, mu_obj: f64, mu_finger: f64) -> Self {
        self.friction = Some(FrictionFile {
            mu_floor,
            mu_obj,
            mu_finger,
        });
        self
    }

    /// The gripper, in the builder's units.
    pub fn gripper(mut self, g: GripperSpec) -> Self {
        self.gripper = g;
        self
    }

    /// The bundled gripper expressed in millimetres (for builders in [`Units::Millimetres`]).
    pub fn gripper_mm_default(self) -> Self {
        let d = GripperSpec::default();
        let mm = |v: f64| v * 1000.0;
        self.gripper(GripperSpec {
            finger_thickness: mm(d.finger_thickness),
            finger_width: mm(d.finger_width),
            finger_length: mm(d.finger_length),
            max_opening: mm(d.max_opening),
            grasp_depth: mm(d.grasp_depth),
            release_clearance: mm(d.release_clearance),
        })
    }

    /// A kind of box: its body edges (x, y, z) and mass in kg.
    pub fn kind(mut self, name: impl Into<String>, size: [f64; 3], mass: f64) -> Self {
        self.kinds.push(KindFile {
            name: name.into(),
            size,
            mass,
            mu_floor: None,
            mu_obj: None,
            mu_finger: None,
        });
        self
    }

    /// A box of `kind` standing on its body z face at world `(x, y)` of the table.
    pub fn object(
        mut self,
        id: impl Into<String>,
        kind: impl Into<String>,
        xy: [f64; 2],
        orientations: Orientations,
    ) -> Self {
        self.objects.push(ObjectFile {
            id: id.into(),
            kind: kind.into(),
            x: xy[0],
            y: xy[1],
            yaw: 0.0,
            up: None,
            orientations: Some(
                match orientations {
                    Orientations::Any => "any",
                    Orientations::Upright => "upright",
                }
                .into(),
            ),
        });
        self
    }

    /// Like [`object`](Self::object), lying on another body face (`up` is the body axis that
    /// points up on the table) and turned by `yaw` radians.
    pub fn object_posed(
        mut self,
        id: impl Into<String>,
        kind: impl Into<String>,
        xy: [f64; 2],
        up: BodyAxis,
        yaw: f64,
        orientations: Orientations,
    ) -> Self {
        self = self.object(id, kind, xy, orientations);
        let o = self.objects.last_mut().expect("just pushed");
        o.up = Some(
            match up {
                BodyAxis::X => "x",
                BodyAxis::Y => "y",
                BodyAxis::Z => "z",
            }
            .into(),
        );
        o.yaw = yaw;
        self
    }

    /// Which arms may act (both by default).
    pub fn arms(mut self, arms: &[Arm]) -> Self {
        self.arms = Some(arms.to_vec());
        self
    }

    /// Whether the cell can regrasp a box (turn it over between pick and place).
    pub fn regrasp(mut self, yes: bool) -> Self {
        self.regrasp = Some(yes);
        self
    }

    /// Seed of every random choice of the planner.
    pub fn seed(mut self, seed: u64) -> Self {
        self.planner.seed = Some(seed);
        self
    }

    /// Time limit of a planning run, seconds.
    pub fn time_limit(mut self, seconds: f64) -> Self {
        self.planner.time_limit = Some(seconds);
        self
    }

    /// Validate and build. Errors name the field as the file loader would (source `<builder>`).
    pub fn build(self) -> Result<Instance> {
        const SOURCE: &str = "<builder>";
        let container = self
            .container
            .ok_or_else(|| Error::input(SOURCE, "container", "missing: call InstanceBuilder::container"))?;
        let friction = self
            .friction
            .ok_or_else(|| Error::input(SOURCE, "friction", "missing: call InstanceBuilder::friction"))?;
        let g = self.gripper;
        let robot = super::file::RobotFile {
            arms: self.arms.map(|a| a.iter().map(|a| a.name().to_string()).collect()),
            regrasp: self.regrasp,
            ..Default::default()
        };
        let file = InstanceFile {
            format_version: 1,
            name: Some(self.name),
            description: None,
            units: Some(
                match self.units {
                    Units::Metres => "m",
                    Units::Centimetres => "cm",
                    Units::Millimetres => "mm",
                }
                .into(),
            ),
            container,
            friction,
            gripper: GripperFile {
                finger_thickness: g.finger_thickness,
                finger_width: g.finger_width,
                finger_length: g.finger_length,
                max_opening: g.max_opening,
                grasp_depth: g.grasp_depth,
                release_clearance: g.release_clearance,
                min_offset: None,
                push_height: None,
                squeeze: None,
                max_effort: None,
            },
            robot,
            planner: self.planner,
            kinds: self.kinds,
            objects: self.objects,
        };
        // serde_json writes non-finite numbers as null; the validator then rejects the value
        // it was given, not the text, so the digest only needs to be stable.
        let canonical = serde_json::to_string(&file).expect("instance files serialise");
        let digest: String = Sha256::digest(canonical.as_bytes())
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        super::validate(file, SOURCE, None, digest)
    }
}
