//! Helpers shared by the integration tests: instance text builders and paths.
#![allow(dead_code)]

use pushpack::instance::Instance;

/// Path of a bundled instance, relative to the crate root.
pub fn bundled(rel: &str) -> String {
    format!("{}/instances/{rel}", env!("CARGO_MANIFEST_DIR"))
}

/// Load a bundled instance.
pub fn load(rel: &str) -> Instance {
    Instance::load(bundled(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// A small splitmix64 generator so tests need no extra crates and stay deterministic.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E3779B97F4A7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        z ^ (z >> 31)
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// A random instance in the default work cell: `n` boxes of up to `kinds` kinds, sizes in
/// whole millimetres between 30 and 70 mm, on a non-overlapping table grid.
pub fn random_instance_text(seed: u64, n: usize, kinds: usize, orientations: &str) -> String {
    random_instance_text_step(seed, n, kinds, orientations, 1)
}

/// Like [`random_instance_text`], with box edges on a grid of `step` millimetres.
pub fn random_instance_text_step(seed: u64, n: usize, kinds: usize, orientations: &str, step: usize) -> String {
    let mut r = Rng(seed);
    let mut s = String::from(
        "units = \"mm\"\n[container]\nwidth = 300\ndepth = 200\nwall_height = 100\nwall_thickness = 10\ncenter = [300, 0]\n\
         [friction]\nmu_floor = 0.35\nmu_obj = 0.4\nmu_finger = 0.6\n\
         [gripper]\nfinger_thickness = 10\nfinger_width = 20\nfinger_length = 60\nmax_opening = 90\ngrasp_depth = 15\nrelease_clearance = 5\n",
    );
    for k in 0..kinds {
        let a = 30 + step * r.below(40 / step + 1);
        let b = 30 + step * r.below(40 / step + 1);
        let c = 25 + step * r.below(30 / step + 1);
        s += &format!(
            "[[kinds]]\nname = \"k{k}\"\nsize = [{a}, {b}, {c}]\nmass = {:.3}\n",
            r.range(0.03, 0.12)
        );
    }
    // Table grid: 2 columns x 3 rows per side, 80 mm pitch.
    let slots: Vec<(i32, i32)> = [230, 310]
        .iter()
        .flat_map(|&x| [240, 320, 400].iter().flat_map(move |&y| [(x, y), (x, -y)]))
        .collect();
    for i in 0..n {
        let (x, y) = slots[i % slots.len()];
        let kind = if i < kinds { i } else { r.below(kinds) };
        s += &format!(
            "[[objects]]\nid = \"o{i}\"\nkind = \"k{kind}\"\nx = {x}\ny = {y}\norientations = \"{orientations}\"\n"
        );
    }
    s
}

/// Parse instance text (TOML).
pub fn parse(text: &str) -> Instance {
    Instance::parse(text, false, "<test>", None).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// True when the instance lets some box turn onto another face: a top-down pick cannot do that,
/// so plans of such an instance are packing studies (`PlanOptions::packing_only`).
pub fn packing_study(inst: &Instance) -> bool {
    !inst.robot.regrasp
        && inst
            .objects
            .iter()
            .any(|o| o.orientations.iter().any(|q| q.up != o.table.up))
}

/// A hand-made placement as a stage result: checked free of violations, status `feasible`.
pub fn hand_result(inst: &Instance, placement: pushpack::placement::Placement) -> pushpack::placement::PlacementResult {
    assert!(
        placement.violations(inst).is_empty(),
        "{:?}",
        placement.violations(inst)
    );
    pushpack::placement::PlacementResult {
        placement,
        status: pushpack::placement::PlacementStatus::Feasible,
        lower_bound: 0.0,
        solver: "hand".into(),
        time_s: 0.0,
        nodes: 0,
        subproblems: 0,
    }
}
pub mod limits;
