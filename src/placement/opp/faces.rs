//! Which footprints can still take part in a packing that beats a contact length: the others
//! are left out of the contact enumeration before it starts.
//!
//! Why it is exact (docs/algorithms.md, *Footprint combinations that can beat the incumbent*):
//! every shared boundary of a packing is the left side of the object on its right or the
//! bottom of the object above, and a wall's contact is a left side, a bottom or a far wall, so
//! a packing's contact is at most the sum of its footprints' widths and depths plus the far
//! walls' lengths. Its footprints' areas also fit the box. So a packing that beats `to_beat`
//! uses, in each class of identical objects, a combination of footprints (how many copies in
//! each pair of area and sides) whose sides over all classes, with the far walls, exceed
//! `to_beat` and whose areas fit `w · d`. Listing those combinations is a small search when
//! the incumbent is close to the bound (on the twenty-object sets one combination is left in
//! every contact stage measured); a footprint in none of them is in no better packing.
//!
//! Objects of different classes left with the same footprints are then one class: they are
//! the same rectangles to the enumeration, and a packing's contact does not depend on which
//! object takes which rectangle, so placing them in index order (as identical objects are)
//! keeps one of each set of packings that differ only in that. On the twenty-object set this
//! happens in four of the twenty files (n20_k4_s0010's two classes both left 3 × 4 cm: 1.05 M
//! → 0.25 M nodes).

use super::{fitting, tol, Item, Pos};

/// Most steps of the search over combinations before it gives up and keeps every footprint:
/// far above what a contact stage near its bound takes, far below what its enumeration costs.
const STEPS_MOST: u64 = 200_000;

/// The footprints of one class that share an area and a sum of sides.
#[derive(Debug)]
struct Face {
    area: f64,
    sides: f64,
}

/// One class of identical items: its copies, the faces of its fitting footprints, and which
/// faces some combination able to beat the bound uses.
#[derive(Debug)]
struct Class {
    copies: usize,
    faces: Vec<Face>,
    used: Vec<bool>,
}

/// The outcome of [`restrict`].
#[derive(Debug)]
pub(super) enum Faces {
    /// Every fitting footprint may be in a better packing (or the search gave up): nothing
    /// changes.
    All,
    /// No combination of footprints beats the bound: no packing does.
    Nothing,
    /// Only some footprints can: the items with those, and per item the index of each kept
    /// footprint among its own ([`Kept::back`]).
    Only(Kept),
}

/// The items with only the footprints that may be in a better packing.
#[derive(Debug)]
pub(super) struct Kept {
    pub(super) items: Vec<Item>,
    /// Per item, per kept footprint: its index in the item's `opts`.
    from: Vec<Vec<usize>>,
    /// Whether objects of different classes became one class (their footprints left the
    /// same), so that the enumeration meets the packings in another order (read by tests).
    #[cfg_attr(not(test), allow(dead_code))]
    pub(super) merged: bool,
}

impl Kept {
    /// A packing of the kept items as one of the original items (footprint indices mapped back).
    pub(super) fn back(&self, pos: &[Pos]) -> Vec<Pos> {
        pos.iter()
            .zip(&self.from)
            .map(|(p, from)| Pos { opt: from[p.opt], ..*p })
            .collect()
    }
}

