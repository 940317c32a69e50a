#!/usr/bin/python3
"""Searches the right foot's base swing for zero-action juggles (docs/learning.md, round 7 and
"A passively stable swing").

A cross-entropy method over the six `leg_swing` parameters of a control graph
(configs/graphs/right_foot_smooth.textproto by default, both nodes alike) and the two kick
feedback gains of a run config. Every candidate is evaluated by `juggle eval --zero-action` on
the same search starts (seeds 5000+, not the held-out 1000000+); its score is the mean juggles
less `--band-weight` times the share of executed kicks whose foot acceleration at impact lies
outside the stable band (`impact_in_band`, docs/planner.md "Impact acceleration"). With
`--objective=kicks` the mean juggles are replaced by the kick quality per episode: for every
kick, its ball's free flight from just after the release (ballistic, from the recording) is
carried down to the contact height and scored exp(-((t/0.06)² + (dx/tol)² + (dy/tol)²)/2): t
the crossing's time from the nominal contact (the ±60 ms window), dx, dy from the next kick's
ball target, tol `--kick-tolerance` (heights and target from the graph's first node). A kick sent far too high completes a juggle and then
loses the ball; it games the juggle count but not this. Each
generation's new mean is half the old plus half the mean of its best `--elite`; the spread
follows the elite's, never below a floor. Deterministic for --seed.

Writes OUT/search.tsv (every candidate), OUT/best_graph.textproto, OUT/best_config.textproto
(the best mean's graph and gains) and a progress line per generation.

  scripts/experiments/swing_search.py OUT [--generations=14 --population=16 --episodes=50
      --seconds=20 --band-weight=0 --config=... --graph=... --juggle=build/release/juggle]
"""
import argparse
import importlib.util
import math
import os
import random
import re
import statistics
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
_spec = importlib.util.spec_from_file_location(
    "kick_stats", os.path.join(REPO, "scripts/analysis/kick_stats.py"))
kick_stats = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(kick_stats)

# Name, where it lives (swing: leg_swing field; feedback: kick_feedback field), initial spread.
PARAMETERS = [
    ("hip_amplitude", "swing", 0.15),
    ("knee_amplitude", "swing", 0.10),
    ("ankle_amplitude", "swing", 0.08),
    ("stance_roll", "swing", 0.03),
    ("phase_lead", "swing", 0.03),
    ("hip_abduction", "swing", 0.03),
    ("hip_per_m", "feedback", 0.5),
    ("abduction_per_m", "feedback", 0.5),
]
# The smallest spread, as a fraction of the initial one: keeps the search from collapsing on
# the noise of one generation's starts.
SPREAD_FLOOR = 0.1


def read_swing(graph_text):
    """The first leg_swing block's numeric fields."""
    block = re.search(r"leg_swing\s*\{(.*?)\}", graph_text, re.S)
    if not block:
        sys.exit("swing_search: the graph has no leg_swing block")
    return {k: float(v) for k, v in re.findall(r"(\w+):\s*(-?[0-9.eE+-]+)", block.group(1))}


def write_graph(graph_text, values, profile=""):
    """`graph_text` with every leg_swing block's swing fields set to `values` (and its profile
    to `profile` when given)."""
    def one_block(match):
        body = match.group(1)
        if profile:
            if re.search(r"\bprofile:", body):
                body = re.sub(r"\bprofile:\s*\w+", "profile: " + profile, body)
            else:
                body = body.rstrip() + "\n      profile: " + profile + "\n    "
        for name, where, _ in PARAMETERS:
            if where != "swing":
                continue
            line = "%s: %.5f" % (name, values[name])
            if re.search(r"\b%s:" % name, body):
                body = re.sub(r"\b%s:\s*-?[0-9.eE+-]+" % name, line, body)
            else:
                body = body.rstrip() + "\n      " + line + "\n    "
        return "leg_swing {" + body + "}"
    return re.sub(r"leg_swing\s*\{(.*?)\}", one_block, graph_text, flags=re.S)


def write_config(path, base_config, graph_path, values, name):
    with open(path, "w") as f:
        f.write('# proto-file: %s/proto/run_config.proto\n' % REPO)
        f.write("# proto-message: juggle.config.RunConfig\n")
        f.write("# Written by scripts/experiments/swing_search.py.\n")
        f.write('base_config: "%s"\nname: "%s"\n' % (base_config, name))
        f.write('soccer_juggle {\n  graph_file: "%s"\n' % graph_path)
        f.write("  env { kick_feedback { hip_per_m: %.5f abduction_per_m: %.5f } }\n}\n"
                % (values["hip_per_m"], values["abduction_per_m"]))


GRAVITY = 9.81


