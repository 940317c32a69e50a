#!/usr/bin/env python3
"""Per-kick statistics of a right-foot soccer recording: how far each kick's ball flight is from
what the next contact needs (docs/learning.md, "Where it stands").

usage: scripts/analysis/kick_stats.py TRAJECTORY [TRAJECTORY ...] [--apex 1.4] [--contact 0.5] [--target_x 0.6]
                             [--target_y -0.1] [--window 0.06]

Each TRAJECTORY is a `juggle eval --record=FILE` or `juggle render --record=FILE` recording of a
graph whose nodes all have the same apex and contact height (right_foot*, default values). For
kick k of every episode (k = 1, 2, ...) it measures, from the ball's recorded flight after the
contact until it falls back through the contact height:
  - apex error: highest ball z minus --apex;
  - crossing dx, dy: where the ball falls through --contact, relative to the root plus the ball
    target (the position the next kick is aimed at);
  - crossing time error: seconds between that crossing and the nominal contact (phase 0.5 of the
    cycle), the quantity the task's ±60 ms contact window limits.
Kicks whose ball does not come back through the contact height (the episode ended first, e.g.
an early contact above it) are counted as "not returned". Standard library only.
"""
import argparse
import math
import statistics
import struct
import sys


def load(path):
    """Returns (channel names, records, header); a record is [time, channels..., qpos...]."""
    try:
        f = open(path, 'rb')
    except OSError as e:
        sys.exit(f'{path}: {e.strerror}')
    with f:
        header, channels = {}, []
        while True:
            line = f.readline()
            if not line:
                sys.exit(f'{path}: no "data" line: not a juggle trajectory')
            key, _, value = line.decode().rstrip('\n').partition(' ')
            if key == 'channel':
                channels.append(value.split(' ')[0])
            else:
                header[key] = value
            if key == 'data':
                break
        if not header.get('juggle-trajectory'):
            sys.exit(f'{path}: not a juggle trajectory (first line)')
        n, nq = int(header['data']), int(header['nq'])
        width = 1 + len(channels) + nq
        raw = f.read()
    if len(raw) != 8 * n * width:
        sys.exit(f'{path}: {len(raw)} bytes of data, expected {8 * n * width}')
    values = struct.unpack(f'<{n * width}d', raw)
    return channels, [values[i * width:(i + 1) * width] for i in range(n)], header


def columns(channels, nq):
    """(channel name -> record column, first qpos column, ball qpos column)."""
    c = {name: 1 + i for i, name in enumerate(channels)}
    q0 = 1 + len(channels)
    return c, q0, q0 + nq - 7  # the ball's free joint is the model's last


def episode_contacts(channels, records, nq, contact):
    """Yields (rows, ball heights, contact indices) per episode: a contact is a local minimum
    of the ball's height below contact + 0.4 m."""
    c, _, ball = columns(channels, nq)
    episodes = {}
    for r in records:
        episodes.setdefault(int(r[c['episode']]), []).append(r)
    for rows in episodes.values():
        z = [r[ball + 2] for r in rows]
        yield rows, z, [i for i in range(1, len(z) - 1)
                        if z[i] < z[i - 1] and z[i + 1] > z[i] and z[i] < contact + 0.4]


def kicks(channels, records, nq, args):
    """Yields (kick number, apex error, dx, dy, time error) or (kick number, None...)."""
    c, q0, ball = columns(channels, nq)
    cycle = 2 * math.sqrt(2 * (args.apex - args.contact) / 9.81)
    for rows, z, contacts in episode_contacts(channels, records, nq, args.contact):
        for k, i in enumerate(contacts, start=1):
            j = i + 1
            while j < len(z) and not (z[j - 1] >= args.contact > z[j]):
                j += 1
            if j >= len(z):
                yield (k, None, None, None, None)
                continue
            f = (z[j - 1] - args.contact) / (z[j - 1] - z[j])
            lerp = lambda col: rows[j - 1][col] + f * (rows[j][col] - rows[j - 1][col])
            dx = lerp(ball) - lerp(q0) - args.target_x
            dy = lerp(ball + 1) - lerp(q0 + 1) - args.target_y
            p0, p1 = rows[j - 1][c['phase']], rows[j][c['phase']]
            phase = p0 + f * (p1 - p0) if p1 >= p0 else p0
            yield (k, max(z[i:j]) - args.apex, dx, dy, (phase - 0.5) * cycle)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('trajectory', nargs='+', help='recordings, pooled')
    parser.add_argument('--apex', type=float, default=1.4)
    parser.add_argument('--contact', type=float, default=0.5)
    parser.add_argument('--target_x', type=float, default=0.6)
    parser.add_argument('--target_y', type=float, default=-0.1)
    parser.add_argument('--window', type=float, default=0.06, help='contact window (s)')
    args = parser.parse_args()
    by_kick = {}
    for path in args.trajectory:
        channels, records, header = load(path)
        if 'phase' not in channels or header.get('family') != 'soccer_juggle':
            sys.exit(f'{path}: needs a soccer_juggle recording with a phase channel')
        for row in kicks(channels, records, int(header['nq']), args):
            # Kicks 1-3 on their own (the first ones set up the rest), later ones pooled.
            key = row[0] if row[0] <= 3 else '4+'
            by_kick.setdefault(key, []).append(row[1:])
    for k in sorted(by_kick, key=lambda k: 4 if k == '4+' else k):
        rows = by_kick[k]
        done = [r for r in rows if r[0] is not None]
        print(f'kick {k}: {len(rows)} kicks, {len(rows) - len(done)} not returned to the contact '
              'height')
        if not done:
            continue
        for col, name in enumerate(('apex error (m)', 'crossing dx (m)', 'crossing dy (m)',
                                    'crossing time error (s)')):
            v = [r[col] for r in done]
            a = sorted(abs(x) for x in v)
            p90 = a[min(len(a) - 1, int(0.9 * len(a)))]
            print(f'  {name:24s} mean {statistics.mean(v):+.3f}  sd {statistics.pstdev(v):.3f}  '
                  f'|median| {a[len(a) // 2]:.3f}  |p90| {p90:.3f}')
        inside = sum(abs(r[3]) <= args.window for r in done)
        print(f'  returned within ±{args.window * 1000:.0f} ms of the nominal contact: '
              f'{inside} of {len(rows)}')


if __name__ == '__main__':
    main()
