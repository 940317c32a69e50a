#!/usr/bin/python3
"""How a troubled kick's outcome depends on its variables, from rescue samples.

Reads the JSON lines of `juggle eval --controller=planner --rescue-samples-out=FILE`
(planner/rescue_sample_log.h; several files: one per part of a split evaluation) and prints,
over the rescues of soccer juggling (the first five variables are the kick set that acts next:
timing in s, hip, abduction, knee, ankle in rad; the outcome is the kick's timing, dx, dy and
apex errors, docs/planner.md):

  1. roughness: pairs of candidates of one rescue (one state) binned by how far apart their
     variables are (max norm, the timing scaled by --timing-scale to radians' size), with the
     median and p90 of how far apart their landings are;
  2. the local Jacobian: per rescue, a least-squares plane through the candidates within
     --near of its best; the median |entry| and median signed entry over the rescues;
  3. how much of each outcome a quadratic in the variables explains within one rescue (R^2).
  4. with python3-sklearn installed: a gradient-boosted model of the outcome from the state's
     observation and the variables, fitted on all files but the last and scored (R^2) on it.

Usage: scripts/analysis/kick_landscape.py FILE.jsonl [FILE.jsonl ...] [--timing-scale=4]
"""
import argparse
import json
import math
import random
import statistics
import sys

OUTCOMES = ["timing", "dx", "dy", "apex"]
VARIABLES = ["timing", "hip", "abduction", "knee", "ankle"]
BINS = [0.01, 0.03, 0.1, 0.3]


def load(paths):
    """[(file index, rescue id, observation, [(vars, outcome, cost)])]"""
    rescues = []
    for f, path in enumerate(paths):
        by_id = {}
        with open(path) as lines:
            for n, line in enumerate(lines, 1):
                try:
                    row = json.loads(line)
                except json.JSONDecodeError as e:
                    sys.exit(f"{path}:{n}: not JSON ({e})")
                k = row["rescue"]
                if "observation" in row:
                    by_id[k] = (f, k, row["observation"], [])
                elif "theta" in row:
                    out = row["outcome"]
                    if len(out) >= 4 and all(v is not None for v in out[:4]):
                        by_id[k][3].append((row["theta"][:5], out[:4], row["cost"]))
        rescues.extend(by_id.values())
    return rescues


def scaled(v, timing_scale):
    return [v[0] * timing_scale] + list(v[1:5])


def distance(a, b):
    return max(abs(x - y) for x, y in zip(a, b))


def percentile(values, q):
    s = sorted(values)
    return s[min(len(s) - 1, int(q * len(s)))] if s else float("nan")


