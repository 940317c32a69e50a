#!/usr/bin/env python3
"""PhysicsFC's kick metrics from `juggle eval --json` lines of the football KICK task, overall
and by target-speed band (docs/football.md, "Results").

    scripts/analysis/football_kicks.py kicks.jsonl [--bands=5,10,15,20,25]

Per band: attempts, KSR (successes / attempts), KDD and KSD (means over successes, as
envs/football/metrics.h aggregates them), the measured ball speed (mean and max over successes),
the kicking foot's speed at the touch, falls, and KDD's floor: the mean over successes of the
least KDD any aim could have given each ball's flight (`kick_direction_floor_deg`, gravity's turn
inside the window; nan for files written before it). Reads only "table": "episode" lines.
"""
import argparse
import json
import math
import sys


def load(path):
    with open(path) as f:
        rows = [json.loads(line) for line in f if line.strip()]
    return [r for r in rows if r.get('table') == 'episode' and 'kick_success' in r]


def summarize(rows):
    ok = [r for r in rows if r['kick_success'] > 0.5]
    mean = lambda xs: sum(xs) / len(xs) if xs else math.nan
    return {
        'n': len(rows),
        'ksr': len(ok) / len(rows) if rows else math.nan,
        'kdd_deg': mean([r['kick_direction_deviation_deg'] for r in ok]),
        'ksd_mps': mean([r['kick_speed_deviation_mps'] for r in ok]),
        'speed_mean': mean([r['kick_speed_mps'] for r in ok]),
        'speed_max': max([r['kick_speed_mps'] for r in ok], default=math.nan),
        'foot_mean': mean([r['kick_foot_speed_mps'] for r in ok if 'kick_foot_speed_mps' in r]),
        'falls': sum(1 for r in rows if r.get('fell', 0) > 0.5),
        'kdd_floor': mean([r['kick_direction_floor_deg'] for r in ok
                           if 'kick_direction_floor_deg' in r]),
    }


def row(label, s):
    return (f"{label:<14} {s['n']:>5} {s['ksr']:>6.3f} {s['kdd_deg']:>8.2f} {s['ksd_mps']:>8.2f} "
            f"{s['speed_mean']:>8.2f} {s['speed_max']:>8.2f} {s['foot_mean']:>8.2f} {s['falls']:>5} "
            f"{s['kdd_floor']:>9.2f}")


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    p.add_argument('jsonl')
    p.add_argument('--bands', default='5,10,15,20,25',
                   help='target-speed band edges, m/s (default 5,10,15,20,25)')
    a = p.parse_args(argv)
    rows = load(a.jsonl)
    if not rows:
        sys.exit(f'{a.jsonl}: no football kick episodes (run juggle eval --json on a KICK config)')
    edges = [float(x) for x in a.bands.split(',')]
    print(f"{'target m/s':<14} {'n':>5} {'ksr':>6} {'kdd_deg':>8} {'ksd_mps':>8} "
          f"{'speed':>8} {'max':>8} {'foot':>8} {'falls':>5} {'kdd_floor':>9}")
    print(row('all', summarize(rows)))
    for lo, hi in zip(edges, edges[1:]):
        band = [r for r in rows if lo <= r['kick_target_speed_mps'] < hi or
                (hi == edges[-1] and r['kick_target_speed_mps'] == hi)]
        print(row(f'[{lo:g}, {hi:g})', summarize(band)))


if __name__ == '__main__':
    main(sys.argv[1:])
