//! The MILP placement against an exhaustive enumeration on small random instances.
//!
//! The enumeration is exhaustive by the sequence-pair theorem (Murata et al., 1996): for every
//! non-overlapping placement there is a sequence pair (Γ+, Γ−) whose relations ("a left of b"
//! when a precedes b in both, "a below b" when a follows b in Γ+ and precedes it in Γ−) the
//! placement satisfies. The smallest placement satisfying a pair's relations (longest paths)
//! has every coordinate no larger, so its extents are no larger. Minimising over all pairs and
//! all footprints therefore gives the minimum occupied area. The enumeration fixes Γ+, then
//! builds Γ− front to back: an item appended to Γ− has all its left/below neighbours already
//! placed, so its position is final and the partial extents only grow — which makes pruning by
//! the incumbent area safe. Identical objects are taken in index order in Γ+ (any placement can
//! be relabelled so).

mod common;

use pushpack::control::TimeLimit;
use pushpack::instance::Instance;
use pushpack::placement::{bl, milp, PlacementResult, PlacementStatus};

fn footprints(inst: &Instance) -> Vec<Vec<[f64; 2]>> {
    inst.objects
        .iter()
        .map(|o| {
            let mut v: Vec<[f64; 2]> = Vec::new();
            for q in &o.orientations {
                let f = q.dims(o.size).0;
                if !v
                    .iter()
                    .any(|g| (g[0] - f[0]).abs() < 1e-9 && (g[1] - f[1]).abs() < 1e-9)
                {
                    v.push(f);
                }
            }
            v
        })
        .collect()
}

struct Enum<'a> {
    fps: &'a [Vec<[f64; 2]>],
    cw: f64,
    cd: f64,
    best: f64,
    leaves: u64,
}

impl Enum<'_> {
    fn gamma_minus(
        &mut self,
        pos_plus: &[usize],
        placed: &mut Vec<(usize, f64, f64, f64, f64)>,
        used: u32,
        w: f64,
        d: f64,
    ) {
        let n = self.fps.len();
        if placed.len() == n {
            self.leaves += 1;
            self.best = self.best.min(w * d);
            return;
        }
        for k in 0..n {
            if used & (1 << k) != 0 {
                continue;
            }
            let mut x: f64 = 0.0;
            let mut y: f64 = 0.0;
            for &(j, xj, yj, wj, dj) in placed.iter() {
                if pos_plus[j] < pos_plus[k] {
                    x = x.max(xj + wj);
                } else {
                    y = y.max(yj + dj);
                }
            }
            for f in &self.fps[k] {
                let (nw, nd) = (w.max(x + f[0]), d.max(y + f[1]));
                if nw > self.cw + 1e-9 || nd > self.cd + 1e-9 || nw * nd >= self.best - 1e-12 {
                    continue;
                }
                placed.push((k, x, y, f[0], f[1]));
                self.gamma_minus(pos_plus, placed, used | (1 << k), nw, nd);
                placed.pop();
            }
        }
    }
}

fn permutations(n: usize) -> Vec<Vec<usize>> {
    fn rec(cur: &mut Vec<usize>, n: usize, out: &mut Vec<Vec<usize>>) {
        if cur.len() == n {
            out.push(cur.clone());
            return;
        }
        for i in 0..n {
            if !cur.contains(&i) {
                cur.push(i);
                rec(cur, n, out);
                cur.pop();
            }
        }
    }
    let mut out = Vec::new();
    rec(&mut Vec::new(), n, &mut out);
    out
}

/// Minimum occupied area by exhaustive sequence-pair enumeration (starting from `upper`).
fn brute_force_area(inst: &Instance, upper: f64) -> f64 {
    let fps = footprints(inst);
    let n = inst.n();
    let identical = |a: usize, b: usize| inst.objects[a].size == inst.objects[b].size && fps[a] == fps[b];
    let mut e = Enum {
        fps: &fps,
        cw: inst.container.width,
        cd: inst.container.depth,
        best: upper + 1e-9,
        leaves: 0,
    };
    for gp in permutations(n) {
        // Symmetry: identical objects appear in index order in Γ+.
        let ok = (0..n).all(|a| {
            (0..n).all(|b| {
                !(a < b && identical(a, b)) || gp.iter().position(|&v| v == a) < gp.iter().position(|&v| v == b)
            })
        });
        if !ok {
            continue;
        }
        let mut pos_plus = vec![0; n];
        for (p, &i) in gp.iter().enumerate() {
            pos_plus[i] = p;
        }
        e.gamma_minus(&pos_plus, &mut Vec::new(), 0, 0.0, 0.0);
    }
    e.best
}

