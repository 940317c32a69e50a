#!/usr/bin/python3
"""Juggles against the planner's cost, one point per setting, as one SVG (standard library only).

Each setting is a folder of `juggle eval --json` parts (scripts/experiments/planner_budget.sh
writes one per setting); every setting must hold the same episodes, so the points compare the
same starts. x: the planner's rollout control steps per simulated second (its budget, the same
whatever else ran) on a log scale; the top axis converts it to wall seconds per simulated
second on 2 cores at STEPS_PER_WALL_S rollout steps per wall second (measured alone, e.g.
`juggle bench planner`). y: mean juggles per episode, with the median as a hollow mark. A
dashed line marks real time (1.0 wall-s per simulated second).

  scripts/analysis/plot_realtime_curve.py [--starts=N] OUT.svg STEPS_PER_WALL_S TITLE LABEL=DIR ...

A setting may also be LABEL=@STEPS,MEAN,MEDIAN: a point taken from a recorded table row
(docs/performance.md) whose run folder is gone; it is taken to hold the same starts. Either form
may end in ~COST: its rollout step costs COST reference steps (e.g. ~0.53 for the 200-Hz world,
whose step simulates half the physics), so the point sits at STEPS × COST. --starts=N: how many
starts the points hold, for the plot's footnote; needed when every point is recorded, and when
a folder is given it must hold that many.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from eval_parts import percentile, summarize  # noqa: E402
from svg_axes import write_svg  # noqa: E402


def load(label, folder):
    parts = sorted(os.path.join(folder, f) for f in os.listdir(folder) if f.endswith(".jsonl"))
    s = summarize(parts)
    if s["rollout_steps"] == 0:
        sys.exit(f"{folder}: no planner_rollout_steps= in the logs beside its JSON parts")
    return {"label": label, "episodes": sorted(s["episodes"]),
            "steps": s["rollout_steps"] / s["seconds"],
            "mean": sum(s["juggles"]) / len(s["juggles"]),
            "median": percentile(s["juggles"], 0.5)}


def recorded(label, numbers):
    try:
        steps, mean, median = (float(v) for v in numbers.split(","))
    except ValueError:
        sys.exit(f"{label}=@{numbers}: a recorded point is @STEPS,MEAN,MEDIAN")
    return {"label": label, "episodes": None, "steps": steps, "mean": mean, "median": median}


def point(setting):
    label, source = setting.split("=", 1)
    source, _, cost = source.partition("~")
    p = recorded(label, source[1:]) if source.startswith("@") else load(label, source)
    p["cost"] = 1.0
    if cost:
        try:
            p["cost"] = float(cost)
        except ValueError:
            sys.exit(f"{setting}: ~COST must be a number")
        p["raw_steps"] = p["steps"]
        p["steps"] *= p["cost"]
    return p


def main(out, steps_per_wall_s, title, settings, starts):
    points = [point(setting) for setting in settings]
    folders = [p for p in points if p["episodes"] is not None]
    for p in folders[1:]:
        if p["episodes"] != folders[0]["episodes"]:
            sys.exit(f"{p['label']} holds episodes {p['episodes']}, {folders[0]['label']} "
                     f"{folders[0]['episodes']}: the points must share their starts")
    if folders:
        if starts is not None and starts != len(folders[0]["episodes"]):
            sys.exit(f"--starts={starts}, but {folders[0]['label']} holds "
                     f"{len(folders[0]['episodes'])} episodes")
        starts = len(folders[0]["episodes"])
    elif starts is None:
        sys.exit("every point is recorded (@STEPS,MEAN,MEDIAN): say how many starts they hold "
                 "with --starts=N")
    left, right, top, height = 70, 620, 60, 300
    lo_x = math.log10(min(min(p["steps"] for p in points), steps_per_wall_s) / 1.5)
    hi_x = math.log10(max(p["steps"] for p in points) * 1.5)
    y_hi = max(max(p["mean"], p["median"]) for p in points) * 1.15 or 1

    def px(steps):
        return left + (right - left) * (math.log10(steps) - lo_x) / (hi_x - lo_x)

    def py(v):
        return top + height - height * v / y_hi

    # Wide enough for the longest legend line (about 6 px per character at 11 px), at least 860.
    legend = max(len(f"{i}: {p['label']}") for i, p in enumerate(points, 1))
    width = max(860, right + 14 + 6 * legend + 10)
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="420">',
           '<rect width="100%" height="100%" fill="white"/>',
           f'<rect x="{left}" y="{top}" width="{right - left}" height="{height}" fill="none" '
           f'stroke="#999"/>',
           f'<text x="{left}" y="{top - 30}" font-size="13" font-family="sans-serif">{title}</text>',
           f'<text x="{left}" y="{top - 14}" font-size="11" font-family="sans-serif" fill="#555">'
           f'top: wall-s per simulated s on 2 cores at {steps_per_wall_s:,.0f} rollout steps '
           f'per wall-s</text>']
    for frac in (0, 0.5, 1):
        v = y_hi * frac
        svg.append(f'<text x="{left - 6}" y="{py(v) + 4:.1f}" font-size="11" text-anchor="end" '
                   f'font-family="sans-serif">{v:.0f}</text>')
    x_labels = []
    for decade in range(int(math.floor(lo_x)), int(math.ceil(hi_x)) + 1):
        for m in (1, 2, 5):
            steps = m * 10 ** decade
            if lo_x <= math.log10(steps) <= hi_x:
                x = px(steps)
                svg.append(f'<line x1="{x:.1f}" y1="{top + height}" x2="{x:.1f}" '
                           f'y2="{top + height + 4}" stroke="#999"/>')
                svg.append(f'<text x="{x:.1f}" y="{top - 2}" font-size="10" text-anchor="middle" '
                           f'font-family="sans-serif" fill="#555">{steps / steps_per_wall_s:.2g}'
                           f'</text>')
                x_labels.append((x, f"{steps:,.0f}"))
    rt = px(steps_per_wall_s)
    svg.append(f'<line x1="{rt:.1f}" y1="{top}" x2="{rt:.1f}" y2="{top + height}" '
               f'stroke="#c33" stroke-dasharray="5,4"/>')
    svg.append(f'<text x="{rt + 4:.1f}" y="{top + 14}" font-size="11" fill="#c33" '
               f'font-family="sans-serif">real time</text>')
    # Each point carries its number; the legend beside the panel names it.
    for i, p in enumerate(points, 1):
        x = px(p["steps"])
        svg.append(f'<circle cx="{x:.1f}" cy="{py(p["mean"]):.1f}" r="4" fill="#26a"/>')
        svg.append(f'<circle cx="{x:.1f}" cy="{py(p["median"]):.1f}" r="4" fill="none" '
                   f'stroke="#26a"/>')
        svg.append(f'<text x="{x + (6 if i % 2 else -6):.1f}" y="{py(p["mean"]) + 4:.1f}" '
                   f'font-size="10" text-anchor="{"start" if i % 2 else "end"}" '
                   f'font-family="sans-serif">{i}</text>')
        svg.append(f'<text x="{right + 14}" y="{top + 10 + 14 * (i - 1)}" font-size="11" '
                   f'font-family="sans-serif">{i}: {p["label"]}</text>')
    svg.append(f'<text x="{(left + right) / 2}" y="{top + height + 36}" font-size="11" '
               f'text-anchor="middle" font-family="sans-serif">rollout control steps per '
               f'simulated s (log); filled: mean juggles, hollow: median; '
               f'{starts} starts</text>')
    write_svg(out, svg, x_labels, top + height + 16)
    for p in points:
        cost = (f"(its own {p['raw_steps']:.0f} at step cost {p['cost']:g}) "
                if "raw_steps" in p else "")
        print(f"{p['label']}: rollout_steps_per_sim_s={p['steps']:.0f} {cost}"
              f"wall_s_per_sim_s_2cores={p['steps'] / steps_per_wall_s:.2f} "
              f"mean={p['mean']:.2f} median={p['median']:g}")


if __name__ == "__main__":
    args = sys.argv[1:]
    starts = None
    if args and args[0].startswith("--starts="):
        try:
            starts = int(args.pop(0).split("=", 1)[1])
        except ValueError:
            sys.exit("--starts=N takes a whole number")
    if len(args) < 4:
        sys.exit(__doc__)
    main(args[0], float(args[1]), args[2], args[3:], starts=starts)
