//! Seeded random instances in the default work cell (SPEC §3), for tests and benchmarks.
//!
//! Kinds draw their edges uniformly from `size_range` on a grid of `step` (product sizes are
//! rarely arbitrary reals, and a coarser grid keeps the exact placement's grid small); objects
//! cycle through the kinds so every kind appears, then draw kinds at random. Table poses are
//! slots of a grid on both sides of the container (centres x 0.20…0.35 m, |y| 0.20…0.40 m),
//! assigned alternately to the left and right side; the pitch keeps every footprint apart.

use super::file::{
    ContainerFile, FrictionFile, GripperFile, InstanceFile, KindFile, ObjectFile, PlannerFile, RobotFile,
};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Parameters of a random instance.
#[derive(Debug, Clone, PartialEq)]
pub struct GenerateParams {
    /// Number of objects (1–24).
    pub objects: usize,
    /// Number of kinds (1..=objects).
    pub kinds: usize,
    /// Seed.
    pub seed: u64,
    /// Edge range of the horizontal edges (m), default 0.030–0.060.
    pub size_range: [f64; 2],
    /// Height range (m), default 0.025–0.055.
    pub height_range: [f64; 2],
    /// Edge grid (m), default 0.005.
    pub step: f64,
    /// `any` or `upright`.
    pub orientations: String,
}

impl GenerateParams {
    /// Defaults for `objects` objects of `kinds` kinds.
    pub fn new(objects: usize, kinds: usize, seed: u64) -> GenerateParams {
        GenerateParams {
            objects,
            kinds,
            seed,
            size_range: [0.030, 0.060],
            height_range: [0.025, 0.055],
            step: 0.005,
            orientations: "any".into(),
        }
    }
}

/// Table slots: 3 columns × 4 rows per side, 65 mm pitch (room for edges up to 60 mm).
fn slots() -> Vec<[f64; 2]> {
    let xs = [0.200, 0.265, 0.330];
    let ys = [0.200, 0.265, 0.330, 0.395];
    let mut out = Vec::new();
    for y in ys {
        for x in xs {
            out.push([x, y]);
            out.push([x, -y]);
        }
    }
    out
}

/// Most objects the table grid holds.
pub const MAX_OBJECTS: usize = 24;

/// Build a random instance file (validate it with [`super::Instance::parse`]).
pub fn random_instance(p: &GenerateParams) -> Result<InstanceFile, String> {
    if p.objects == 0 || p.objects > MAX_OBJECTS {
        return Err(format!("objects must be 1..={MAX_OBJECTS}, got {}", p.objects));
    }
    if p.kinds == 0 || p.kinds > p.objects {
        return Err(format!("kinds must be 1..={}, got {}", p.objects, p.kinds));
    }
    if !(p.step > 0.0
        && p.size_range[0] > 0.0
        && p.size_range[0] <= p.size_range[1]
        && p.size_range[1] <= 0.060 + 1e-12)
    {
        return Err("size range must be positive, ordered and at most 0.060 m (the table pitch)".into());
    }
    if !(p.height_range[0] > 0.0 && p.height_range[0] <= p.height_range[1]) {
        return Err("height range must be positive and ordered".into());
    }
    let mut rng = ChaCha8Rng::seed_from_u64(p.seed);
    let mut draw = |lo: f64, hi: f64| {
        let steps = ((hi - lo) / p.step + 1e-9).floor() as u64;
        let k = if steps == 0 { 0 } else { rng.random_range(0..=steps) };
        ((lo + k as f64 * p.step) * 1e6).round() / 1e6
    };
    let kinds: Vec<KindFile> = (0..p.kinds)
        .map(|k| {
            let a = draw(p.size_range[0], p.size_range[1]);
            let b = draw(p.size_range[0], p.size_range[1]);
            let c = draw(p.height_range[0], p.height_range[1]);
            let mass = (((a * b * c) * 600.0) * 1e4).round() / 1e4; // ~600 kg/m³ (wood, printed parts)
            KindFile {
                name: format!("k{k}"),
                size: [a, b, c],
                mass: mass.max(0.005),
                mu_floor: None,
                mu_obj: None,
                mu_finger: None,
            }
        })
        .collect();
    let mut rng2 = ChaCha8Rng::seed_from_u64(p.seed ^ 0x5eed);
    let slots = slots();
    let objects = (0..p.objects)
        .map(|i| {
            let kind = if i < p.kinds { i } else { rng2.random_range(0..p.kinds) };
            let [x, y] = slots[i];
            ObjectFile {
                id: format!("o{i:02}"),
                kind: format!("k{kind}"),
                x,
                y,
                yaw: 0.0,
                up: None,
                orientations: Some(p.orientations.clone()),
            }
        })
        .collect();
    Ok(InstanceFile {
        format_version: 1,
        name: Some(format!("random-n{:02}-k{}-s{}", p.objects, p.kinds, p.seed)),
        description: Some(format!(
            "pushpack generate --objects {} --kinds {} --seed {} (edges {}-{} m, heights {}-{} m, grid {} m, orientations {})",
            p.objects, p.kinds, p.seed, p.size_range[0], p.size_range[1], p.height_range[0], p.height_range[1], p.step, p.orientations
        )),
        units: None,
        container: ContainerFile {
            width: 0.30,
            depth: 0.20,
            wall_height: 0.10,
            wall_thickness: 0.01,
            center: [0.30, 0.0],
            yaw: 0.0,
            floor_z: None,
        },
        friction: FrictionFile { mu_floor: 0.35, mu_obj: 0.4, mu_finger: 0.6 },
        gripper: GripperFile {
            finger_thickness: 0.010,
            finger_width: 0.020,
            finger_length: 0.060,
            max_opening: 0.090,
            grasp_depth: 0.015,
            release_clearance: 0.005,
            min_offset: None,
            push_height: None,
            squeeze: None,
            max_effort: None,
        },
        robot: RobotFile::default(),
        planner: PlannerFile { seed: Some(p.seed), ..PlannerFile::default() },
        kinds,
        objects,
    })
}