/// Bottom-Left (64 orders) and the MILP warm-started by it, contact stage on, 60 s limit.
fn bl_and_milp(inst: &Instance, seed: u64) -> (PlacementResult, PlacementResult) {
    bl_and_milp_with(inst, seed, milp::AreaMaster::Search)
}

/// [`bl_and_milp`] with the area stage's boxes decided by `area_master`.
fn bl_and_milp_with(inst: &Instance, seed: u64, area_master: milp::AreaMaster) -> (PlacementResult, PlacementResult) {
    let blr = bl::solve(inst, seed, 64, &TimeLimit::new(30.0)).unwrap();
    let settings = milp::MilpSettings {
        time_limit: 60.0,
        contact_stage: true,
        seed,
        area_master,
        ..Default::default()
    };
    let r = milp::solve(inst, &blr, &settings, &TimeLimit::new(60.0)).unwrap();
    (blr, r)
}

/// Object count (2 up to `1 + sizes`), number of kinds and orientations of the random
/// instance for `seed`: the exhaustive tests cycle through them so every combination occurs.
fn seed_shape(seed: u64, sizes: usize) -> (usize, usize, &'static str) {
    let n = 2 + (seed as usize % sizes);
    let kinds = 1 + (seed as usize % 3);
    let ori = if seed % 3 == 0 { "upright" } else { "any" };
    (n, kinds, ori)
}

#[test]
fn milp_matches_exhaustive_enumeration_on_random_small_instances() {
    let mut checked = 0;
    let mut improved_over_bl = 0;
    for seed in 0..52u64 {
        let (n, kinds, ori) = seed_shape(seed, 5); // 2..=6 objects
                                                   // Box edges on a 5 mm grid (product sizes), and on a 1 mm grid for up to 4 objects:
                                                   // 1 mm edges make the MILP's grid fine and its run long (docs/benchmarks.md).
        let step = if n <= 4 && seed % 2 == 0 { 1 } else { 5 };
        let inst = common::parse(&common::random_instance_text_step(1000 + seed, n, kinds, ori, step));
        let (blr, r) = bl_and_milp(&inst, seed);
        assert!(
            r.placement.violations(&inst).is_empty(),
            "seed {seed}: {:?}",
            r.placement.violations(&inst)
        );
        let area = r.placement.occupied_area();
        let exact = brute_force_area(&inst, blr.placement.occupied_area());
        assert_eq!(
            r.status,
            PlacementStatus::Optimal,
            "seed {seed}: small instances are proven within the limit"
        );
        assert!(
            (area - exact).abs() <= 1e-9,
            "seed {seed} (n={n}): MILP {area} vs exhaustive {exact}"
        );
        assert!(r.lower_bound >= area - 1e-9, "optimal means the bound meets the area");
        assert!(
            area <= blr.placement.occupied_area() + 1e-12,
            "never worse than Bottom-Left"
        );
        if area < blr.placement.occupied_area() - 1e-9 {
            improved_over_bl += 1;
        }
        checked += 1;
    }
    assert!(checked >= 50);
    // The exhaustive check is meaningful only if BL is sometimes suboptimal.
    assert!(
        improved_over_bl > 0,
        "BL was optimal on every instance: the test would not catch a MILP that returns BL"
    );
}

