#!/usr/bin/env python3
"""The expert-iteration loop as training goes on (issue 48; docs/performance.md).

Reads a run's metrics.jsonl (learner/run_log.h) and prints one markdown row per window of
iterations: training minutes, labels, the planner's rollout control steps per label (its cost
per simulated control step), the rescue share, the share of re-plans that chose the learned
policy alone, the expert-driven episodes that ended and their juggles, rollout steps per
expert juggle, and the student's error on fresh labels; then the in-run evaluations of the
policy alone.

  scripts/analysis/expert_iteration_curve.py RUN_DIR [WINDOW_ITERATIONS]
"""
import json
import sys


def main():
    if len(sys.argv) < 2:
        print(__doc__.strip())
        return 2
    path = sys.argv[1].rstrip("/") + "/metrics.jsonl"
    window = int(sys.argv[2]) if len(sys.argv) > 2 else 50
    iterations, evaluations = [], []
    with open(path) as f:
        for line in f:
            r = json.loads(line)
            if "iteration" in r and r.get("event") is None and "samples_per_s" in r:
                iterations.append(r)
            elif r.get("event") == "eval":
                evaluations.append(r)
    print("| iterations | minutes | labels | rollout steps / label | rescues / re-plan | "
          "policy chosen / re-plan | expert episodes | juggles / episode | "
          "rollout steps / juggle | fresh error |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for start in range(0, len(iterations), window):
        w = iterations[start:start + window]
        g = lambda k: sum(r.get(k, 0) for r in w)
        labels, steps = g("expert_labels"), g("expert_rollout_steps")
        replans, tried = g("expert_replans"), g("expert_proposal_tried")
        episodes = g("expert_episodes")
        juggles = sum(r.get("expert_episodes", 0) * r.get("expert_juggles_per_episode", 0) for r in w)
        # The window's rollout steps over the juggles of the expert episodes that ended in it
        # (an episode's juggles count when it ends: use windows of several episodes).
        per_juggle = "%.0f" % (steps / juggles) if juggles > 0 else "—"
        fresh = [r["imitation_fresh_error"] for r in w if r.get("imitation_fresh_error", 0) > 0]
        print("| %d–%d | %.1f | %d | %.0f | %.3f | %s | %d | %s | %s | %s |" % (
            w[0]["iteration"], w[-1]["iteration"], w[-1]["train_s"] / 60, labels,
            steps / labels if labels else 0, g("expert_rescues") / replans if replans else 0,
            "%.3f" % (g("expert_proposal_chosen") / tried) if tried else "—", episodes,
            "%.1f" % (juggles / episodes) if episodes else "—", per_juggle,
            "%.4f" % (sum(fresh) / len(fresh)) if fresh else "—"))
    if evaluations:
        print()
        print("| after iteration | minutes | the policy alone: median | mean | episodes |")
        print("|---|---|---|---|---|")
        for e in evaluations:
            print("| %d | %.1f | %.1f | %.2f | %d |" % (e["iteration"], e["train_s"] / 60,
                                                     e["median_juggles"], e["mean_juggles"],
                                                     e["episodes"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
