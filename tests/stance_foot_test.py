#!/usr/bin/env python3
"""scripts/analysis/stance_foot.py on a hand-made recording whose headings and sole are known.

Steps 0-10: the character turned about the vertical by 0, 1, ..., 10 degrees, legs straight, the
root 0.5 mm lower than the sole's rest height (0.881416 m: the thigh's and shin's lengths plus the
box's half height and offset), so all four corners are down and the foot turns +10 degrees on its
whole sole. Step 11: the left ankle pitched 0.2 rad about its lateral axis (toe up), so the toe's
corners rise and the heel's sink (the box's corners at x = 0.045 -/+ 0.0885, y = -0.05 rotated)
(closed form below); two corners down. Step 12: turned to 12 degrees on those two corners.
"""
import math
import os
import struct
import subprocess
import sys
import tempfile

NQ = 50
HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, '..', 'scripts', 'analysis', 'stance_foot.py')
REST = 0.421546 + 0.40987 + 0.05
UPRIGHT = (math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0)


def turned(deg):
    h = math.radians(deg) / 2
    c, s = math.cos(h), math.sin(h)
    w, x, y, z = UPRIGHT  # (cos h, 0, 0, sin h) * upright
    return (c * w - s * z, c * x - s * y, c * y + s * x, c * z + s * w)


def frame(deg, ankle_pitch):
    qpos = [0.0] * NQ
    qpos[2] = REST - 0.0005
    qpos[3:7] = turned(deg)
    for adr in (7, 11, 15, 20, 25, 30, 34, 39):  # every ball joint at identity
        qpos[adr] = 1.0
    qpos[39:43] = (math.cos(ankle_pitch / 2), 0.0, 0.0, math.sin(ankle_pitch / 2))
    return qpos


def main():
    rows = [frame(d, 0.0) for d in range(11)] + [frame(10, 0.2), frame(12, 0.2)]
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, 's.traj')
        with open(path, 'wb') as f:
            f.write(b'juggle-trajectory 2\nfamily soccer_juggle\nconfig x\ncontrol_dt 0.02\n'
                    b'nq 50\nchannel episode\nchannel outcome running,fell\n')
            f.write(f'data {len(rows)}\n'.encode())
            for i, q in enumerate(rows):
                f.write(struct.pack(f'<{3 + NQ}d', i * 0.02, 0, 0, *q))
        out = subprocess.run([sys.executable, SCRIPT, path, '--every', '0.1', '--corners',
                              '--from', '0.22', '--to', '0.22'], capture_output=True, text=True,
                             check=True).stdout
    print(out)
    failures = []
    lines = out.splitlines()
    corner_line = next(l for l in lines if 'corners_mm' in l)
    heights = [float(v) for v in corner_line.split(')')[-1].split()]
    a = 0.2
    heel = 1000 * (-0.0435 * math.sin(a) - 0.05 * math.cos(a) + 0.05) - 0.5
    toe = 1000 * (0.1335 * math.sin(a) - 0.05 * math.cos(a) + 0.05) - 0.5
    for got, want in zip(heights, [heel, heel, toe, toe]):
        if abs(got - want) > 0.06:
            failures.append(f'corner height {got} mm, want {want:.2f}')
    if 'left_foot=  10.00' not in corner_line:
        failures.append('the pitched foot keeps its heading of 10 degrees')
    headings = [l for l in lines if l.strip().startswith('t=') and 'corners' not in l]
    if not any('t=  0.20 root=  10.00 left_foot=  10.00' in l for l in headings):
        failures.append('expected root and foot at 10 degrees at t = 0.2')
    four = next((l for l in lines if l.strip().startswith('4 down')), '')
    two = next((l for l in lines if l.strip().startswith('2 down')), '')
    if '91.7 % of steps' not in four or 'net    +10.0 deg' not in four:
        failures.append(f'the ten 1-degree turns and the pitch on the whole sole: "{four}"')
    if '8.3 % of steps' not in two or 'net     +2.0 deg' not in two:
        failures.append(f'the last 2-degree turn on the toe alone: "{two}"')
    for f in failures:
        print('FAIL:', f)
    sys.exit(1 if failures else 0)


if __name__ == '__main__':
    main()
