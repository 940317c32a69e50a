#!/usr/bin/env python3
"""Plots a run's metrics.jsonl as an SVG learning curve (standard library only).

usage: scripts/analysis/plot_metrics.py RUN_DIR/metrics.jsonl OUT.svg [--title TEXT]

Three panels over wall-clock minutes: completions per episode, mean episode length (s),
mean episode return. Each panel shows the raw per-iteration values and a moving average.
"""
import json
import sys

from svg_axes import axes, moving_average, write_svg


def panel(x, y, top, height, width, title, colour):
    parts, px, py = axes(70, width - 20, top, height, max(x), min(y), max(y), title)
    raw = " ".join(f"{px(a):.1f},{py(b):.1f}" for a, b in zip(x, y))
    smooth = " ".join(f"{px(a):.1f},{py(b):.1f}" for a, b in zip(x, moving_average(y, 20)))
    parts.append(f'<polyline points="{raw}" fill="none" stroke="{colour}" stroke-opacity="0.3"/>')
    parts.append(f'<polyline points="{smooth}" fill="none" stroke="{colour}" stroke-width="2"/>')
    return parts, px


def main(argv):
    if len(argv) < 3:
        print(__doc__)
        return 2
    title = argv[argv.index("--title") + 1] if "--title" in argv else argv[1]
    rows = [json.loads(line) for line in open(argv[1]) if line.strip()]
    rows = [r for r in rows if "event" not in r]  # iterations only (not eval/run/walk records)
    if not rows:
        print("no rows in", argv[1])
        return 1
    minutes, total = [], 0.0
    for r in rows:
        total += r.get("iteration_s", 0.0)
        minutes.append(total / 60)
    dt = 0.02
    width, height = 760, 620
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}">',
           '<rect width="100%" height="100%" fill="white"/>',
           f'<text x="{width/2}" y="22" font-size="15" text-anchor="middle" '
           f'font-family="sans-serif">{title}</text>']
    specs = [("completions_per_episode", "node completions per episode", "#1f77b4", 1.0),
             ("mean_episode_len", "mean episode length (s)", "#2ca02c", dt),
             ("mean_return", "mean episode return", "#d62728", 1.0)]
    px = None
    for i, (key, label, colour, scale) in enumerate(specs):
        y = [r.get(key, 0.0) * scale for r in rows]
        parts, px = panel(minutes, y, 50 + i * 185, 140, width, label, colour)
        svg += parts
    xmax = max(minutes)
    write_svg(argv[2], svg, [(px(xmax * f), f"{xmax*f:.0f} min") for f in (0, 0.25, 0.5, 0.75, 1)],
              height - 12)
    print(f"wrote {argv[2]} ({len(rows)} iterations, {xmax:.1f} min)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
