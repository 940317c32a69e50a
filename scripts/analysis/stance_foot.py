#!/usr/bin/python3
"""The standing (left) foot over soccer-juggling recordings: its heading and its sole's corners.

    scripts/analysis/stance_foot.py [--every S] [--from T0 --to T1] [--corners] RUN.traj ...

Per recording, every S seconds: the root's and the left foot's headings (degrees about the
world's vertical, 0 along +x); with --corners the heights (mm) of the left sole's four lower
corners at every control step between T0 and T1. Over all recordings, the foot's turn split by
how many corners are down (< 1 mm above the floor): where a foot that turns pivots on a corner,
where it creeps on its whole sole (docs/planner.md, "The standing foot's turn, traced").
Forward kinematics of configs/models/humanoid.xml (its bodies carry no rotations of their own,
so every body's local x is forward at rest) and juggle_scene.xml's box foot; standard library.
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from trajectory import read_trajectory  # noqa: E402

# qpos addresses in the juggling scenes (nq 50): root 0-6, then the joints in humanoid.xml's order.
LEFT_HIP, LEFT_KNEE, LEFT_ANKLE = 34, 38, 39
HIP_OFFSET = (0, 0, -0.084887)  # left_hip in root
KNEE_OFFSET = (0, -0.421546, 0)  # left_knee in left_hip
ANKLE_OFFSET = (0, -0.40987, 0)  # left_ankle in left_knee
SOLE = [(0.045 + sx * 0.0885, -0.05, sz * 0.045) for sx in (-1, 1) for sz in (-1, 1)]


def qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return (w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2)


def rotate(q, v):
    w, x, y, z = q
    r = [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
         [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
         [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]
    return [sum(r[i][k] * v[k] for k in range(3)) for i in range(3)]


def heading(q):
    w, x, y, z = q
    return math.degrees(math.atan2(2 * (x * y + w * z), 1 - 2 * (y * y + z * z)))


def left_foot(qpos):
    """The left foot's world rotation and its sole's corner heights (m)."""
    root = tuple(qpos[3:7])
    hip = qmul(root, tuple(qpos[LEFT_HIP:LEFT_HIP + 4]))
    half = qpos[LEFT_KNEE] / 2  # the knee turns about its body's z
    knee = qmul(hip, (math.cos(half), 0, 0, math.sin(half)))
    foot = qmul(knee, tuple(qpos[LEFT_ANKLE:LEFT_ANKLE + 4]))
    pos = [a + b for a, b in zip(qpos[0:3], rotate(root, HIP_OFFSET))]
    pos = [a + b for a, b in zip(pos, rotate(hip, KNEE_OFFSET))]
    pos = [a + b for a, b in zip(pos, rotate(knee, ANKLE_OFFSET))]
    return foot, [pos[2] + rotate(foot, c)[2] for c in SOLE]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("traj", nargs="+")
    ap.add_argument("--every", type=float, default=5.0, help="seconds between heading lines")
    ap.add_argument("--corners", action="store_true", help="corner heights between --from/--to")
    ap.add_argument("--from", dest="t0", type=float, default=0.0)
    ap.add_argument("--to", dest="t1", type=float, default=1e9)
    args = ap.parse_args()
    split = {}  # corners down -> [steps, net turn, |turn|]
    for path in args.traj:
        header, _, rows = read_trajectory(path)
        if header.get("family") != "soccer_juggle" or int(header["nq"]) != 50:
            sys.exit(f"{path}: not a soccer-juggling recording (family {header.get('family')})")
        print(path)
        previous, next_line = None, 0.0
        for row in rows:
            qpos, t = row["qpos"], row["time"]
            foot, heights = left_foot(qpos)
            down = sum(h < 0.001 for h in heights)
            if t + 1e-9 >= next_line:
                print(f"  t={t:6.2f} root={heading(tuple(qpos[3:7])):7.2f} "
                      f"left_foot={heading(foot):7.2f}")
                next_line += args.every
            if args.corners and args.t0 - 1e-9 <= t <= args.t1 + 1e-9:
                print(f"  t={t:6.2f} left_foot={heading(foot):7.2f} corners_mm (heel-l heel-r "
                      "toe-l toe-r) " + " ".join(f"{1000 * h:6.1f}" for h in heights))
            if previous is not None and row["outcome"] == 0:
                turn = (heading(foot) - previous[0] + 180) % 360 - 180
                entry = split.setdefault(previous[1], [0, 0.0, 0.0])
                entry[0] += 1
                entry[1] += turn
                entry[2] += abs(turn)
            previous = (heading(foot), down)
    steps = sum(e[0] for e in split.values())
    print("the left foot's turn by corners down (all recordings, running steps):")
    for down in sorted(split):
        n, net, total = split[down]
        print(f"  {down} down: {100 * n / steps:5.1f} % of steps, net {net:+8.1f} deg, "
              f"|turn| {total:7.1f} deg")


if __name__ == "__main__":
    main()
