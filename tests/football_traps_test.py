#!/usr/bin/env python3
"""scripts/analysis/football_traps.py on hand-made episode lines whose metrics are known: four
traps (three lobs, one ground pass), one failed but touched first by another part, one a
handball; TSR counts every attempt, seed 002's TSR any first touch before the turf, HRTS and
RBSPT the successes only, lobs split by part; TRAP_KICK's lines add the sequences' table (the
share switched to the kick, succeeded, out of reach; KDD and KSD over successful kicks) and the
count of the kick's first touches by part."""
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, '..', 'scripts', 'analysis', 'football_traps.py')


def trap(part, lob, ok, any_first, rbspt=None, handball=0.0, meet=10.0, fell=0.0):
    r = {'table': 'episode', 'trap_success': 1.0 if ok else 0.0,
         'trap_touch_before_ground': 1.0 if any_first else 0.0, 'trap_part': part,
         'trap_lob': 1.0 if lob else 0.0, 'trap_meet_speed_mps': meet, 'fell': fell}
    if ok:
        r.update({'trap_handball': handball, 'trap_rbspt_mps': rbspt})
    return r


rows = [{'table': 'summary', 'episodes': 4},
        trap(1, True, True, True, rbspt=2.0, meet=8),
        trap(4, True, True, True, rbspt=4.0, handball=1.0, meet=12),
        trap(4, True, False, True, fell=1.0, meet=10),
        trap(1, False, True, True, rbspt=1.0, meet=4)]
with tempfile.NamedTemporaryFile('w', suffix='.jsonl', delete=False) as f:
    for r in rows:
        f.write(json.dumps(r) + '\n')
out = subprocess.run([sys.executable, SCRIPT, f.name], capture_output=True, text=True,
                     check=True).stdout.splitlines()
lines = {l.split()[0]: l.split() for l in out[1:]}
# all: 4 attempts, 3 successes, 4 first touches before the turf; 1 handball of 3; RBSPT 7/3.
assert lines['all'][1:] == ['4', '0.750', '1.000', '0.333', '2.33', '8.50', '1'], lines['all']
assert lines['lob'][1:] == ['3', '0.667', '1.000', '0.500', '3.00', '10.00', '1'], lines['lob']
assert lines['ground'][1:] == ['1', '1.000', '1.000', '0.000', '1.00', '4.00', '0'], lines['ground']
assert lines['lob:head'][1:] == ['2', '0.500', '1.000', '1.000', '4.00', '11.00', '1'], lines['lob:head']
assert lines['lob:foot'][1:3] == ['1', '1.000'], lines['lob:foot']
assert not any(l.startswith('seq:') for l in lines), 'no sequence table for TRAP lines'

# TRAP_KICK lines: two sequences reach the kick (one kicked well, one kick failed), one ends
# out of reach.
def sequence(part, lob, switched, ok, kdd=None, ksd=None, outcome='kicked', touch=None):
    r = trap(part, lob, switched, True, rbspt=1.0)
    r.update({'outcome': outcome, 'trap_kick_switched': 1.0 if switched else 0.0,
              'trap_kick_success': 1.0 if ok else 0.0})
    if switched:
        r['kick_success'] = 1.0 if kdd is not None else 0.0
    if kdd is not None:
        r.update({'kick_direction_deviation_deg': kdd, 'kick_speed_deviation_mps': ksd})
    if touch is not None:
        for part in ('kicking_leg', 'standing_leg', 'upper_body'):
            r[f'kick_touch_{part}'] = 1.0 if touch == part else 0.0
    return r


seq = [sequence(1, False, True, True, kdd=4.0, ksd=2.0, touch='kicking_foot'),
       sequence(3, True, True, False, outcome='wrong_touch', touch='standing_leg'),
       sequence(4, True, True, False, outcome='wrong_touch', touch='standing_leg'),
       sequence(3, True, False, False, outcome='out_of_reach')]
with tempfile.NamedTemporaryFile('w', suffix='.jsonl', delete=False) as h:
    for r in seq:
        h.write(json.dumps(r) + '\n')
out = subprocess.run([sys.executable, SCRIPT, h.name], capture_output=True, text=True,
                     check=True).stdout.splitlines()
seqs = {l.split()[0]: l.split() for l in out if l.startswith('seq:')}
assert seqs['seq:all'][1:] == ['4', '0.750', '0.250', '0.250', '4.00', '2.00'], seqs['seq:all']
assert seqs['seq:lob:torso'][1:5] == ['2', '0.500', '0.000', '0.500'], seqs['seq:lob:torso']
assert out[-1] == 'first touch of the kick: standing_leg 2, kicking_foot 1', out[-1]
assert seqs['seq:ground'][1:4] == ['1', '1.000', '1.000'], seqs['seq:ground']

# No trap lines: a clear error.
with tempfile.NamedTemporaryFile('w', suffix='.jsonl', delete=False) as g:
    g.write(json.dumps({'table': 'summary'}) + '\n')
bad = subprocess.run([sys.executable, SCRIPT, g.name], capture_output=True, text=True)
assert bad.returncode != 0 and 'no football trap episodes' in bad.stderr, bad.stderr
print('ok')
