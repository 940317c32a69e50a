#!/usr/bin/env python3
"""PhysicsFC's trap metrics from `juggle eval --json` lines of the football TRAP task, overall,
for lobs and ground passes, and by designated part (docs/football.md, "The trap by search").

    scripts/analysis/football_traps.py traps.jsonl

Per group: attempts; TSR as issue 45 defines it (the designated part first, before the turf, the
ball within reach afterwards: trap_success); seed 002's own TSR (any part first, before the
turf: trap_touch_before_ground); HRTS (successes the arms touched / successes); RBSPT (mean
relative speed over successes, m/s); the ball's speed at the meeting point; falls. For the
TRAP_KICK task (lines with trap_kick_success) a second table, its groups named seq:<group>:
the share of sequences that reached the kick (trap_kick_switched), that succeeded
(trap_kick_success: the trap, the kick, no fall), that ended out_of_reach, and KDD (deg) and
KSD (m/s) over the successful kicks, then which part touched the ball first in the kicks that
reached a touch (kick_touch_*). Reads only "table": "episode" lines.
"""
import argparse
import json
import math
import sys

PARTS = {1: 'foot', 2: 'lower_leg', 3: 'torso', 4: 'head'}
# The kick's first-touch metrics (0/1, envs/football/env.h); all 0: the kicking foot.
TOUCH_PARTS = ('kicking_leg', 'standing_leg', 'upper_body')


def load(path):
    with open(path) as f:
        rows = [json.loads(line) for line in f if line.strip()]
    return [r for r in rows if r.get('table') == 'episode' and 'trap_success' in r]


def summarize(rows):
    ok = [r for r in rows if r['trap_success'] > 0.5]
    mean = lambda xs: sum(xs) / len(xs) if xs else math.nan
    return {
        'n': len(rows),
        'tsr': len(ok) / len(rows) if rows else math.nan,
        'tsr_any': mean([r['trap_touch_before_ground'] for r in rows]),
        'hrts': mean([r.get('trap_handball', 0) for r in ok]),
        'rbspt': mean([r['trap_rbspt_mps'] for r in ok if 'trap_rbspt_mps' in r]),
        'meet_speed': mean([r['trap_meet_speed_mps'] for r in rows]),
        'falls': sum(1 for r in rows if r.get('fell', 0) > 0.5),
    }


def summarize_sequences(rows):
    mean = lambda xs: sum(xs) / len(xs) if xs else math.nan
    kicks = [r for r in rows if r.get('kick_success', 0) > 0.5]
    return {
        'n': len(rows),
        'switched': mean([r['trap_kick_switched'] for r in rows]),
        'trap_kick': mean([r['trap_kick_success'] for r in rows]),
        'out_of_reach': mean([1.0 if r.get('outcome') == 'out_of_reach' else 0.0 for r in rows]),
        'kdd': mean([r['kick_direction_deviation_deg'] for r in kicks]),
        'ksd': mean([r['kick_speed_deviation_mps'] for r in kicks]),
    }


def sequence_row(label, s):
    return (f"{label:<16} {s['n']:>5} {s['switched']:>8.3f} {s['trap_kick']:>9.3f} "
            f"{s['out_of_reach']:>8.3f} {s['kdd']:>7.2f} {s['ksd']:>7.2f}")


def row(label, s):
    return (f"{label:<12} {s['n']:>5} {s['tsr']:>6.3f} {s['tsr_any']:>8.3f} {s['hrts']:>6.3f} "
            f"{s['rbspt']:>7.2f} {s['meet_speed']:>7.2f} {s['falls']:>5}")


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    p.add_argument('jsonl')
    a = p.parse_args(argv)
    rows = load(a.jsonl)
    if not rows:
        sys.exit(f'{a.jsonl}: no football trap episodes (run juggle eval --json on a TRAP config)')
    print(f"{'passes':<12} {'n':>5} {'tsr':>6} {'tsr_any':>8} {'hrts':>6} {'rbspt':>7} "
          f"{'meet':>7} {'falls':>5}")
    print(row('all', summarize(rows)))
    lobs = [r for r in rows if r['trap_lob'] > 0.5]
    ground = [r for r in rows if r['trap_lob'] <= 0.5]
    for label, group in (('lob', lobs), ('ground', ground)):
        if group:
            print(row(label, summarize(group)))
    for part, name in PARTS.items():
        group = [r for r in lobs if int(r['trap_part']) == part]
        if group:
            print(row(f'lob:{name}', summarize(group)))
    sequences = [r for r in rows if 'trap_kick_success' in r]
    if not sequences:
        return
    print(f"\n{'sequences':<16} {'n':>5} {'switched':>8} {'trap_kick':>9} {'out_reach':>8} "
          f"{'kdd':>7} {'ksd':>7}")
    groups = [('seq:all', sequences),
              ('seq:lob', [r for r in sequences if r['trap_lob'] > 0.5]),
              ('seq:ground', [r for r in sequences if r['trap_lob'] <= 0.5])]
    groups += [(f'seq:lob:{name}', [r for r in sequences
                                   if r['trap_lob'] > 0.5 and int(r['trap_part']) == part])
               for part, name in PARTS.items()]
    for label, group in groups:
        if group:
            print(sequence_row(label, summarize_sequences(group)))
    touches = {}
    for r in sequences:
        if 'kick_touch_upper_body' in r:
            name = next((p for p in TOUCH_PARTS if r[f'kick_touch_{p}'] > 0.5), 'kicking_foot')
            touches[name] = touches.get(name, 0) + 1
    if touches:
        print('\nfirst touch of the kick: ' +
              ', '.join(f'{name} {n}' for name, n in sorted(touches.items(), key=lambda x: -x[1])))


if __name__ == '__main__':
    main(sys.argv[1:])