/// The HiGHS master (Benders: x by a MILP, y by the y-phase, no-good cuts) proves the same
/// areas as exhaustive enumeration; its status is optimal only with the bound at the area.
#[test]
fn highs_master_matches_exhaustive_enumeration_on_random_small_instances() {
    let mut improved_over_bl = 0;
    for seed in 0..40u64 {
        let (n, kinds, ori) = seed_shape(seed, 5);
        let inst = common::parse(&common::random_instance_text_step(1000 + seed, n, kinds, ori, 5));
        let (blr, r) = bl_and_milp_with(&inst, seed, milp::AreaMaster::Highs);
        assert!(r.placement.violations(&inst).is_empty(), "seed {seed}");
        let area = r.placement.occupied_area();
        let exact = brute_force_area(&inst, blr.placement.occupied_area());
        assert_eq!(r.status, PlacementStatus::Optimal, "seed {seed}");
        assert!(
            (area - exact).abs() <= 1e-9,
            "seed {seed} (n={n}): HiGHS master {area} vs exhaustive {exact}"
        );
        assert!(r.lower_bound >= area - 1e-9);
        improved_over_bl += (area < blr.placement.occupied_area() - 1e-9) as usize;
    }
    assert!(
        improved_over_bl > 0,
        "BL optimal everywhere: the test would not catch a master returning BL"
    );
}

#[test]
fn stopped_milp_reports_feasible_with_a_valid_bound() {
    let inst = common::load("paper/exp2_8objects.toml");
    let blr = bl::solve(&inst, 1, 64, &TimeLimit::new(30.0)).unwrap();
    let settings = milp::MilpSettings {
        time_limit: 0.05,
        contact_stage: true,
        seed: 0,
        ..Default::default()
    };
    let r = milp::solve(&inst, &blr, &settings, &TimeLimit::new(0.05)).unwrap();
    let area = r.placement.occupied_area();
    assert!(r.placement.violations(&inst).is_empty());
    assert!(area <= blr.placement.occupied_area() + 1e-12);
    assert!(r.lower_bound <= area + 1e-12);
    if r.status == PlacementStatus::Optimal {
        assert!(r.lower_bound >= area - 1e-9);
    } else {
        assert!(r.gap() >= 0.0);
    }
}

#[test]
fn candidate_widths_are_subset_sums() {
    let inst = common::load("paper/exp1_4objects.toml");
    let blr = bl::solve(&inst, 1, 8, &TimeLimit::new(30.0)).unwrap();
    // BL's occupied width is a sum of footprint widths, so it must be among the candidates.
    let w = blr.placement.extent().0;
    let fps: Vec<pushpack::placement::area::Footprints> = inst
        .objects
        .iter()
        .map(|o| {
            o.orientations
                .iter()
                .map(|q| pushpack::placement::area::Footprint {
                    size: q.dims(o.size).0,
                    orientation: *q,
                    height: q.dims(o.size).1,
                })
                .collect()
        })
        .collect();
    let c = milp::candidate_widths(&fps, inst.container.width);
    assert!(c.iter().any(|v| (v - w).abs() < 1e-9), "{w} not in {c:?}");
}

/// Instance text with the given kinds (`[a, b, c]` mm, count) on the common table slots.
fn kinds_instance_text(kinds: &[([u32; 3], usize)], orientations: &str) -> String {
    let base = common::random_instance_text_step(0, 1, 1, orientations, 5);
    let header = &base[..base.find("[[kinds]]").expect("generated text has kinds")];
    let mut s = header.to_string();
    for (k, (size, _)) in kinds.iter().enumerate() {
        s += &format!(
            "[[kinds]]\nname = \"k{k}\"\nsize = [{}, {}, {}]\nmass = 0.05\n",
            size[0], size[1], size[2]
        );
    }
    let slots: Vec<(i32, i32)> = [230, 310]
        .iter()
        .flat_map(|&x| [240, 320, 400].iter().flat_map(move |&y| [(x, y), (x, -y)]))
        .collect();
    let mut i = 0;
    for (k, (_, count)) in kinds.iter().enumerate() {
        for _ in 0..*count {
            let (x, y) = slots[i % slots.len()];
            s += &format!(
                "[[objects]]\nid = \"o{i}\"\nkind = \"k{k}\"\nx = {x}\ny = {y}\norientations = \"{orientations}\"\n"
            );
            i += 1;
        }
    }
    s
}

