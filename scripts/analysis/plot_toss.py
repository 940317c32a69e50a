#!/usr/bin/env python3
"""Plots a `juggle toss --record` trajectory as an SVG (standard library only).

usage: scripts/analysis/plot_toss.py RUN.traj OUT.svg [--seconds S] [--title TEXT]

Two panels over the first S seconds (default 3): every ball's height and horizontal position
(one colour per ball; thin while held, thick in flight) with both palms in grey. Crossing
throws (odd values) show as balls moving between the hands' x; a drop as a ball falling
below the palms.
"""
import argparse
import sys

from svg_axes import axes
from trajectory import read_trajectory

COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2"]


def read(path, seconds):
    try:
        _, channels, rows = read_trajectory(path)
    except (OSError, ValueError) as e:
        sys.exit(f"error: {e}")
    rows = [r for r in rows if r["time"] <= seconds + 1e-9]
    if not rows:
        sys.exit(f"error: {path} has no rows within {seconds} s")
    balls = sum(1 for name, _ in channels if name.startswith("ball") and name.endswith("_mode"))
    # Ball modes as the runtime numbers them: 0 parked, 1 free (in flight), 2 held.
    for r in rows:
        for b in range(balls):
            r[f"ball{b}_mode"] = str(int(r[f"ball{b}_mode"]))
    return rows, balls


def panel(rows, balls, key, top, height, width, title, lo, hi):
    left, right = 60, width - 20
    t_max = float(rows[-1]["time"])
    out, px, py = axes(left, right, top, height, t_max, lo, hi, title)
    t = 0.0
    while t <= t_max + 1e-9:
        out.append(f'<text x="{px(t):.1f}" y="{top+height+14}" font-size="11" text-anchor="middle" '
                   f'font-family="sans-serif">{t:.1f}</text>')
        t += 0.5
    for palm in ("right_palm", "left_palm"):
        pts = " ".join(f"{px(float(r['time'])):.1f},{py(float(r[f'{palm}_{key}'])):.1f}" for r in rows)
        out.append(f'<polyline points="{pts}" fill="none" stroke="#bbb" stroke-width="6" '
                   f'stroke-linejoin="round"/>')
    for b in range(balls):
        colour = COLOURS[b % len(COLOURS)]
        segment, mode = [], None
        for r in rows + [None]:
            m = None if r is None else r[f"ball{b}_mode"]
            if segment and (m != mode):
                width_px = 2.5 if mode == "1" else 1.0
                if mode != "0":
                    out.append(f'<polyline points="{" ".join(segment)}" fill="none" stroke="{colour}" '
                               f'stroke-width="{width_px}"/>')
                segment = segment[-1:] if r is not None else []
            if r is None:
                break
            mode = m
            segment.append(f"{px(float(r['time'])):.1f},{py(float(r[f'ball{b}_{key}'])):.1f}")
    return out


def main():
    parser = argparse.ArgumentParser(description="Plots a `juggle toss --record` CSV as an SVG.")
    parser.add_argument("csv")
    parser.add_argument("svg")
    parser.add_argument("--seconds", type=float, default=3.0)
    parser.add_argument("--title", default="juggle toss")
    a = parser.parse_args()
    rows, balls = read(a.csv, a.seconds)
    width, height = 900, 560
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}">',
             '<rect width="100%" height="100%" fill="white"/>',
             f'<text x="{width/2}" y="22" font-size="15" text-anchor="middle" '
             f'font-family="sans-serif">{a.title}</text>']
    z_max = max(float(r[f"ball{b}_z"]) for r in rows for b in range(balls) if r[f"ball{b}_mode"] != "0")
    parts += panel(rows, balls, "z", 50, 280, width,
                   "height z (m): balls (thick in flight), palms (grey)", 0.5, z_max + 0.05)
    parts += panel(rows, balls, "x", 380, 140, width, "x (m, + = juggler's left) over time (s)",
                   -0.35, 0.35)
    parts.append("</svg>")
    with open(a.svg, "w") as f:
        f.write("\n".join(parts) + "\n")
    print(f"wrote {a.svg}: {balls} balls, {len(rows)} frames")


if __name__ == "__main__":
    main()