/// The instance as TOML text.
pub fn to_toml(f: &InstanceFile) -> String {
    toml::to_string(f).expect("instance files serialise")
}

/// The consecutive-squares family (OEIS A038666): squares 1×1 … n×n in 2 mm units, upright, in
/// a container of `c` units (default: the sum of the sides, which never binds), as instance
/// TOML. A standard benchmark of exact rectangle packing; the tests and
/// `benches/placement_squares.rs` use it.
pub fn consecutive_squares_toml(n: u32, c: Option<(u32, u32)>) -> String {
    const U: u32 = 2;
    let s = n * (n + 1) / 2;
    let (cw, cd) = c.unwrap_or((s, s));
    let (cw, cd) = (cw * U, cd * U);
    let mut t = format!(
        "format_version = 1\nname = \"squares-{n}\"\nunits = \"mm\"\n[container]\nwidth = {cw}\ndepth = {cd}\n\
         wall_height = 60\nwall_thickness = 5\ncenter = [{}, 0]\n[friction]\nmu_floor = 0.35\nmu_obj = 0.4\n\
         mu_finger = 0.6\n[gripper]\nfinger_thickness = 10\nfinger_width = 20\nfinger_length = 60\n\
         max_opening = 90\ngrasp_depth = 15\nrelease_clearance = 5\n",
        300.0 + f64::from(cw) / 2.0
    );
    for i in 1..=n {
        t += &format!(
            "[[kinds]]\nname = \"s{i}\"\nsize = [{}, {}, 30]\nmass = 0.05\n",
            i * U,
            i * U
        );
    }
    for k in 0..n {
        let y = if (k / 2) % 2 == 1 { 1 } else { -1 } * (60 + 60 * (k / 4) as i32);
        t += &format!(
            "[[objects]]\nid = \"o{}\"\nkind = \"s{}\"\nx = {}\ny = {y}\norientations = \"upright\"\n",
            k + 1,
            k + 1,
            200 + 60 * (k % 2)
        );
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::instance::Instance;

    #[test]
    fn generated_instances_validate_and_are_deterministic() {
        for n in [1, 4, 8, 12, 16, 20, 24] {
            let p = GenerateParams::new(n, n.min(4), 7);
            let a = to_toml(&random_instance(&p).unwrap());
            let b = to_toml(&random_instance(&p).unwrap());
            assert_eq!(a, b);
            Instance::parse(&a, false, "<gen>", None).unwrap_or_else(|e| panic!("n={n}: {e}"));
        }
        assert!(random_instance(&GenerateParams::new(25, 2, 0)).is_err());
        assert!(random_instance(&GenerateParams::new(3, 4, 0)).is_err());
    }
}