def read_geometry(graph_text):
    """The first node's contact height, apex height and ball target (x, y), with the schema's
    defaults (proto/control_graph.proto) where the node leaves them out."""
    node = re.search(r"node\s*\{(.*?)\n\}", graph_text, re.S)
    body = node.group(1) if node else ""
    def number(pattern, default):
        found = re.search(pattern, body, re.S)
        return float(found.group(1)) if found else default
    target = re.search(r"ball_target\s*\{([^}]*)\}", body)
    target = target.group(1) if target else ""
    def coordinate(name, default):
        found = re.search(r"\b%s:\s*(-?[0-9.eE+-]+)" % name, target)
        return float(found.group(1)) if found else default
    return (number(r"\bapex_height:\s*(-?[0-9.eE+-]+)", 1.4),
            number(r"\bcontact_height:\s*(-?[0-9.eE+-]+)", 0.5),
            coordinate("x", 0.6), coordinate("y", 0.0))


def kick_quality(args, trajectory):
    """The summed quality of every kick (see the module doc) per episode, against the graph's
    first node's heights and ball target (args.geometry)."""
    APEX, CONTACT, TARGET_X, TARGET_Y = args.geometry
    channels, records, header = kick_stats.load(trajectory)
    dt, nq = float(header["control_dt"]), int(header["nq"])
    c, q0, ball = kick_stats.columns(channels, nq)
    cycle = 2 * math.sqrt(2 * (APEX - CONTACT) / GRAVITY)
    total = 0.0
    for rows, z, contacts in kick_stats.episode_contacts(channels, records, nq, CONTACT):
        for i in contacts:
            a, b = i + 2, i + 3  # two samples of the free flight after the release
            if b >= len(rows) or z[b] <= z[a]:
                continue
            v = [(rows[b][ball + k] - rows[a][ball + k]) / dt for k in range(3)]
            v[2] -= 0.5 * GRAVITY * dt  # the velocity at sample b
            reach = v[2] ** 2 + 2 * GRAVITY * (z[b] - CONTACT)
            if reach < 0:
                continue  # released below the contact height, never rises to it
            t = (v[2] + math.sqrt(reach)) / GRAVITY
            dx = rows[b][ball] + v[0] * t - rows[b][q0] - TARGET_X
            dy = rows[b][ball + 1] + v[1] * t - rows[b][q0 + 1] - TARGET_Y
            phase = rows[b][c["phase"]] + t / cycle
            timing = ((phase - 0.5 + 0.5) % 1.0 - 0.5) * cycle
            tol = args.kick_tolerance
            total += math.exp(-0.5 * ((timing / 0.06) ** 2 + (dx / tol) ** 2 + (dy / tol) ** 2))
    return total / args.episodes