/// Long boxes (wider than half of most candidate widths, so the stacking bound of the width
/// enumeration is active and often tight), mixed with small ones, some on a 1 mm grid so depth
/// sums are irregular: the per-width depth bounds and their rounding to depth sums must never
/// close a width that holds the optimum.
#[test]
fn milp_matches_exhaustive_enumeration_on_long_boxes() {
    let cases: [&[([u32; 3], usize)]; 5] = [
        &[([70, 25, 30], 3), ([30, 30, 30], 2)],
        &[([65, 30, 30], 2), ([40, 35, 30], 2), ([33, 27, 30], 1)],
        &[([60, 20, 30], 4), ([45, 45, 30], 1)],
        &[([71, 23, 40], 2), ([37, 31, 30], 3)],
        &[([50, 26, 30], 3), ([26, 26, 30], 3)],
    ];
    for (c, kinds) in cases.iter().enumerate() {
        for ori in ["upright", "any"] {
            let inst = common::parse(&kinds_instance_text(kinds, ori));
            let (blr, r) = bl_and_milp(&inst, c as u64);
            assert!(r.placement.violations(&inst).is_empty(), "case {c} {ori}");
            let area = r.placement.occupied_area();
            let exact = brute_force_area(&inst, blr.placement.occupied_area());
            assert_eq!(r.status, PlacementStatus::Optimal, "case {c} {ori}");
            assert!(
                (area - exact).abs() <= 1e-9,
                "case {c} {ori}: MILP {area} vs exhaustive {exact}"
            );
            assert!(r.lower_bound >= area - 1e-9 && r.lower_bound <= area + 1e-9);
            assert!(area <= blr.placement.occupied_area() + 1e-12);
        }
    }
}

/// Maximum contact length over every BL-stable placement whose occupied area is at most
/// `area` (the proven minimum), by exhaustive enumeration in integer millimetres.
///
/// Exhaustive because, in a BL-stable placement, every object's low x is 0 or the high x of an
/// object touching it on the left (so that object has a smaller x), and every low y is 0 or the
/// high y of the object below: so every y is a sum of footprint depths of distinct other
/// objects (a chain of supports), and the enumeration tries every such sum. Objects are placed
/// in increasing `(x, y)`, which orders any placement uniquely, so each object's left support is
/// already placed and is checked at once; the support from below is checked when all are
/// placed. The contact length is computed here from its definition (shared edge lengths plus
/// edges on the four walls), independently of the library.
fn brute_force_contact(inst: &Instance, area: f64) -> f64 {
    let mm = |v: f64| (v * 1000.0).round() as i64;
    let fps: Vec<Vec<[i64; 2]>> = footprints(inst)
        .iter()
        .map(|o| o.iter().map(|f| [mm(f[0]), mm(f[1])]).collect())
        .collect();
    let (cw, cd) = (mm(inst.container.width), mm(inst.container.depth));
    let n = inst.n();
    let area_mm = (area * 1e6).round() as i64;
    // Every sum of depths of distinct objects (one footprint each) up to the container depth.
    let mut ys: Vec<i64> = vec![0];
    for o in &fps {
        let mut next = ys.clone();
        for &y in &ys {
            for f in o {
                if y + f[1] <= cd {
                    next.push(y + f[1]);
                }
            }
        }
        next.sort_unstable();
        next.dedup();
        ys = next;
    }
    let identical = |a: usize, b: usize| inst.objects[a].size == inst.objects[b].size && fps[a] == fps[b];
    struct S<'a> {
        fps: &'a [Vec<[i64; 2]>],
        ys: &'a [i64],
        cw: i64,
        cd: i64,
        area: i64,
        n: usize,
        identical: &'a dyn Fn(usize, usize) -> bool,
        best: i64,
        leaves: u64,
    }
    fn overlap(a0: i64, a1: i64, b0: i64, b1: i64) -> i64 {
        a1.min(b1) - a0.max(b0)
    }
    fn contact(r: &[(usize, [i64; 4])], cw: i64, cd: i64) -> i64 {
        let mut c = 0;
        for (k, &(_, a)) in r.iter().enumerate() {
            let [x0, y0, x1, y1] = a;
            c += (x0 == 0) as i64 * (y1 - y0) + (x1 == cw) as i64 * (y1 - y0);
            c += (y0 == 0) as i64 * (x1 - x0) + (y1 == cd) as i64 * (x1 - x0);
            for &(_, b) in &r[k + 1..] {
                if a[2] == b[0] || b[2] == a[0] {
                    c += overlap(a[1], a[3], b[1], b[3]).max(0);
                }
                if a[3] == b[1] || b[3] == a[1] {
                    c += overlap(a[0], a[2], b[0], b[2]).max(0);
                }
            }
        }
        c
    }
    fn rec(s: &mut S, placed: &mut Vec<(usize, [i64; 4])>, used: u32, ext: (i64, i64)) {
        if placed.len() == s.n {
            s.leaves += 1;
            let below_ok = placed.iter().all(|&(_, a)| {
                a[1] == 0
                    || placed
                        .iter()
                        .any(|&(_, b)| b[3] == a[1] && overlap(a[0], a[2], b[0], b[2]) > 0)
            });
            if below_ok {
                s.best = s.best.max(contact(placed, s.cw, s.cd));
            }
            return;
        }
        let last = placed.last().map(|&(_, a)| (a[0], a[1]));
        let mut xs: Vec<i64> = vec![0];
        xs.extend(placed.iter().map(|&(_, a)| a[2]));
        xs.sort_unstable();
        xs.dedup();
        for k in 0..s.n {
            if used & (1 << k) != 0 {
                continue;
            }
            // Identical objects in index order: any placement can be relabelled so.
            if (0..k).any(|j| used & (1 << j) == 0 && (s.identical)(j, k)) {
                continue;
            }
            for fi in 0..s.fps[k].len() {
                let [w, d] = s.fps[k][fi];
                for &x in &xs {
                    for &y in s.ys {
                        if last.is_some_and(|l| (x, y) <= l) {
                            continue;
                        }
                        let r = [x, y, x + w, y + d];
                        let e = (ext.0.max(r[2]), ext.1.max(r[3]));
                        if r[2] > s.cw || r[3] > s.cd || e.0 * e.1 > s.area {
                            continue;
                        }
                        if placed
                            .iter()
                            .any(|&(_, b)| overlap(r[0], r[2], b[0], b[2]) > 0 && overlap(r[1], r[3], b[1], b[3]) > 0)
                        {
                            continue;
                        }
                        let left_ok = x == 0
                            || placed
                                .iter()
                                .any(|&(_, b)| b[2] == x && overlap(r[1], r[3], b[1], b[3]) > 0);
                        if !left_ok {
                            continue;
                        }
                        placed.push((k, r));
                        rec(s, placed, used | (1 << k), e);
                        placed.pop();
                    }
                }
            }
        }
    }
    let mut s = S {
        fps: &fps,
        ys: &ys,
        cw,
        cd,
        area: area_mm,
        n,
        identical: &identical,
        best: -1,
        leaves: 0,
    };
    rec(&mut s, &mut Vec::new(), 0, (0, 0));
    assert!(s.best >= 0, "no BL-stable placement reaches the area {area}");
    s.best as f64 / 1000.0
}

