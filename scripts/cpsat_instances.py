#!/usr/bin/env python3
"""pushpack instance files (the committed random sets, say) with OR-Tools CP-SAT, for a
same-machine comparison of both placement stages with `pushpack place --solver milp`
(docs/benchmarks.md, "Against CP-SAT on the random sets"). Not part of the build or of CI:
`pip install ortools==9.15.6755` first.

The method is cpsat_squares.py's, for objects with several footprints: candidate enclosing
boxes W x D in increasing area (ties by smaller D), each decided by CP-SAT with one
NoOverlap2D constraint over variable-size intervals (one footprint per object, chosen by a
Boolean), the two cumulative relaxations, identical objects ordered by x, and the first
object of the largest footprint area in the lower-left quarter; the first feasible box is
optimal because every smaller one was proven infeasible. The boxes' sides are sums of
footprint extents (a BL-stable packing's extents are; SPEC section 4), as pushpack's are.
Then the contact stage: in every feasible box of the optimal area (and its transpose, when the
container holds it), the largest contact length of a BL-stable packing, walls x = 0 and y = 0
always and the far walls where the box reaches the container's.

Orientations follow pushpack's validation (docs/formats.md, "Body axes and orientations"): the
allowed ones in which the object fits the container, can be held (one side plus twice the
release clearance within the opening, taller than grasp_depth) and pushed (taller than
push_height). Sizes go to an integer grid (the largest step that divides every extent and the
container's sides, at most 1 micrometre fine).

With `--area-from BIN` the area stage is not run: BIN (a pushpack binary) proves the optimal
area (`place FILE --solver milp --json`), and CP-SAT decides only the boxes of that area, each
by its contact model at once (an infeasible box is then proven so by CP-SAT), so that the
contact stages can be compared where CP-SAT's area stage does not finish.

With `--bounds` each box of the area stage first meets the bounds pushpack decides boxes by
before its search (`opp::refuted_by_bounds`: every object fits, the least total area, objects
wider than half the box stack, and the dual-feasible functions of Fekete and Schepers on both
axes, every pair); a box they refute is not given to CP-SAT, so that the comparison is of the
searches rather than of the bounds. Their time counts in the area stage.

usage: cpsat_instances.py FILE... [--workers 2] [--time-limit 60] [--no-contact] [--area-from BIN]
                          [--bounds]
prints one line per file: the optimal area (m^2), its box, boxes decided (and refuted by the
bounds) and seconds, then the
best contact length (m), whether proven, and the contact stage's seconds (its own limit)
"""
import argparse
import json
import math
from fractions import Fraction
import subprocess
import time
import tomllib

from ortools.sat.python import cp_model

SCALE = {"m": 1.0, "cm": 0.01, "mm": 0.001}
AXES = {"x": 0, "y": 1, "z": 2}


def dims(size, up, yaw90):
    """pushpack's `Orientation::dims`: footprint along C x and C y, and the height."""
    a = AXES[up]
    b, c = [k for k in range(3) if k != a]
    fp = (size[c], size[b]) if yaw90 else (size[b], size[c])
    return fp, size[a]


def load(path):
    """Container (width, depth) and per object its distinct allowed footprints, in metres."""
    with open(path, "rb") as f:
        doc = tomllib.load(f)
    s = SCALE[doc.get("units", "m")]
    cont = doc["container"]
    width, depth, wall = cont["width"] * s, cont["depth"] * s, cont["wall_height"] * s
    g = doc["gripper"]
    opening, clearance, grasp = g["max_opening"] * s, g["release_clearance"] * s, g["grasp_depth"] * s
    push = g["push_height"] * s if "push_height" in g else 0.005
    regrasp = doc.get("robot", {}).get("regrasp", False)
    kinds = {k["name"]: [v * s for v in k["size"]] for k in doc["kinds"]}
    objects = []
    for o in doc["objects"]:
        size = kinds[o["kind"]]
        up = o.get("up", "z")
        rule = o.get("orientations", "any" if regrasp else "upright")
        cands = [(u, y) for u in "xyz" for y in (False, True)] if rule == "any" else [(up, False), (up, True)]
        fps = []
        for u, y in cands:
            fp, h = dims(size, u, y)
            fits = h <= wall + 1e-9 and fp[0] <= width + 1e-9 and fp[1] <= depth + 1e-9
            held = min(fp) + 2 * clearance <= opening + 1e-9 and h > grasp + 1e-9
            if fits and held and h > push + 1e-9 and not any(close(fp, q) for q in fps):
                fps.append(fp)
        objects.append(fps)
    return (width, depth), objects