def evaluate(args, config_path):
    """The eval line's key=value pairs as floats (strings where not numeric); with
    --objective=kicks also kick_quality."""
    command = [args.juggle, "eval", "--zero-action", "--config=" + config_path,
               "--episodes=%d" % args.episodes, "--max_seconds=%g" % args.seconds,
               "--seed=%d" % args.eval_seed]
    trajectory = config_path + ".traj"
    if args.objective == "kicks":
        command.append("--record=" + trajectory)
    run = subprocess.run(command, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit("swing_search: %s failed:\n%s" % (" ".join(command), run.stderr))
    last = run.stdout.strip().splitlines()[-1]
    out = {}
    for pair in last.split():
        key, _, value = pair.partition("=")
        try:
            out[key] = float(value)
        except ValueError:
            out[key] = value
    if args.objective == "kicks":
        out["kick_quality"] = kick_quality(args, trajectory)
        os.remove(trajectory)
    return out


def score_of(args, result):
    outside = 1.0 - result.get("impact_in_band", 0.0) if result.get("impact_kicks", 0) else 1.0
    primary = result["kick_quality"] if args.objective == "kicks" else result["mean_juggles"]
    return primary - args.band_weight * outside


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("out")
    p.add_argument("--config", default=os.path.join(REPO, "configs/learning/kick_smooth_lowstd.textproto"))
    p.add_argument("--graph", default=os.path.join(REPO, "configs/graphs/right_foot_smooth.textproto"))
    p.add_argument("--juggle", default=os.path.join(REPO, "build/release/juggle"))
    p.add_argument("--generations", type=int, default=14)
    p.add_argument("--population", type=int, default=16)
    p.add_argument("--elite", type=int, default=4)
    p.add_argument("--episodes", type=int, default=50)
    p.add_argument("--seconds", type=float, default=20)
    p.add_argument("--eval-seed", type=int, default=5000)
    p.add_argument("--band-weight", type=float, default=0.0,
                   help="score = mean juggles - band_weight * share of kicks outside the band")
    p.add_argument("--objective", choices=["juggles", "kicks"], default="juggles",
                   help="what the score counts: mean juggles, or kick quality per episode")
    p.add_argument("--kick-tolerance", type=float, default=0.2,
                   help="--objective=kicks: the landing error scale (m) of the kick quality")
    p.add_argument("--profile", default="",
                   help="the swing profile for every candidate (SINE, RAISED_COSINE, FLAT_TOP; "
                        "default: the graph's)")
    p.add_argument("--spread-scale", type=float, default=1.0,
                   help="multiplies every initial spread")
    p.add_argument("--start", default="",
                   help="name=value,... overriding the start point (e.g. phase_lead=0.08)")
    p.add_argument("--seed", type=int, default=1)
    args = p.parse_args()

    os.makedirs(args.out, exist_ok=True)
    args.config = os.path.abspath(args.config)
    with open(args.graph) as f:
        graph_text = f.read()
    swing = read_swing(graph_text)
    args.geometry = read_geometry(graph_text)
    feedback = {"hip_per_m": 0.0, "abduction_per_m": 0.0}
    with open(args.config) as f:  # the gains, when the config names them itself
        for k, v in re.findall(r"(hip_per_m|abduction_per_m):\s*(-?[0-9.eE+-]+)", f.read()):
            feedback[k] = float(v)
    mean = {name: (swing.get(name, 0.0) if where == "swing" else feedback[name])
            for name, where, _ in PARAMETERS}
    for pair in filter(None, args.start.split(",")):
        name, _, value = pair.partition("=")
        if name not in mean:
            sys.exit("swing_search: --start names unknown parameter %r" % name)
        mean[name] = float(value)
    spread = {name: s * args.spread_scale for name, _, s in PARAMETERS}
    rng = random.Random(args.seed)
    names = [name for name, _, _ in PARAMETERS]

    table = open(os.path.join(args.out, "search.tsv"), "w")
    table.write("\t".join(["generation", "candidate", "score", "mean_juggles", "kick_quality", "impact_median",
                           "impact_in_band", "impact_kicks"] + names) + "\n")
    work = os.path.join(args.out, "candidates")
    os.makedirs(work, exist_ok=True)

    def run_candidate(generation, index, values):
        graph_path = os.path.join(work, "graph_%d_%d.textproto" % (generation, index))
        config_path = os.path.join(work, "config_%d_%d.textproto" % (generation, index))
        with open(graph_path, "w") as f:
            f.write(write_graph(graph_text, values, args.profile))
        write_config(config_path, args.config, graph_path, values, "swing_%d_%d" % (generation, index))
        result = evaluate(args, config_path)
        score = score_of(args, result)
        table.write("\t".join(str(x) for x in [generation, index, "%.4f" % score,
                                                result["mean_juggles"], result.get("kick_quality", "nan"),
                                                result.get("impact_median", "nan"),
                                                result.get("impact_in_band", "nan"),
                                                int(result.get("impact_kicks", 0))]
                              + ["%.5f" % values[n] for n in names]) + "\n")
        table.flush()
        os.remove(graph_path)
        os.remove(config_path)
        return score, result

    started = time.time()
    score, result = run_candidate(0, 0, mean)
    print("start: score %.3f, mean juggles %.3f, kick quality %s, impact median %s, in band %s" % (
        score, result["mean_juggles"], result.get("kick_quality"), result.get("impact_median"),
        result.get("impact_in_band")), flush=True)
    for generation in range(1, args.generations + 1):
        scored = []
        for index in range(args.population):
            values = {n: rng.gauss(mean[n], spread[n]) for n in names}
            values["hip_abduction"] = max(values["hip_abduction"], 0.0)
            scored.append((run_candidate(generation, index, values)[0], index, values))
        scored.sort(key=lambda x: -x[0])
        elite = [v for _, _, v in scored[:args.elite]]
        for n, _, s0 in PARAMETERS:
            elite_mean = statistics.fmean(v[n] for v in elite)
            elite_sd = statistics.pstdev(v[n] for v in elite)
            mean[n] = 0.5 * mean[n] + 0.5 * elite_mean
            spread[n] = max(0.5 * spread[n] + 0.5 * elite_sd, SPREAD_FLOOR * s0 * args.spread_scale)
        score, result = run_candidate(generation, args.population, mean)
        print("generation %d (%.0f s): best candidate %.3f; mean's score %.3f, mean juggles %.3f, "
              "kick quality %s, impact median %s, in band %s" % (
                  generation, time.time() - started, scored[0][0], score, result["mean_juggles"],
                  result.get("kick_quality"), result.get("impact_median"),
                  result.get("impact_in_band")), flush=True)
    with open(os.path.join(args.out, "best_graph.textproto"), "w") as f:
        f.write(write_graph(graph_text, mean, args.profile))
    write_config(os.path.join(args.out, "best_config.textproto"), args.config,
                 os.path.join(os.path.abspath(args.out), "best_graph.textproto"), mean, "swing_best")
    print("final mean: " + " ".join("%s=%.5f" % (n, mean[n]) for n in names))


if __name__ == "__main__":
    main()