/// The lexicographic second objective: among placements of minimum area, the MILP's contact
/// length is the maximum over all BL-stable ones (its contact stage, including the skip of
/// transposed extents, must never lose the best).
#[test]
fn milp_contact_length_matches_exhaustive_enumeration() {
    let mut checked = 0;
    let mut tied_extents = 0;
    for seed in 0..40u64 {
        let (n, kinds, ori) = seed_shape(seed, 4); // 2..=5 objects
        let inst = common::parse(&common::random_instance_text_step(2000 + seed, n, kinds, ori, 5));
        let (blr, r) = bl_and_milp(&inst, seed);
        assert_eq!(r.status, PlacementStatus::Optimal, "seed {seed}");
        let area = r.placement.occupied_area();
        let exact_area = brute_force_area(&inst, blr.placement.occupied_area());
        assert!(
            (area - exact_area).abs() <= 1e-9,
            "seed {seed}: area {area} vs {exact_area}"
        );
        let c = r.placement.contact_length(&inst);
        let exact = brute_force_contact(&inst, exact_area);
        assert!(
            (c - exact).abs() <= 1e-6,
            "seed {seed} (n={n}, {ori}): MILP contact {c} vs exhaustive {exact}"
        );
        let (w, d) = r.placement.extent();
        if (w - d).abs() > 1e-9 && w <= inst.container.depth && d <= inst.container.width {
            tied_extents += 1;
        }
        checked += 1;
    }
    assert_eq!(checked, 40);
    // Some optimum must have a transposable extent, or the skip of transposed extents is untested.
    assert!(tied_extents > 0);
}
