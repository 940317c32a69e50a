#!/usr/bin/python3
"""Summarizes `juggle eval --json` files made in parts (scripts/experiments/planner_eval.sh).

Reads the "episode" lines of every file given, refuses an episode that appears twice, and
prints the juggles distribution as `juggle eval` does (median, p10, p90 with the same linear
interpolation as eval/summary.cc), the endings, and the planner cost when the logs beside the
JSON files (same name, .log) carry `wall_s=` (wall time: core-seconds only while the parts had
a core each) and `planner_rollout_steps=` (control steps simulated by the planner's rollouts:
its budget, the same whatever else ran on the machine). Then the per-node table summed over
the parts (visits, completions, success, and the episodes each node ended by how).

  scripts/analysis/eval_parts.py runs/planner_eval60/ep_*.jsonl
"""
import json
import math
import os
import re
import sys


def percentile(values, q):
    """The interpolated percentile of eval/summary.cc (Percentile)."""
    if not values:
        return 0.0
    v = sorted(values)
    pos = min(max(q, 0.0), 1.0) * (len(v) - 1)
    lo = int(math.floor(pos))
    hi = min(lo + 1, len(v) - 1)
    return v[lo] + (pos - lo) * (v[hi] - v[lo])


def summarize(paths):
    """The episodes of `paths` and their planner cost: a dict with episodes (by number),
    juggles (list), seconds (simulated), wall (s), rollout_steps (0 when no log says) and nodes
    (name -> visits, completions, endings summed over the files' "node" lines)."""
    episodes = {}
    nodes = {}
    wall = 0.0
    rollout_steps = 0
    for path in paths:
        with open(path) as f:
            for number, line in enumerate(f, 1):
                record = json.loads(line)
                if record.get("table") == "node":
                    add_node(nodes, record)
                if record.get("table") != "episode":
                    continue
                if record["episode"] in episodes:
                    sys.exit(f"{path}:{number}: episode {record['episode']} appears twice")
                episodes[record["episode"]] = record
        log = re.sub(r"\.jsonl$", ".log", path)
        if os.path.exists(log):
            found = re.findall(r"wall_s=([0-9.]+)", open(log).read())
            wall += float(found[-1]) if found else 0.0
            steps = re.findall(r"planner_rollout_steps=([0-9]+)", open(log).read())
            rollout_steps += int(steps[-1]) if steps else 0
    if not episodes:
        sys.exit("no episode lines in " + " ".join(paths))
    return {"episodes": episodes,
            "juggles": [e["juggles"] for e in episodes.values()],
            "seconds": sum(e["seconds"] for e in episodes.values()),
            "wall": wall, "rollout_steps": rollout_steps, "nodes": nodes}


def add_node(nodes, record):
    """Adds one "node" line of `juggle eval --json` to the running sums in `nodes`."""
    n = nodes.setdefault(record["node"], {"visits": 0, "completions": 0, "endings": {}})
    n["visits"] += record["visits"]
    n["completions"] += record["completions"]
    for how, count in record.get("endings", {}).items():
        n["endings"][how] = n["endings"].get(how, 0) + count


def main(paths):
    s = summarize(paths)
    episodes, juggles, seconds = s["episodes"], s["juggles"], s["seconds"]
    wall, rollout_steps = s["wall"], s["rollout_steps"]
    endings = {}
    for e in episodes.values():
        endings[e["outcome"]] = endings.get(e["outcome"], 0) + 1
    print(f"episodes={len(juggles)} ({min(episodes)}..{max(episodes)}) "
          f"median_juggles={percentile(juggles, 0.5):g} p10_juggles={percentile(juggles, 0.1):g} "
          f"p90_juggles={percentile(juggles, 0.9):g} mean_juggles={sum(juggles) / len(juggles):.2f} "
          f"mean_episode_s={seconds / len(juggles):.2f} "
          + " ".join(f"{k}={v}" for k, v in sorted(endings.items()))
          + (f" wall_s={wall:.0f} core_s_per_sim_s={wall / seconds:.2f}" if wall > 0 else "")
          + (f" rollout_steps_per_sim_s={rollout_steps / seconds:.0f}" if rollout_steps > 0 else ""))
    print("juggles by episode: " + " ".join(f"{k}:{episodes[k]['juggles']}" for k in sorted(episodes)))
    for name, n in sorted(s["nodes"].items()):
        success = n["completions"] / n["visits"] if n["visits"] else 0.0
        print(f"node {name}: {n['completions']}/{n['visits']} success={success:.2f} "
              + " ".join(f"{k}={v}" for k, v in sorted(n["endings"].items())))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    if sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        sys.exit(0)
    main(sys.argv[1:])
