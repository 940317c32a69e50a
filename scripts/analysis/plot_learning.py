#!/usr/bin/env python3
"""Juggles-vs-wall-clock curves of several soccer runs as one SVG (standard library only).

usage: scripts/analysis/plot_learning.py OUT.svg RUN_DIR [RUN_DIR ...] [--x samples]

Top panel: mean juggles of each run's in-run evaluations (the `"event": "eval"` lines of
RUN_DIR/metrics.jsonl: mean-action policy, held-out starts, no training curricula). Bottom
panel: juggles per training episode (exploration noise and training curricula on), moving
average over 20 iterations. The x axis is training wall-clock minutes (`train_s`), or samples
(millions) with `--x samples`. Runs are labelled PARENT/RUN (round folder and run folder).
"""
import json
import os
import sys

from svg_axes import axes

COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#17becf", "#7f7f7f"]


def read_run(path, x_key):
    evals, train = [], []
    summed_s = 0.0  # runs older than `train_s`: the iterations' own seconds, summed
    metrics = os.path.join(path, "metrics.jsonl")
    with open(metrics) as f:
        for number, line in enumerate(f, 1):
            d = json.loads(line)
            if d.get("event") not in (None, "eval"):
                continue  # run, walk and other records
            summed_s += d.get("iteration_s", 0.0)
            if x_key == "minutes" and d.get("event") is None and "train_s" not in d and "iteration_s" not in d:
                sys.exit(f"{metrics}:{number}: neither train_s nor iteration_s: no wall-clock axis")
            seconds = d.get("train_s", summed_s)
            x = seconds / 60 if x_key == "minutes" else d["samples"] / 1e6
            if d.get("event") == "eval":
                evals.append((x, d["mean_juggles"]))
            else:
                train.append((x, d.get("juggles_per_episode", 0.0)))
    return evals, train


def label(run_dir):
    """PARENT/RUN: the A/B round's folder and the run's."""
    path = os.path.normpath(os.path.abspath(run_dir))
    return "/".join(path.split(os.sep)[-2:])


def smooth(points, window=20):
    out, acc = [], 0.0
    for i, (x, y) in enumerate(points):
        acc += y
        if i >= window:
            acc -= points[i - window][1]
        out.append((x, acc / min(i + 1, window)))
    return out


def main(argv):
    x_key = "minutes"
    if "--x" in argv:
        i = argv.index("--x")
        x_key = argv[i + 1]
        argv = argv[:i] + argv[i + 2:]
    if len(argv) < 3 or x_key not in ("minutes", "samples"):
        sys.exit(__doc__)
    out, runs = argv[1], argv[2:]
    data = [(label(r), *read_run(r, x_key)) for r in runs]
    x_max = max([p[0] for _, e, t in data for p in e + t] + [1e-9])
    width, height = 820, 560
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}">',
           '<rect width="100%" height="100%" fill="white"/>']
    xlabel = "training wall-clock (min)" if x_key == "minutes" else "samples (millions)"
    panels = [(40, "mean juggles, in-run evaluation (held-out starts)", 1, False),
              (310, "juggles per training episode (moving average)", 2, True)]
    for top, title, index, smoothed in panels:
        series = [smooth(d[index]) if smoothed else d[index] for d in data]
        hi = max([y for s in series for _, y in s] + [1.0])
        parts, px, py = axes(70, width - 230, top, 200, x_max, 0.0, hi, title)
        svg += parts
        for k, (s, (name, _, _)) in enumerate(zip(series, data)):
            colour = COLOURS[k % len(COLOURS)]
            pts = " ".join(f"{px(x):.1f},{py(y):.1f}" for x, y in s)
            svg.append(f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-width="2"/>')
            if not smoothed:
                svg += [f'<circle cx="{px(x):.1f}" cy="{py(y):.1f}" r="3" fill="{colour}"/>' for x, y in s]
            svg.append(f'<text x="{width - 220}" y="{top + 14 + 16 * k}" font-size="12" '
                       f'font-family="sans-serif" fill="{colour}">{name}</text>')
        svg.append(f'<text x="{(70 + width - 230) / 2}" y="{top + 225}" font-size="12" '
                   f'text-anchor="middle" font-family="sans-serif">{xlabel} (max {x_max:.1f})</text>')
    svg.append("</svg>")
    with open(out, "w") as f:
        f.write("\n".join(svg) + "\n")


if __name__ == "__main__":
    main(sys.argv)
