#!/usr/bin/env python3
"""Consecutive squares 1x1 ... NxN (OEIS A038666) with OR-Tools CP-SAT, for a same-machine
comparison with `pushpack place --solver milp` (docs/benchmarks.md, "CP-SAT on the same
machine"). Not part of the build or of CI: `pip install ortools==9.15.6755` first.

The method is the one issue 21 quotes: candidate enclosing boxes W x D (integers, W >= D >= N,
W * D >= the squares' area) in increasing area (ties by smaller D first), each decided by CP-SAT
with one NoOverlap2D constraint; the first feasible box is optimal because every smaller one
was proven infeasible. Symmetry: the largest square in the lower-left quarter of the box
(mirroring a packing keeps it a packing), and by default the two cumulative relaxations
(`--no-cumulative` leaves them out). Only the area is optimised; CP-SAT does not score
contact unless asked (`--contact`: then, in every box of the optimal area and its transpose,
the largest contact of a BL-stable packing, as pushpack's contact stage finds it).

usage: cpsat_squares.py FROM TO [--workers 2] [--time-limit 60] [--no-cumulative] [--contact [--no-bl-stable]]
prints one line per N: N, optimal area, W x D, boxes decided, seconds (wall, whole N); with
--contact a second line: the best contact (units), whether proven, seconds (its own limit)
"""
import argparse
import time

from ortools.sat.python import cp_model


def decide(n, w, d, workers, limit, cumulative, contact=False, bl_stable=True):
    """True / False when the box is proven feasible / infeasible, None when stopped. With
    `contact`, returns (best contact, proven) for a feasible box instead of True."""
    m = cp_model.CpModel()
    xs, ys, px, py = [], [], [], []
    for s in range(1, n + 1):
        x = m.new_int_var(0, w - s, f"x{s}")
        y = m.new_int_var(0, d - s, f"y{s}")
        px.append(x)
        py.append(y)
        xs.append(m.new_fixed_size_interval_var(x, s, f"ix{s}"))
        ys.append(m.new_fixed_size_interval_var(y, s, f"iy{s}"))
        if s == n and not contact:
            # not with contact: the walls are at x = 0 and y = 0 only, so a mirror changes it
            m.add(2 * x <= w - s)
            m.add(2 * y <= d - s)
    m.add_no_overlap_2d(xs, ys)
    if cumulative:
        # The redundant one-dimensional relaxations a CP modeller adds: every vertical line
        # crosses squares of total side at most d, every horizontal line at most w.
        m.add_cumulative(xs, list(range(1, n + 1)), d)
        m.add_cumulative(ys, list(range(1, n + 1)), w)
    if contact:
        if bl_stable:
            add_bl_stable(m, n, px, py)
        add_contact_objective(m, n, px, py)
    solver = cp_model.CpSolver()
    solver.parameters.num_workers = workers
    solver.parameters.max_time_in_seconds = limit
    st = solver.solve(m)
    if contact and st in (cp_model.OPTIMAL, cp_model.FEASIBLE):
        return round(solver.objective_value), st == cp_model.OPTIMAL
    if st in (cp_model.OPTIMAL, cp_model.FEASIBLE):
        return True
    if st == cp_model.INFEASIBLE:
        return False
    return None  # stopped by the limit


def add_bl_stable(m, n, px, py):
    """SPEC section 4: every object touches a wall or an object on its -x side and on its -y
    side. Without it the contact optimum can be higher: squares 1...16 in 56 x 27 reach 261 with
    square 2 hanging over a gap, 260 when every square rests (pushpack's answer)."""
    for i in range(n):
        a = i + 1
        for p, q in ((px, py), (py, px)):
            wall = m.new_bool_var("")
            m.add(p[i] == 0).only_enforce_if(wall)
            supports = [wall]
            for j in range(n):
                if j == i:
                    continue
                b = j + 1
                lit = m.new_bool_var("")
                # j's far side meets i's near side, with a common part of positive length
                m.add(p[j] + b == p[i]).only_enforce_if(lit)
                m.add(q[j] + b >= q[i] + 1).only_enforce_if(lit)
                m.add(q[i] + a >= q[j] + 1).only_enforce_if(lit)
                supports.append(lit)
            m.add_bool_or(supports)