def roughness(rescues, timing_scale, rng):
    """{bin upper edge: [(|d dx|, |d dy|)]}: near pairs by a grid, far pairs by sampling."""
    pairs = {b: [] for b in BINS}
    for _, _, _, rows in rescues:
        pts = [(scaled(v, timing_scale), o) for v, o, _ in rows]
        grid = {}
        for i, (p, _) in enumerate(pts):
            grid.setdefault(tuple(int(math.floor(x / BINS[1])) for x in p), []).append(i)
        for i, (p, o) in enumerate(pts):  # pairs closer than BINS[1]: neighbouring cells only
            cell = tuple(int(math.floor(x / BINS[1])) for x in p)
            for d in range(3 ** 5):
                other = tuple(c + (d // 3 ** k) % 3 - 1 for k, c in enumerate(cell))
                for j in grid.get(other, []):
                    if j <= i:
                        continue
                    dist = distance(p, pts[j][0])
                    if 1e-9 < dist < BINS[1]:
                        b = BINS[0] if dist < BINS[0] else BINS[1]
                        pairs[b].append((abs(o[1] - pts[j][1][1]), abs(o[2] - pts[j][1][2])))
        for _ in range(min(4000, len(pts) * (len(pts) - 1) // 2)):  # farther pairs: a sample
            i, j = rng.sample(range(len(pts)), 2)
            dist = distance(pts[i][0], pts[j][0])
            b = next((b for b in BINS if dist < b), None)
            if b is not None and dist >= BINS[1]:
                pairs[b].append((abs(pts[i][1][1] - pts[j][1][1]),
                                 abs(pts[i][1][2] - pts[j][1][2])))
    return pairs


def solve(a, b):
    """Least squares by the normal equations (small, well-posed systems); None if singular."""
    n = len(a[0])
    m = [[sum(r[i] * r[j] for r in a) + (1e-12 if i == j else 0) for j in range(n)] +
         [sum(r[i] * y for r, y in zip(a, b))] for i in range(n)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        if abs(m[p][c]) < 1e-15:
            return None
        m[c], m[p] = m[p], m[c]
        for r in range(n):
            if r != c:
                f = m[r][c] / m[c][c]
                m[r] = [x - f * y for x, y in zip(m[r], m[c])]
    return [m[i][n] / m[i][i] for i in range(n)]


def jacobians(rescues, near):
    out = []
    for _, _, _, rows in rescues:
        if not rows:
            continue
        best = min(rows, key=lambda r: r[2])[0]
        local = [(v, o) for v, o, _ in rows if distance(v, best) < near]
        if len(local) < 15:
            continue
        a = [[x - y for x, y in zip(v, best)] + [1.0] for v, _ in local]
        cols = [solve(a, [o[k] for _, o in local]) for k in range(4)]
        if all(c is not None for c in cols):
            out.append([[cols[k][v] for k in range(4)] for v in range(5)])
    return out


def quadratic_r2(rescues):
    r2 = {k: [] for k in range(4)}
    for _, _, _, rows in rescues:
        if len(rows) < 60:
            continue
        a = [[1.0] + list(v) + [x * x for x in v] for v, _, _ in rows]
        for k in range(4):
            y = [o[k] for _, o, _ in rows]
            c = solve(a, y)
            var = statistics.pvariance(y)
            if c is None or var <= 0:
                continue
            res = sum((sum(ci * xi for ci, xi in zip(c, r)) - t) ** 2 for r, t in zip(a, y))
            r2[k].append(1 - res / len(y) / var)
    return r2


def across_states(rescues):
    try:
        from sklearn.ensemble import HistGradientBoostingRegressor
        from sklearn.metrics import r2_score
    except ImportError:
        print("4. across states: skipped (python3-sklearn is not installed)")
        return
    last = max(f for f, _, _, _ in rescues)
    if last == 0:
        print("4. across states: skipped (give two or more files: the last is held out)")
        return
    split = {True: ([], []), False: ([], [])}
    for f, _, obs, rows in rescues:
        for v, o, _ in rows:
            split[f == last][0].append(list(obs) + list(v))
            split[f == last][1].append(o)
    (xt, yt), (xh, yh) = split[False], split[True]
    print(f"4. across states: fitted on {len(xt)} rollouts, held out {len(xh)} (the last file)")
    for k, name in enumerate(OUTCOMES):
        model = HistGradientBoostingRegressor(max_iter=300).fit(xt, [y[k] for y in yt])
        print(f"   {name:7s} R^2 {r2_score([y[k] for y in yh], model.predict(xh)):+.2f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("files", nargs="+")
    parser.add_argument("--timing-scale", type=float, default=4.0,
                        help="rad per s of timing in the distances (the kick box: 0.6 / 0.15)")
    parser.add_argument("--near", type=float, default=0.05,
                        help="max-norm radius around a rescue's best for its Jacobian")
    args = parser.parse_args()
    rescues = [r for r in load(args.files) if r[3]]
    rollouts = sum(len(r[3]) for r in rescues)
    print(f"{len(rescues)} rescues, {rollouts} rollouts with a kick outcome")
    pairs = roughness(rescues, args.timing_scale, random.Random(1))
    print("1. roughness: candidates of one state, their landings apart (m)")
    lower = 0
    for b in BINS:
        p = pairs[b]
        if p:
            xs, ys = [x for x, _ in p], [y for _, y in p]
            print(f"   vars {lower:<5g}-{b:<5g} apart: {len(p):7d} pairs, |d dx| median "
                  f"{statistics.median(xs):.3f} p90 {percentile(xs, 0.9):.3f}, |d dy| median "
                  f"{statistics.median(ys):.3f} p90 {percentile(ys, 0.9):.3f}")
        lower = b
    jac = jacobians(rescues, args.near)
    print(f"2. local Jacobian near the best ({len(jac)} rescues; rows: variables, columns: "
          f"{', '.join(OUTCOMES)}; per s of timing, per rad of the angles)")
    for v, name in enumerate(VARIABLES):
        med = [statistics.median(abs(j[v][k]) for j in jac) for k in range(4)]
        sig = [statistics.median(j[v][k] for j in jac) for k in range(4)]
        print(f"   {name:9s} |J| " + " ".join(f"{x:7.2f}" for x in med) +
              "   signed " + " ".join(f"{x:7.2f}" for x in sig))
    r2 = quadratic_r2(rescues)
    print("3. a quadratic in the variables within one rescue explains (median R^2 over rescues): " +
          ", ".join(f"{OUTCOMES[k]} {statistics.median(r2[k]):.2f}" for k in range(4) if r2[k]))
    across_states(rescues)


if __name__ == "__main__":
    main()
