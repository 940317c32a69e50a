#!/usr/bin/env python3
"""scripts/analysis/football_kicks.py on hand-made episode lines whose metrics are known: four
kicks, one failed (no deviation fields) and one fallen, in two target-speed bands; KSR counts
every attempt, KDD and KSD average the successes only, bands split at their edges, KDD's floor
averages the successes that report it."""
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, '..', 'scripts', 'analysis', 'football_kicks.py')


def kick(target, ok, kdd=0.0, ksd=0.0, speed=0.0, fell=0.0, floor=None):
    r = {'table': 'episode', 'kick_success': 1.0 if ok else 0.0, 'kick_target_speed_mps': target,
         'fell': fell}
    if ok:
        r.update({'kick_direction_deviation_deg': kdd, 'kick_speed_deviation_mps': ksd,
                  'kick_speed_mps': speed, 'kick_foot_speed_mps': speed / 2})
    if floor is not None:
        r['kick_direction_floor_deg'] = floor
    return r


rows = [{'table': 'summary', 'episodes': 4},
        kick(6, True, kdd=2, ksd=1, speed=7, floor=1.5),
        kick(8, True, kdd=4, ksd=3, speed=5, floor=2.5),
        kick(12, False, fell=1.0),
        kick(14, True, kdd=9, ksd=6, speed=8)]
with tempfile.NamedTemporaryFile('w', suffix='.jsonl', delete=False) as f:
    for r in rows:
        f.write(json.dumps(r) + '\n')
out = subprocess.run([sys.executable, SCRIPT, f.name, '--bands=5,10,15'], capture_output=True,
                     text=True, check=True).stdout.splitlines()
lines = {l.split()[0]: l.split() for l in out[1:]}
# all: 4 attempts, 3 successes; KDD (2+4+9)/3 = 5, KSD (1+3+6)/3 = 3.333; max speed 8; 1 fall;
# the floor averages the successes that report it, (1.5+2.5)/2.
assert lines['all'][1:] == ['4', '0.750', '5.00', '3.33', '6.67', '8.00', '3.33', '1', '2.00'], \
    lines['all']
# [5, 10): the two slow kicks; [10, 15): one failure, one success without a floor.
assert lines['[5,'][2:] == ['2', '1.000', '3.00', '2.00', '6.00', '7.00', '3.00', '0', '2.00'], \
    lines['[5,']
assert lines['[10,'][2:] == ['2', '0.500', '9.00', '6.00', '8.00', '8.00', '4.00', '1', 'nan'], \
    lines['[10,']
# No kick lines: a clear error.
with tempfile.NamedTemporaryFile('w', suffix='.jsonl', delete=False) as g:
    g.write(json.dumps({'table': 'summary'}) + '\n')
bad = subprocess.run([sys.executable, SCRIPT, g.name], capture_output=True, text=True)
assert bad.returncode != 0 and 'no football kick episodes' in bad.stderr, bad.stderr
print('ok')