def close(a, b):
    return abs(a[0] - b[0]) <= 1e-9 and abs(a[1] - b[1]) <= 1e-9


def to_grid(container, objects):
    """Integer sizes on the coarsest common grid (in micrometres first), and its step in m."""
    um = lambda v: round(v * 1e6)
    vals = [um(v) for v in container] + [um(v) for fps in objects for fp in fps for v in fp]
    step = 0
    for v in vals:
        step = math.gcd(step, v)
    cw, cd = (um(v) // step for v in container)
    objs = [[(um(a) // step, um(b) // step) for a, b in fps] for fps in objects]
    return (cw, cd), objs, step * 1e-6


def sums(extents, limit):
    """Sums of at most one extent per object, up to `limit` (a BL-stable packing's sides)."""
    reach = {0}
    for opts in extents:
        reach |= {r + e for r in reach for e in set(opts) if r + e <= limit}
    return sorted(reach - {0})


def model(objs, w, d, cont, contact):
    """The CP-SAT model of `objs` in the box w x d; with `contact`, BL-stable packings and the
    contact length to maximise."""
    m = cp_model.CpModel()
    n = len(objs)
    x, y, ws, ds, xi, yi = [], [], [], [], [], []
    for i, fps in enumerate(objs):
        fits = [f for f in fps if f[0] <= w and f[1] <= d]
        if not fits:
            return None
        pick = [m.new_bool_var(f"o{i}f{k}") for k in range(len(fits))]
        m.add_exactly_one(pick)
        wi = m.new_int_var_from_domain(cp_model.Domain.from_values(sorted({f[0] for f in fits})), f"w{i}")
        di = m.new_int_var_from_domain(cp_model.Domain.from_values(sorted({f[1] for f in fits})), f"d{i}")
        m.add(wi == sum(f[0] * p for f, p in zip(fits, pick)))
        m.add(di == sum(f[1] * p for f, p in zip(fits, pick)))
        xv, yv = m.new_int_var(0, w, f"x{i}"), m.new_int_var(0, d, f"y{i}")
        xe, ye = m.new_int_var(0, w, f"xe{i}"), m.new_int_var(0, d, f"ye{i}")
        x.append(xv), y.append(yv), ws.append(wi), ds.append(di)
        xi.append(m.new_interval_var(xv, wi, xe, f"ix{i}"))
        yi.append(m.new_interval_var(yv, di, ye, f"iy{i}"))
    m.add_no_overlap_2d(xi, yi)
    m.add_cumulative(xi, ds, d)
    m.add_cumulative(yi, ws, w)
    # Identical objects (the same footprints) in the order of their left edges: a relabelling.
    for i in range(n):
        for j in range(i + 1, n):
            if objs[i] == objs[j]:
                m.add(x[i] <= x[j])
                break
    if not contact:
        # Mirroring a packing in either axis keeps it a packing (not its contact: the walls).
        big = max(range(n), key=lambda i: min(a * b for a, b in objs[i]))
        m.add(2 * x[big] + ws[big] <= w)
        m.add(2 * y[big] + ds[big] <= d)
        return m
    reach = (w == cont[0], d == cont[1])
    terms = []
    for i in range(n):
        for pos, side, size, limit, far in ((x, ds, ws, w, reach[0]), (y, ws, ds, d, reach[1])):
            for at_far in (False, True) if far else (False,):
                lit = m.new_bool_var("")
                m.add(pos[i] + size[i] == limit if at_far else pos[i] == 0).only_enforce_if(lit)
                c = m.new_int_var(0, max(max(f) for f in objs[i]), "")
                m.add(c <= side[i])
                m.add(c == 0).only_enforce_if(lit.negated())
                terms.append(c)
    touch = {}  # (i, j, axis): j's near side on i's far side along axis
    for i in range(n):
        for j in range(n):
            if i == j:
                continue
            for axis, (p, q, sp, sq) in enumerate(((x, y, ws, ds), (y, x, ds, ws))):
                lit = m.new_bool_var("")
                m.add(p[i] + sp[i] == p[j]).only_enforce_if(lit)
                m.add(q[i] + sq[i] >= q[j] + 1).only_enforce_if(lit)
                m.add(q[j] + sq[j] >= q[i] + 1).only_enforce_if(lit)
                touch[i, j, axis] = lit
    for i in range(n):
        for j in range(i + 1, n):
            cap = min(max(max(f) for f in objs[i]), max(max(f) for f in objs[j]))
            c = m.new_int_var(0, cap, "")
            lits = []
            for axis, (q, sq) in enumerate(((y, ds), (x, ws))):
                for a, b in ((i, j), (j, i)):
                    lit = touch[a, b, axis]
                    m.add(c <= q[a] + sq[a] - q[b]).only_enforce_if(lit)
                    m.add(c <= q[b] + sq[b] - q[a]).only_enforce_if(lit)
                    m.add(c <= sq[a]).only_enforce_if(lit)
                    m.add(c <= sq[b]).only_enforce_if(lit)
                    lits.append(lit)
            m.add(sum(lits) <= 1)
            m.add(c == 0).only_enforce_if([lit.negated() for lit in lits])
            terms.append(c)
    # SPEC section 4: every object touches a wall or an object on its -x side and its -y side.
    for j in range(n):
        for axis, pos in enumerate((x, y)):
            wall = m.new_bool_var("")
            m.add(pos[j] == 0).only_enforce_if(wall)
            m.add_bool_or([wall] + [touch[i, j, axis] for i in range(n) if i != j])
    m.maximize(sum(terms))
    return m


def dffs(c, sizes):
    """Dual-feasible functions for capacity c, on integer sizes, exactly (pushpack's `opp::dffs`):
    the identity, U^e for every size e <= c/2 (sizes above c - e become c, below e vanish), and
    u^(k) for k = 1..4 (floor((k+1)x/c) c/k, unless (k+1)x/c is an integer)."""
    out = [lambda v: Fraction(v)]
    for e in sorted({v for v in sizes if 0 < 2 * v <= c}):
        out.append(lambda v, e=e: Fraction(c) if v > c - e else Fraction(0) if v < e else Fraction(v))
    for k in range(1, 5):
        q = k + 1
        out.append(lambda v, q=q, k=k: Fraction(v) if (q * v) % c == 0 else Fraction((q * v) // c * c, k))
    return out


def refuted(objs, w, d):
    """True when a bound proves that no packing of `objs` fits the box w x d."""
    fits = [[f for f in fps if f[0] <= w and f[1] <= d] for fps in objs]
    if any(not f for f in fits):
        return True
    if sum(min(a * b for a, b in f) for f in fits) > w * d:
        return True
    for axis, (cap, other) in enumerate(((w, d), (d, w))):
        stack = sum(min(g[1 - axis] for g in f) for f in fits if all(2 * g[axis] > cap for g in f))
        if stack > other:
            return True
    fx = dffs(w, [g[0] for f in fits for g in f])
    fy = dffs(d, [g[1] for f in fits for g in f])
    for f in fx:
        for g in fy:
            if sum(min(f(a) * g(b) for a, b in o) for o in fits) > w * d:
                return True
    return False


def solve(m, workers, limit):
    s = cp_model.CpSolver()
    s.parameters.num_workers = workers
    s.parameters.max_time_in_seconds = max(limit, 0.01)
    return s, s.solve(m)


def boxes_by_area(objs, cont):
    """Candidate boxes (area, d, w): sides sums of footprint extents, area at least the least
    total footprint area, in increasing area (ties by smaller d)."""
    lb = sum(min(a * b for a, b in fps) for fps in objs)
    widths = sums([[f[0] for f in fps] for fps in objs], cont[0])
    depths = sums([[f[1] for f in fps] for fps in objs], cont[1])
    return sorted(((a * b, b, a) for a in widths for b in depths if a * b >= lb), key=lambda t: (t[0], t[1]))


def area_stage(objs, cont, workers, limit, bounds=False):
    """The optimal area (grid cells) and its feasible boxes, the boxes CP-SAT decided and those
    the bounds refuted (with `bounds`), and whether proven (None: stopped)."""
    start = time.monotonic()
    decided, by_bounds, best, packed = 0, 0, None, []
    for area, d, w in boxes_by_area(objs, cont):
        if best is not None and area > best:
            break
        if bounds and refuted(objs, w, d):
            by_bounds += 1
            if time.monotonic() - start > limit:
                return best, packed, (decided, by_bounds), False
            continue
        m = model(objs, w, d, cont, False)
        if m is None:
            continue
        left = limit - (time.monotonic() - start)
        if left <= 0:
            return best, packed, (decided, by_bounds), False
        s, st = solve(m, workers, left)
        if st == cp_model.UNKNOWN or st == cp_model.MODEL_INVALID:
            return best, packed, (decided, by_bounds), False
        decided += 1
        if st in (cp_model.OPTIMAL, cp_model.FEASIBLE):
            best = area
            packed.append((w, d))
    return best, packed, (decided, by_bounds), best is not None


def contact_stage(objs, cont, packed, workers, limit):
    """The best contact (grid units) over the packed boxes and their transposes (the boxes may
    include infeasible ones, which CP-SAT then proves so), and whether proven."""
    start = time.monotonic()
    boxes = list(packed) + [(d, w) for w, d in packed if w != d and d <= cont[0] and w <= cont[1]]
    best, proven = None, True
    for w, d in dict.fromkeys(boxes):
        m = model(objs, w, d, cont, True)
        if m is None:
            continue
        s, st = solve(m, workers, limit - (time.monotonic() - start))
        if st in (cp_model.OPTIMAL, cp_model.FEASIBLE):
            v = round(s.objective_value)
            best = v if best is None else max(best, v)
        proven &= st in (cp_model.OPTIMAL, cp_model.INFEASIBLE)
    return best, proven


def report_contact(name, objs, cont, boxes, step, a):
    """Run the contact stage over `boxes` and print its line."""
    t0 = time.monotonic()
    c, ok = contact_stage(objs, cont, boxes, a.workers, a.time_limit)
    shown = "none" if c is None else f"{c * step:.4f}"
    print(f"{name} contact={shown} {'optimal' if ok else 'unproven'} {time.monotonic() - t0:.3f} s", flush=True)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("files", nargs="+")
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--time-limit", type=float, default=60.0)
    p.add_argument("--no-contact", action="store_true")
    p.add_argument("--area-from", metavar="BIN", help="a pushpack binary that proves the optimal area")
    p.add_argument("--bounds", action="store_true", help="boxes pushpack's bounds refute are not given to CP-SAT")
    a = p.parse_args()
    for path in a.files:
        cont_m, objects = load(path)
        cont, objs, step = to_grid(cont_m, objects)
        name = path.rsplit("/", 1)[-1]
        if a.area_from:
            out = subprocess.run([a.area_from, "place", path, "--solver", "milp", "--json"], capture_output=True, text=True)
            area_m = json.loads(out.stdout)["objective"]["occupied_area"]
            cells = round(area_m / step / step)
            boxes = [(w, d) for area, d, w in boxes_by_area(objs, cont) if area == cells]
            print(f"{name} area={area_m:.6f} from pushpack, boxes of that area: {len(boxes)}", flush=True)
            report_contact(name, objs, cont, boxes, step, a)
            continue
        t0 = time.monotonic()
        area, packed, (decided, by_bounds), proven = area_stage(objs, cont, a.workers, a.time_limit, a.bounds)
        ta = time.monotonic() - t0
        boxes = f"boxes={decided}" + (f" refuted_by_bounds={by_bounds}" if a.bounds else "")
        if area is None:
            print(f"{name} area=none {boxes} {ta:.3f} s", flush=True)
            continue
        print(
            f"{name} area={area * step * step:.6f} {'optimal' if proven else 'unproven'} "
            f"box={packed[0][0] * step:.3f}x{packed[0][1] * step:.3f} {boxes} {ta:.3f} s",
            flush=True,
        )
        if not a.no_contact and proven:
            report_contact(name, objs, cont, packed, step, a)


if __name__ == "__main__":
    main()
