#!/usr/bin/env python3
"""Plots the ablation study's learning curves as one SVG (standard library only).

usage: scripts/analysis/plot_ablation.py OUT_DIR OUT.svg [--x samples|minutes] [--eval median|mean]

Reads OUT_DIR/<config>_s<seed>/metrics.jsonl (scripts/experiments/ablation.sh's and
ab_learning.sh's runs). Panels over training samples (or training wall-clock minutes,
`train_s`, with --x minutes): juggles per episode and node completions per episode (training
episodes, moving average over 20 iterations), and the in-run evaluation's median juggles (or
mean juggles with --eval mean). Each config is one colour: the mean over its seeds as a line,
the range over seeds as a band, over the points all its seeds reached.
"""
import bisect
import glob
import json
import os
import re
import sys

from svg_axes import axes, moving_average, write_svg

COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"]


def load_runs(out_dir, x_key="samples", eval_key="median_juggles"):
    """{config: [(iterations, evaluations), ...] per seed}: iterations as (x, juggles,
    completions), evaluations as (x, eval_key's value); x is samples or train_s minutes."""
    runs = {}
    for path in sorted(glob.glob(os.path.join(out_dir, "*_s*", "metrics.jsonl"))):
        match = re.match(r"(.+)_s(\d+)$", os.path.basename(os.path.dirname(path)))
        if not match:
            continue
        it, ev = [], []
        for line in open(path):
            if not line.strip():
                continue
            row = json.loads(line)
            if row.get("event") not in (None, "eval"):
                continue
            if x_key == "minutes" and "train_s" not in row:
                sys.exit(f"{path}: a record without train_s: no wall-clock axis")
            x = row["train_s"] / 60 if x_key == "minutes" else row["samples"]
            if row.get("event") == "eval":
                ev.append((x, row[eval_key]))
            else:
                it.append((x, row.get("juggles_per_episode", 0.0),
                           row.get("completions_per_episode", 0.0)))
        if it:
            runs.setdefault(match.group(1), []).append((it, ev))
    return runs


def mean_curve(series):
    """Mean and range over seeds at the points of the seed that got least far: [(x, mean, lo,
    hi)]; every other seed contributes its last point at or before each x (runs of the same
    samples per iteration line up exactly; runs of different speeds on a minutes axis do not)."""
    grid = min(series, key=lambda s: s[-1][0])
    xs = [[p[0] for p in s] for s in series]
    out = []
    for x, _ in grid:
        ys = [s[max(bisect.bisect_right(sx, x) - 1, 0)][1] for s, sx in zip(series, xs)]
        out.append((x, sum(ys) / len(ys), min(ys), max(ys)))
    return out


def option(argv, name, choices, default):
    """The value of `name VALUE` in argv (removed from it), one of choices."""
    if name not in argv:
        return default
    i = argv.index(name)
    if i + 1 >= len(argv) or argv[i + 1] not in choices:
        sys.exit(f"{name} takes one of {', '.join(choices)}")
    value = argv[i + 1]
    del argv[i:i + 2]
    return value


def main(argv):
    argv = list(argv)
    x_key = option(argv, "--x", ("samples", "minutes"), "samples")
    eval_stat = option(argv, "--eval", ("median", "mean"), "median")
    if len(argv) != 3:
        print(__doc__)
        return 2
    runs = load_runs(argv[1], x_key, eval_stat + "_juggles")
    if not runs:
        print("no runs with metrics.jsonl in", argv[1])
        return 1
    width, height = 780, 680
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}">',
           '<rect width="100%" height="100%" fill="white"/>',
           f'<text x="{width/2}" y="22" font-size="15" text-anchor="middle" '
           f'font-family="sans-serif">Ablations: {os.path.basename(os.path.normpath(argv[1]))}'
           '</text>']
    panels = [("juggles per episode (training)", lambda it, ev: [(s, j) for s, j, _ in it], 20),
              ("node completions per episode (training)",
               lambda it, ev: [(s, c) for s, _, c in it], 20),
              (f"{eval_stat} juggles (in-run evaluation)", lambda it, ev: ev, 1)]
    curves = {}
    for title, pick, window in panels:
        for config, seeds in runs.items():
            series = []
            for it, ev in seeds:
                points = pick(it, ev)
                if not points:
                    continue
                smooth = moving_average([y for _, y in points], window)
                series.append([(x, y) for (x, _), y in zip(points, smooth)])
            if series:
                curves[(title, config)] = mean_curve(series)
    x_max = max((c[-1][0] for c in curves.values() if c), default=1)
    for p, (title, _, window) in enumerate(panels):
        values = [v for (t, _), c in curves.items() if t == title for point in c for v in point[1:]]
        lo, hi = (min(values), max(values)) if values else (0, 1)
        top = 60 + p * 190
        parts, px, py = axes(70, width - 170, top, 140, x_max, lo, hi, title)
        svg += parts
        for k, config in enumerate(sorted(runs)):
            c = curves.get((title, config))
            if not c:
                continue
            colour = COLOURS[k % len(COLOURS)]
            band = [f"{px(x):.1f},{py(h):.1f}" for x, _, _, h in c]
            band += [f"{px(x):.1f},{py(l):.1f}" for x, _, l, _ in reversed(c)]
            svg.append(f'<polygon points="{" ".join(band)}" fill="{colour}" fill-opacity="0.15"/>')
            line = " ".join(f"{px(x):.1f},{py(m):.1f}" for x, m, _, _ in c)
            svg.append(f'<polyline points="{line}" fill="none" stroke="{colour}" stroke-width="2"/>')
            if window == 1:  # evaluations are sparse: mark each one
                svg += [f'<circle cx="{px(x):.1f}" cy="{py(m):.1f}" r="3" fill="{colour}"/>'
                        for x, m, _, _ in c]
            if p == 0:
                svg.append(f'<text x="{width-160}" y="{top+16+16*k}" font-size="12" fill="{colour}" '
                           f'font-family="sans-serif">{config} ({len(runs[config])} seeds)</text>')
    label = ((lambda f: f"{x_max*f:.0f} minutes") if x_key == "minutes"
             else (lambda f: f"{x_max*f/1e6:.2f} M samples"))
    write_svg(argv[2], svg, [(70 + (width - 240) * f, label(f)) for f in (0, 0.5, 1)],
              height - 14)
    print(f"wrote {argv[2]} ({len(runs)} configs, {sum(len(s) for s in runs.values())} runs)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