/// The footprints of `items` in `w × d` that some packing with contact above `to_beat` may use
/// (far walls where `far` says), classes left with the same footprints merged. Scores within
/// `tie` of `to_beat` do not beat it.
pub(super) fn restrict(items: &[Item], w: f64, d: f64, to_beat: f64, far: [bool; 2], tie: f64) -> Faces {
    if !to_beat.is_finite() {
        return Faces::All;
    }
    let t = tol(w, d);
    let walls = if far[0] { d } else { 0.0 } + if far[1] { w } else { 0.0 };
    // Classes in order of first appearance; `of[i]`: item i's class.
    let mut classes: Vec<Class> = Vec::new();
    let mut firsts: Vec<usize> = Vec::new();
    let mut of = Vec::with_capacity(items.len());
    for (i, it) in items.iter().enumerate() {
        if let Some(c) = firsts.iter().position(|&j| items[j].class == it.class) {
            classes[c].copies += 1;
            of.push(c);
            continue;
        }
        let mut faces: Vec<Face> = Vec::new();
        for f in fitting(it, w, d) {
            let (area, sides) = (f[0] * f[1], f[0] + f[1]);
            if !faces
                .iter()
                .any(|g| (g.area - area).abs() <= t * (w + d) && (g.sides - sides).abs() <= t)
            {
                faces.push(Face { area, sides });
            }
        }
        if faces.is_empty() {
            // An item that fits nowhere: no packing at all.
            return Faces::Nothing;
        }
        // Most sides first, so that the search meets the combinations able to beat first.
        faces.sort_by(|a, b| b.sides.total_cmp(&a.sides).then(a.area.total_cmp(&b.area)));
        let n = faces.len();
        classes.push(Class {
            copies: 1,
            faces,
            used: vec![false; n],
        });
        firsts.push(i);
        of.push(classes.len() - 1);
    }
    // What the classes from `c` on add at the least (area) and at the most (sides).
    let mut least_area = vec![0.0; classes.len() + 1];
    let mut most_sides = vec![0.0; classes.len() + 1];
    for c in (0..classes.len()).rev() {
        let k = &classes[c];
        let a = k.faces.iter().map(|f| f.area).fold(f64::INFINITY, f64::min);
        let s = k.faces.iter().map(|f| f.sides).fold(0.0, f64::max);
        least_area[c] = least_area[c + 1] + k.copies as f64 * a;
        most_sides[c] = most_sides[c + 1] + k.copies as f64 * s;
    }
    let mut search = Combos {
        classes,
        least_area,
        most_sides,
        cap: w * d + t * (w + d),
        // Beats only above `to_beat + tie`; half a tie absorbs the rounding of the sums.
        need: to_beat + 0.5 * tie - walls,
        counts: Vec::new(),
        steps: 0,
        any: false,
    };
    if !search.class(0, 0.0, 0.0) {
        return Faces::All;
    }
    if !search.any {
        return Faces::Nothing;
    }
    let classes = search.classes;
    // Keep a footprint when its face is used; nothing changes when every fitting one is.
    let mut changed = false;
    let mut kept = Vec::with_capacity(items.len());
    let mut from = Vec::with_capacity(items.len());
    for (it, &c) in items.iter().zip(&of) {
        let k = &classes[c];
        let keep = |f: &[f64; 2]| {
            f[0] <= w + t
                && f[1] <= d + t
                && (k.faces.iter().zip(&k.used)).any(|(g, &u)| {
                    u && (g.area - f[0] * f[1]).abs() <= t * (w + d) && (g.sides - f[0] - f[1]).abs() <= t
                })
        };
        let idx: Vec<usize> = (0..it.opts.len()).filter(|&o| keep(&it.opts[o])).collect();
        changed |= idx.len() < it.opts.len();
        kept.push(Item {
            opts: idx.iter().map(|&o| it.opts[o]).collect(),
            class: it.class,
        });
        from.push(idx);
    }
    if !changed {
        return Faces::All;
    }
    // Objects of different classes left with the same footprints are the same rectangles to
    // the enumeration: one class, so that it places them in index order instead of trying
    // every way to share their places out between the classes (a packing's contact does not
    // depend on which object takes which rectangle).
    let eq = |f: &[f64; 2], g: &[f64; 2]| (f[0] - g[0]).abs() <= t && (f[1] - g[1]).abs() <= t;
    // Where each of `b`'s footprints is in `a`'s list, when both hold the same ones.
    let order = |a: &Item, b: &Item| -> Option<Vec<usize>> {
        (a.opts.len() == b.opts.len())
            .then(|| b.opts.iter().map(|g| a.opts.iter().position(|f| eq(f, g))).collect())
            .flatten()
    };
    let mut merged = false;
    for i in 0..kept.len() {
        let to = (0..i).find_map(|j| {
            (kept[j].class != kept[i].class)
                .then(|| order(&kept[i], &kept[j]).map(|o| (kept[j].class, o)))
                .flatten()
        });
        if let Some((class, o)) = to {
            // Its footprints in the other class's order, so that an index means one rectangle.
            kept[i].opts = o.iter().map(|&p| kept[i].opts[p]).collect();
            from[i] = o.iter().map(|&p| from[i][p]).collect();
            kept[i].class = class;
            merged = true;
        }
    }
    Faces::Only(Kept {
        items: kept,
        from,
        merged,
    })
}

/// The search over combinations: class by class, each class's copies spread over its faces.
struct Combos {
    classes: Vec<Class>,
    least_area: Vec<f64>,
    most_sides: Vec<f64>,
    cap: f64,
    /// Sides the footprints must exceed.
    need: f64,
    /// Per class so far: copies in each face.
    counts: Vec<Vec<usize>>,
    steps: u64,
    /// Whether any combination beats.
    any: bool,
}

impl Combos {
    /// Spread class `c` and those after it, with `area` and `sides` from the classes before.
    /// Returns false when it gave up.
    fn class(&mut self, c: usize, area: f64, sides: f64) -> bool {
        if c == self.classes.len() {
            self.any = true;
            for (k, n) in self.classes.iter_mut().zip(&self.counts) {
                for (u, &m) in k.used.iter_mut().zip(n) {
                    *u |= m > 0;
                }
            }
            return true;
        }
        let mut n = vec![0; self.classes[c].faces.len()];
        let copies = self.classes[c].copies;
        self.spread(c, 0, copies, &mut n, area, sides)
    }

    /// Put `left` copies of class `c` into its faces from `f` on (`n`: copies per face so far).
    fn spread(&mut self, c: usize, f: usize, left: usize, n: &mut Vec<usize>, area: f64, sides: f64) -> bool {
        self.steps += 1;
        if self.steps > STEPS_MOST {
            return false;
        }
        let k = &self.classes[c];
        // The rest of this class at its least area and most sides among the faces from `f` on.
        let rest = &k.faces[f..];
        let a = rest.iter().map(|g| g.area).fold(f64::INFINITY, f64::min);
        let s = rest.iter().map(|g| g.sides).fold(0.0, f64::max);
        let (a, s) = if left == 0 {
            (0.0, 0.0)
        } else {
            (left as f64 * a, left as f64 * s)
        };
        if area + a + self.least_area[c + 1] > self.cap || sides + s + self.most_sides[c + 1] <= self.need {
            return true;
        }
        if left == 0 || f + 1 == k.faces.len() {
            let (fa, fs) = (k.faces[f].area, k.faces[f].sides);
            n[f] += left;
            self.counts.push(n.clone());
            let (a2, s2) = (area + left as f64 * fa, sides + left as f64 * fs);
            let ok = self.class(c + 1, a2, s2);
            self.counts.pop();
            n[f] -= left;
            return ok;
        }
        let (fa, fs) = (k.faces[f].area, k.faces[f].sides);
        for m in (0..=left).rev() {
            n[f] += m;
            let ok = self.spread(c, f + 1, left - m, n, area + m as f64 * fa, sides + m as f64 * fs);
            n[f] -= m;
            if !ok {
                return false;
            }
        }
        true
    }
}