def add_contact_objective(m, n, px, py):
    """Maximise pushpack's contact length (SPEC: shared boundary lengths object-object and
    object-wall; the container never binds, so its walls are x = 0 and y = 0 only). Each pair
    touches along at most one side; its contact variable is at most the overlap of the two
    sides when the touch literal holds and zero otherwise, so the maximum is the true contact."""
    terms = []
    for i in range(n):
        a = i + 1
        for var in (px[i], py[i]):
            wall = m.new_bool_var("")
            m.add(var == 0).only_enforce_if(wall)
            terms.append(a * wall)
        for j in range(i + 1, n):
            b = j + 1
            c = m.new_int_var(0, min(a, b), "")
            touches = []
            # (position along the touching axis, across it) for i then j, four ways to touch
            for (pi, qi, pj, qj) in ((px[i], py[i], px[j], py[j]), (py[i], px[i], py[j], px[j])):
                for lo, hi, slo, shi in ((pi, pj, a, b), (pj, pi, b, a)):
                    lit = m.new_bool_var("")
                    m.add(lo + slo == hi).only_enforce_if(lit)
                    m.add(c <= qi + a - qj).only_enforce_if(lit)
                    m.add(c <= qj + b - qi).only_enforce_if(lit)
                    touches.append(lit)
            m.add(c <= min(a, b) * sum(touches))
            m.add(sum(touches) <= 1)
            terms.append(c)
    m.maximize(sum(terms))


def boxes_of_area(n, a):
    """The boxes W x D of area `a` with W >= D >= N, by increasing D."""
    for d in range(n, int(a**0.5) + 1):
        if a % d == 0 and a // d >= d:
            yield a // d, d


def best_contact(n, area, workers, limit, cumulative, bl_stable):
    """The largest contact over the feasible boxes of the optimal area, and whether proven."""
    start = time.monotonic()
    best, proven = None, True
    for w, d in boxes_of_area(n, area):
        left = limit - (time.monotonic() - start)
        if left <= 0:
            return best, False, time.monotonic() - start
        r = decide(n, w, d, workers, left, cumulative, contact=True, bl_stable=bl_stable)
        if r is None:
            return best, False, time.monotonic() - start
        if r is False:
            continue
        c, ok = r
        best = c if best is None else max(best, c)
        proven &= ok
        # pushpack's boxes are transposes too: a w x d packing turned is a d x w one with the
        # same shared boundaries and the wall contacts swapped, so the turned box is searched too
        if w != d:
            r = decide(n, d, w, workers, max(0.0, limit - (time.monotonic() - start)), cumulative, True, bl_stable)
            if isinstance(r, tuple):
                best = max(best, r[0])
                proven &= r[1]
            else:
                proven = False
    return best, proven, time.monotonic() - start


def solve(n, workers, limit, cumulative):
    area = n * (n + 1) * (2 * n + 1) // 6
    start = time.monotonic()
    decided = 0
    a = area
    while True:
        for w, d in boxes_of_area(n, a):
            left = limit - (time.monotonic() - start)
            if left <= 0:
                return None, None, decided, time.monotonic() - start
            r = decide(n, w, d, workers, left, cumulative)
            if r is None:
                return None, None, decided, time.monotonic() - start
            decided += 1
            if r:
                return a, (w, d), decided, time.monotonic() - start
        a += 1


def main():
    p = argparse.ArgumentParser()
    p.add_argument("first", type=int)
    p.add_argument("last", type=int)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--time-limit", type=float, default=60.0)
    p.add_argument("--no-cumulative", action="store_true", help="NoOverlap2D alone")
    p.add_argument("--contact", action="store_true", help="then maximise contact in the optimal boxes")
    p.add_argument("--no-bl-stable", action="store_true", help="contact without SPEC's BL-stability")
    a = p.parse_args()
    for n in range(a.first, a.last + 1):
        area, box, decided, secs = solve(n, a.workers, a.time_limit, not a.no_cumulative)
        if area is None:
            print(f"N={n} stopped after {decided} boxes, {secs:.3f} s", flush=True)
        else:
            print(f"N={n} area={area} box={box[0]}x{box[1]} boxes={decided} {secs:.3f} s", flush=True)
            if a.contact:
                c, ok, cs = best_contact(n, area, a.workers, a.time_limit, not a.no_cumulative, not a.no_bl_stable)
                print(f"N={n} contact={c} {'optimal' if ok else 'unproven'} {cs:.3f} s", flush=True)


if __name__ == "__main__":
    main()
