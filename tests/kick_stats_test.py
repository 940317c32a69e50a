#!/usr/bin/env python3
"""scripts/analysis/kick_stats.py on hand-made recordings whose kick errors are known in closed form.

Episode 0: the ball falls from the 1.4 m apex (phase 0 at t = 0) onto the foot at 0.5 m, leaves
it at v = sqrt(2 g 1.0) (apex 1.5 m) with vx = 0.05 m/s from 0.1 m ahead of the target, and falls
back through 0.5 m after 2v/g: apex error +0.1, dx = 0.1 + 0.05·2v/g, dy = 0.02, time error
2v/g − cycle. Episode 1: the same kick, but the episode ends at the apex (not returned).
"""
import math
import os
import struct
import subprocess
import sys
import tempfile

G, DT, NQ = 9.81, 0.02, 50
HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, '..', 'scripts', 'analysis', 'kick_stats.py')
CYCLE = 2 * math.sqrt(2 * 0.9 / G)
T_CONTACT = CYCLE / 2
V_OUT = math.sqrt(2 * G * 1.0)


def ball(t):
    """Ball (x, y, z) relative to a root at the origin."""
    if t <= T_CONTACT:
        return 0.7, -0.08, 1.4 - 0.5 * G * t * t
    s = t - T_CONTACT
    return 0.7 + 0.05 * s, -0.08, 0.5 + V_OUT * s - 0.5 * G * s * s


def write(path, end_times):
    records = []
    for episode, end in enumerate(end_times):
        for i in range(int(end / DT) + 1):
            t = i * DT
            qpos = [0.0] * NQ
            qpos[2] = 0.9
            qpos[43:46] = ball(t)
            phase = (t / CYCLE) % 1.0
            node = 0 if phase < 0.5 else 1
            records.append([t, episode, t, 0, node, phase] + qpos)
    with open(path, 'wb') as f:
        f.write(b'juggle-trajectory 2\nfamily soccer_juggle\nconfig x\ncontrol_dt 0.02\n'
                b'nq 50\nchannel episode\nchannel episode_time\n'
                b'channel outcome running,time_limit\nchannel node down,up\nchannel phase\n')
        f.write(f'data {len(records)}\n'.encode())
        for r in records:
            f.write(struct.pack(f'<{len(r)}d', *r))


def field(out, line_start, name):
    line = next(l for l in out.splitlines() if l.strip().startswith(line_start))
    return float(line.split(name)[1].split()[0])


def main():
    flight = 2 * V_OUT / G
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, 'k.traj')
        write(path, [T_CONTACT + flight + 0.1, T_CONTACT + V_OUT / G])
        out = subprocess.run([sys.executable, SCRIPT, path], capture_output=True, text=True,
                             check=True).stdout
        # Two recordings are pooled: each kick counted twice, the errors unchanged.
        pooled = subprocess.run([sys.executable, SCRIPT, path, path], capture_output=True,
                                text=True, check=True).stdout
    print(out)
    failures = []

    def expect(what, got, want, tol):
        if abs(got - want) > tol:
            failures.append(f'{what}: got {got}, want {want} ± {tol}')

    if 'kick 1: 2 kicks, 1 not returned' not in out:
        failures.append('expected "kick 1: 2 kicks, 1 not returned"')
    expect('apex error', field(out, 'apex error', 'mean'), 0.1, 0.005)
    expect('crossing dx', field(out, 'crossing dx', 'mean'), 0.1 + 0.05 * flight, 0.003)
    expect('crossing dy', field(out, 'crossing dy', 'mean'), 0.02, 1e-6)
    expect('time error', field(out, 'crossing time error', 'mean'), flight - CYCLE, 0.003)
    if 'returned within ±60 ms of the nominal contact: 1 of 2' not in out:
        failures.append('expected 1 of 2 kicks inside the window')
    if 'kick 1: 4 kicks, 2 not returned' not in pooled:
        failures.append('expected two pooled recordings to give "kick 1: 4 kicks, 2 not returned"')
    elif field(pooled, 'apex error', 'mean') != field(out, 'apex error', 'mean'):
        failures.append('pooling the same recording twice changed the mean apex error')
    for f in failures:
        print('FAIL:', f)
    sys.exit(1 if failures else 0)


if __name__ == '__main__':
    main()
