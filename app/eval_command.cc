// `juggle eval`: runs a trained policy without exploration noise (the mean action), or the
// zero-action baseline, for a set of seeded episodes side by side, and reports the juggles
// distribution and how episodes ended, the per-node table, optionally the force sweep
// (eval/tables.h) and JSON lines. The last line is key=value pairs (eval/summary.h).
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "app/commands.h"
#include "app/controller_factory.h"
#include "app/planner_flags.h"
#include "app/policy_source.h"
#include "common/file_io.h"
#include "envs/registry.h"
#include "eval/controller.h"
#include "eval/episode_runner.h"
#include "eval/summary.h"
#include "eval/tables.h"
#include "planner/impact_observer.h"
#include "planner/kick_memory_recorder.h"
#include "planner/planner_controller.h"
#include "planner/replan_trace.h"
#include "planner/rescue_sample_log.h"

namespace juggle {
namespace {

// Episode seeds no training run uses: training streams are (run seed, worker slot, env), with
// run seeds and slots far below this.
constexpr int64_t kHeldOutSeed = 1000000;

struct EvalFlags {
  std::string policy;
  std::string config;
  bool zero_action = false;
  std::string controller;  // "", "policy", "zero" or "planner"
  bool planner_trace = false;
  PlannerFlags planner;
  std::string proposal;  // --controller=planner: a policy as the plans' prior
  std::string kick_memory_out;  // --controller=planner, soccer: the solved kicks' memory
  std::string rescue_samples_out;  // --controller=planner: every rescue rollout (JSON lines)
  int episodes = 50;
  int64_t seed = kHeldOutSeed;
  int first_episode = 0;
  int planner_stream_base = -1;  // -1: first_episode
  double max_seconds = 60;
  std::string record;
  std::string json;
  bool force_sweep = false;
  double force_step = 1.0;
  double force_max = 5.0;
  double min_median_juggles = 10;
  // The stable band of the foot's acceleration at impact for this ball (restitution 0.8):
  // −2g(1+e²)/(1+e)² < a < 0 (docs/planner.md, "Impact acceleration").
  std::vector<double> impact_band = {-9.9, 0.0};
};

// A progress line at most every 10 s of wall time: the planner is far slower than real time.
// With `trace`, a line per re-plan.
std::function<void(int, const planner::ReplanReport&)> PlannerProgress(
    std::shared_ptr<const EnvSpec> spec, const planner::PlanningTask* task, int episodes,
    std::chrono::steady_clock::time_point started, bool trace) {
  auto last = std::make_shared<std::chrono::steady_clock::time_point>(started);
  return [spec, task, episodes, started, last, trace](int slot, const planner::ReplanReport& r) {
    if (trace) {
      std::printf("%s\n", planner::FormatReplanTrace(*task, *spec, slot, r).c_str());
      return;
    }
    const auto now = std::chrono::steady_clock::now();
    if (now - *last < std::chrono::seconds(10)) return;
    *last = now;
    // The episodes run side by side (eval/episode_runner.h): progress is the simulated time.
    std::printf("  planner: %.0f s wall, %d episodes side by side at %.2f s simulated; slot "
                "%d re-planned: cost %.3g -> %.3g%s\n",
                std::chrono::duration<double>(now - started).count(), episodes,
                r.env_step * spec->control_dt(), slot + 1, r.incumbent_cost, r.best_cost,
                r.predicts_failure ? " (predicts a failure)" : "");
    std::fflush(stdout);
  };
}

// Writes `lines` (JSON objects) to `path`, one per line.
absl::Status WriteJsonLines(const std::string& path, const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) absl::StrAppend(&text, line, "\n");
  return WriteFile(path, text);
}

int Evaluate(EvalFlags f) {
  if (f.zero_action) {
    if (!f.controller.empty() && f.controller != "zero") {
      return UsageError("--zero-action and --controller=" + f.controller + " exclude each other");
    }
    f.controller = "zero";
  }
  if (f.controller.empty() && !f.policy.empty()) f.controller = "policy";
  if (f.controller.empty()) {
    return UsageError("give --policy=PATH, --zero-action or --controller=planner");
  }
  if ((f.controller == "policy") == f.policy.empty()) {
    return UsageError(f.policy.empty() ? "--controller=policy needs --policy=PATH"
                                       : "--policy needs --controller=policy (or none)");
  }
  if (!f.proposal.empty() && f.controller != "planner") {
    return UsageError("--proposal needs --controller=planner");
  }
  if (!f.kick_memory_out.empty() && f.controller != "planner") {
    return UsageError("--kick-memory-out needs --controller=planner");
  }
  if (!f.rescue_samples_out.empty() && f.controller != "planner") {
    return UsageError("--rescue-samples-out needs --controller=planner");
  }
  if (f.impact_band[0] > f.impact_band[1]) {
    return UsageError(absl::StrFormat("--impact-band: MIN %g is above MAX %g", f.impact_band[0],
                                      f.impact_band[1]));
  }
  std::optional<PolicySource> source;
  LoadedConfig config;
  if (f.controller == "policy") {
    absl::StatusOr<PolicySource> loaded = LoadPolicySource(f.policy, f.config);
    if (!loaded.ok()) return Fail(loaded.status());
    source = std::move(*loaded);
    config = source->config;
    std::printf("policy %s\n", source->path.c_str());
  } else {
    if (f.config.empty()) return UsageError("--controller=" + f.controller + " needs --config");
    absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(f.config);
    if (!loaded.ok()) return Fail(loaded.status());
    config = std::move(*loaded);
  }
  if (absl::Status s = ApplyPlannerFlags(f.planner, &config); !s.ok()) return Fail(s);
  absl::StatusOr<const EnvFamily*> family = FamilyOf(config.run);
  if (!family.ok()) return Fail(family.status());
  (*family)->ConfigureForEvaluation(f.max_seconds, &config.run);
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(config);
  if (!spec.ok()) return Fail(spec.status());

  if (!f.json.empty()) {
    // Fail before evaluating, not after.
    if (absl::Status s = WriteJsonLines(f.json, {}); !s.ok()) return Fail(s);
  }
  if (!f.kick_memory_out.empty()) {
    if (absl::Status s = CheckWritable(f.kick_memory_out); !s.ok()) return Fail(s);
  }
  std::unique_ptr<planner::RescueSampleLog> rescue_samples;
  if (!f.rescue_samples_out.empty()) {
    absl::StatusOr<std::unique_ptr<planner::RescueSampleLog>> opened =
        planner::RescueSampleLog::Open(f.rescue_samples_out, (*spec)->obs_dim());
    if (!opened.ok()) return Fail(opened.status());
    rescue_samples = *std::move(opened);
  }
  PolicyController* policy_controller = nullptr;
  planner::PlannerController* planner_controller = nullptr;
  const auto started = std::chrono::steady_clock::now();
  ControllerChoice choice;
  choice.kind = f.controller;
  if (source) choice.policy = source->policy;
  choice.keep_gates = true;
  choice.planner_stream_base =
      static_cast<uint64_t>(f.planner_stream_base >= 0 ? f.planner_stream_base : f.first_episode);
  if (!f.proposal.empty()) {
    absl::StatusOr<PolicySource> proposal = LoadPolicySource(f.proposal, f.config);
    if (!proposal.ok()) return Fail(proposal.status());
    choice.proposal = proposal->policy;
    std::printf("proposal policy %s\n", proposal->path.c_str());
  }
  choice.on_planner = [&](planner::PlannerController* p) {
    planner_controller = p;
    p->set_on_replan(PlannerProgress(*spec, &p->task(), f.episodes, started, f.planner_trace));
    p->set_rescue_log(rescue_samples.get());
  };
  absl::StatusOr<std::unique_ptr<Controller>> made = MakeController(choice, *spec, config);
  if (!made.ok()) return Fail(made.status());
  std::unique_ptr<Controller> controller = *std::move(made);
  policy_controller = dynamic_cast<PolicyController*>(controller.get());
  if (planner_controller != nullptr) {
    const config::PlannerConfig& pc = config.run.planner();
    std::printf("planner: %d samples x %d iterations, horizon %d steps, re-plan every %d, "
                "%d threads\n",
                pc.samples(), pc.iterations(), pc.horizon_steps(), pc.replan_every(),
                pc.threads());
  }
  EpisodeOptions options;
  options.episodes = f.episodes;
  options.seed = static_cast<uint64_t>(f.seed);
  options.first_episode = f.first_episode;
  options.record = !f.record.empty();
  options.config_path = RecordedConfigName(config);
  planner::ImpactObservingController observed(controller.get());
  std::optional<planner::KickMemoryRecorder> remembered;
  Controller* acting = &observed;
  if (!f.kick_memory_out.empty()) {
    remembered.emplace(&observed, planner_controller);
    acting = &*remembered;
  }
  absl::StatusOr<EpisodeReport> report = RunEpisodes(*spec, acting, options);
  if (!report.ok()) return Fail(report.status());
  if (remembered.has_value()) {
    if (absl::Status s = WriteFileAtomically(f.kick_memory_out, remembered->FileText()); !s.ok()) {
      return Fail(s);
    }
    std::printf("kick memory: %d kicks to %s\n", static_cast<int>(remembered->rows().size()),
                f.kick_memory_out.c_str());
  }
  if (rescue_samples != nullptr) {
    if (absl::Status s = rescue_samples->Close(); !s.ok()) return Fail(s);
    std::printf("rescue samples: %d rescues, %lld rollouts to %s\n", rescue_samples->rescues(),
                static_cast<long long>(rescue_samples->rollouts()), f.rescue_samples_out.c_str());
  }
  if (report->trajectory) {
    if (absl::Status s = WriteTrajectory(*report->trajectory, f.record); !s.ok()) return Fail(s);
    std::printf("recorded %d episodes (%.2f s) to %s\n", f.episodes,
                report->trajectory->duration(), f.record.c_str());
  }
  const EvalSummary summary =
      Summarize(report->episodes, (*spec)->control_dt(), (*spec)->outcome_names());
  std::string line = absl::StrCat("policy=", controller->name(), " seed=", f.seed,
                                  " max_seconds=", f.max_seconds, " ",
                                  SummaryLine(summary, (*spec)->counts_juggles()));
  {
    // The family's own summary (football: PhysicsFC's metrics, envs/football/metrics.h).
    std::vector<std::vector<NamedValue>> metrics;
    for (const EpisodeResult& e : report->episodes) metrics.push_back(e.metrics);
    if (const std::string own = (*spec)->EvaluationLine(metrics); !own.empty()) {
      absl::StrAppend(&line, " ", own);
    }
  }
  if (planner_controller != nullptr) {
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    const planner::PlannerTotals t = planner_controller->totals();
    double sim_seconds = 0;
    for (const EpisodeResult& e : report->episodes) sim_seconds += e.steps * (*spec)->control_dt();
    absl::StrAppend(&line, absl::StrFormat(
        " planner_replans=%d planner_rollouts=%d planner_rollout_steps=%d planner_rescues=%d "
        "prediction_checks=%d prediction_mismatches=%d wall_s=%.1f wall_s_per_sim_s=%.3f",
        t.replans, t.rollouts, t.rollout_steps, t.rescues, t.prediction_checks, t.prediction_mismatches,
        wall, wall / std::max(sim_seconds, 1e-9)));
    if (t.rescues > 0) {
      // The rollout steps the rescues simulated (the rest: the regular searches).
      absl::StrAppend(&line,
                      absl::StrFormat(" planner_rescue_rollout_steps=%d", t.rescue_rollout_steps));
    }
    if (t.light_replans > 0) {
      // Re-plans that kept their healthy warm start without a search (planner.search_every).
      absl::StrAppend(&line, absl::StrFormat(" planner_light_replans=%d", t.light_replans));
    }
    if (t.rescues_paused > 0) {
      // Troubled re-plans without a rescue after one that still predicted the episode's end
      // (planner.rescue.pause_after_lost).
      absl::StrAppend(&line, absl::StrFormat(" planner_rescues_paused=%d", t.rescues_paused));
    }
    if (t.refined_out_of_trouble > 0) {
      // Troubled re-plans the refinement before the rescue fixed (planner.rescue.refine_first).
      absl::StrAppend(&line, absl::StrFormat(" planner_refined_out_of_trouble=%d",
                                             t.refined_out_of_trouble));
    }
    if (t.full_after_decay > 0) {
      // Decayed rescues still in trouble that a full one followed (planner.rescue.full_after_decay).
      absl::StrAppend(&line, absl::StrFormat(" planner_full_after_decay=%d", t.full_after_decay));
    }
    if (t.full_after_narrowed > 0) {
      // Narrowed rescues still in trouble that an unnarrowed one followed
      // (planner.rescue.full_after_narrowed).
      absl::StrAppend(&line,
                      absl::StrFormat(" planner_full_after_narrowed=%d", t.full_after_narrowed));
    }
    if (t.half_fixed_rescues > 0) {
      // Rescues in trouble only by planner.rescue.half_fixed_above.
      absl::StrAppend(&line, absl::StrFormat(" planner_half_fixed_rescues=%d",
                                             t.half_fixed_rescues));
    }
    if (t.proposal_tried > 0) {
      // The learned proposal (--proposal): re-plans that chose it alone, without offsets.
      absl::StrAppend(&line, absl::StrFormat(
          " proposal_tried=%d proposal_chosen=%d proposal_weight_mean=%.3f", t.proposal_tried,
          t.proposal_chosen, t.proposal_weight_sum / double(t.proposal_tried)));
    }
    if (t.model_checks > 0) {
      // A planning model (planner.planning_model): its choices checked on the executed model.
      const double disagreement = double(t.model_disagreements) / double(t.model_checks);
      absl::StrAppend(&line, absl::StrFormat(
          " planner_exact_rollouts=%d planner_exact_rollout_steps=%d model_checks=%d "
          "model_disagreements=%d model_disagreement_share=%.3f model_overrides=%d "
          "model_cost_gap_mean=%.2f",
          t.exact_rollouts, t.exact_rollout_steps, t.model_checks, t.model_disagreements,
          disagreement, t.model_overrides, t.model_cost_gap_sum / double(t.model_checks)));
      const double limit = config.run.planner().planning_model().max_disagreement_share();
      if (disagreement > limit) {
        std::printf("warning: the planning model and the executed model judged the chosen plan "
                    "differently (a failure or a missed contact predicted by one only) in %ld of "
                    "%ld re-plans (%.1f %%), above planner.planning_model.max_disagreement_share "
                    "%.3g: its predictions do not hold; use a finer planning model\n",
                    static_cast<long>(t.model_disagreements), static_cast<long>(t.model_checks),
                    100 * disagreement, limit);
      }
    }
  }
  if (observed.envs_measured() > 0) {
    absl::StrAppend(&line, planner::ImpactSummary(observed.accelerations(), f.impact_band[0],
                                                  f.impact_band[1]));
  }
  if (policy_controller != nullptr && policy_controller->gates().rows() > 0) {
    const GateStatistics g = ComputeGateStatistics(policy_controller->gates());
    absl::StrAppend(&line, absl::StrFormat(" gate_specialization=%.3f gate_utilization=%.3f",
                                           g.specialization, g.utilization));
  }
  const std::vector<NodeRow> nodes =
      NodeTable(report->episodes, (*spec)->graph(), (*spec)->outcome_names());
  std::printf("%s", FormatNodeTable(nodes).c_str());
  std::vector<std::string> json = {SummaryJson(summary)};
  for (const NodeRow& row : nodes) json.push_back(NodeRowJson(row));
  for (const EdgeRow& row : EdgeTable(report->episodes, (*spec)->graph())) {
    json.push_back(EdgeRowJson(row));
  }
  for (size_t i = 0; i < report->episodes.size(); ++i) {
    json.push_back(EpisodeJson(f.first_episode + static_cast<int>(i), report->episodes[i],
                               (*spec)->control_dt(), (*spec)->outcome_names()));
  }

  if (f.force_sweep) {
    ForceSweepOptions sweep;
    sweep.magnitudes.clear();
    for (int k = 0; k * f.force_step <= f.force_max + 1e-9; ++k) {
      sweep.magnitudes.push_back(k * f.force_step);
    }
    sweep.min_median_juggles = f.min_median_juggles;
    sweep.baseline = summary;  // the plain evaluation above: the same episodes without force
    sweep.episodes = options;
    sweep.episodes.record = false;
    // Controllers of their own: the gate statistics above stay those of the plain evaluation.
    // The planner plans with each swept config, so its model includes the force.
    // The swept planners report progress too: a sweep is many planner evaluations in a row.
    ControllerChoice swept_choice;
    swept_choice.kind = f.controller;
    if (source) swept_choice.policy = source->policy;
    swept_choice.proposal = choice.proposal;
    swept_choice.planner_stream_base = choice.planner_stream_base;
    const int episodes = f.episodes;
    const bool trace = f.planner_trace;
    const std::shared_ptr<const EnvSpec> swept_spec = *spec;
    swept_choice.on_planner = [swept_spec, episodes, started, trace](planner::PlannerController* p) {
      p->set_on_replan(PlannerProgress(swept_spec, &p->task(), episodes, started, trace));
    };
    absl::StatusOr<ControllerFactory> controllers = MakeControllerFactory(std::move(swept_choice));
    if (!controllers.ok()) return Fail(controllers.status());
    std::printf("force sweep: constant force on the ball, %zu magnitudes per direction, "
                "%d episodes each, pass: median juggles >= %g\n",
                sweep.magnitudes.size(), f.episodes, f.min_median_juggles);
    absl::StatusOr<ForceSweepReport> swept =
        RunForceSweep(config, *controllers, sweep, [](const std::string& l) {
          std::printf("  %s\n", l.c_str());
          std::fflush(stdout);
        });
    if (!swept.ok()) return Fail(swept.status());
    std::printf("%-9s %12s\n", "direction", "max_force_n");
    for (const std::string& direction : swept->directions) {
      // "none": even the smallest force fails.
      const double force = swept->max_force_n.at(direction);
      std::printf("%-9s %12s\n", direction.c_str(),
                  force < 0 ? "none" : absl::StrFormat("%.3f", force).c_str());
      absl::StrAppend(&line, absl::StrFormat(" max_force_%s=%g", direction, force));
      json.push_back(ForceLimitJson(direction, force, f.min_median_juggles));
    }
    for (const auto& [direction, why] : swept->unsupported) {
      std::printf("%-9s %12s  (%s)\n", direction.c_str(), "-", why.c_str());
    }
    for (const ForceSweepRow& row : swept->rows) json.push_back(ForceRowJson(row));
  }
  if (!f.json.empty()) {
    if (absl::Status s = WriteJsonLines(f.json, json); !s.ok()) return Fail(s);
    std::printf("wrote %zu JSON lines to %s\n", json.size(), f.json.c_str());
  }
  std::printf("%s\n", line.c_str());
  return 0;
}

}  // namespace

CommandBody AddEvalCommand(CLI::App* cmd) {
  auto f = std::make_shared<EvalFlags>();
  cmd->add_option("--policy,--checkpoint", f->policy,
                  "checkpoint file (.jglc), run directory (its newest checkpoint) or exported "
                  "policy (.jglpolicy)");
  cmd->add_option("--config", f->config,
                  "run config (default: the one recorded with the policy; required with "
                  "--zero-action)");
  cmd->add_flag("--zero-action", f->zero_action, "evaluate the zero-action baseline instead");
  cmd->add_option("--controller", f->controller,
                  "what acts: policy (the --policy's mean action), zero (= --zero-action) or "
                  "planner (model-predictive search with the config's planner settings, "
                  "docs/planner.md)")
      ->check(CLI::IsMember({"policy", "zero", "planner"}));
  AddPlannerFlags(cmd, &f->planner);
  cmd->add_flag("--planner-trace", f->planner_trace,
                "print every re-plan: its cost, each cost term and the kick it predicts");
  cmd->add_option("--proposal", f->proposal,
                  "with --controller=planner: a policy (checkpoint, run directory or .jglpolicy) "
                  "whose mean action is every plan's prior, the search correcting it "
                  "(planner.policy_prior; docs/planner.md)");
  cmd->add_option("--kick-memory-out", f->kick_memory_out,
                  "with --controller=planner on soccer juggling: write a memory of the solved "
                  "kicks (each incoming ball and the kick variables executed for it), which "
                  "planner.soccer_juggle.kick_memory reads as the next kick's proposal");
  cmd->add_option("--rescue-samples-out", f->rescue_samples_out,
                  "with --controller=planner: write every rollout of the rescue searches as "
                  "JSON lines (the troubled state's observation, each candidate's variables, "
                  "outcome and cost; planner/rescue_sample_log.h), e.g. for "
                  "scripts/analysis/kick_landscape.py");
  cmd->add_option("--episodes", f->episodes, "episodes, one per env seed")
      ->check(Between(1, 100000))
      ->capture_default_str();
  cmd->add_option("--seed", f->seed,
                  "episode i starts from stream (seed, 0, first-episode + i); the default is "
                  "held out from training")
      ->check(AtLeast(0))
      ->capture_default_str();
  cmd->add_option("--first-episode", f->first_episode,
                  "index of the first episode: one evaluation split into parts (e.g. "
                  "--episodes=5 --first-episode=5 is episodes 5-9 of --episodes=10; with "
                  "--controller=planner episode i also plans from planner stream first-episode + i)")
      ->check(Between(0, 100000000))
      ->capture_default_str();
  cmd->add_option("--planner-stream-base", f->planner_stream_base,
                  "with --controller=planner: the planner stream of the run's first episode "
                  "(-1: --first-episode, so a part plans as in the whole run; 0: every part "
                  "from stream 0, as evaluations split into parts did before 2026-12-01 and "
                  "scripts/experiments/planner_eval.sh still does)")
      ->check(Between(-1, 100000000))
      ->capture_default_str();
  cmd->add_option("--max_seconds", f->max_seconds,
                  "episode length limit in simulated seconds (0: the config's)")
      ->check(Between(0, 86400))
      ->capture_default_str();
  cmd->add_option("--record", f->record,
                  "write every episode, one after another, as a trajectory (docs/recording.md)");
  cmd->add_option("--json", f->json,
                  "also write the tables as JSON lines: summary, one per node, and with "
                  "--force-sweep one per direction and force (docs/results.md)");
  cmd->add_flag("--force-sweep", f->force_sweep,
                "robustness sweep (paper Table 1): a constant force on the ball along +-x, +-y, "
                "+-z at 0, step, 2*step, ... up to --force-max, each with the same episodes");
  cmd->add_option("--force-step", f->force_step, "force sweep step, N")
      ->check(Between(1e-6, 1000))
      ->capture_default_str();
  cmd->add_option("--force-max", f->force_max, "largest force of the sweep, N")
      ->check(Between(0, 1000))
      ->capture_default_str();
  cmd->add_option("--min-median-juggles", f->min_median_juggles,
                  "a force passes when the median juggles stay at or above this")
      ->check(AtLeast(0))
      ->capture_default_str();
  cmd->add_option("--impact-band", f->impact_band,
                  "soccer: the band of the kicking body's acceleration at impact (m/s^2, MIN MAX) "
                  "whose share impact_in_band reports; the default is this ball's stable band")
      ->expected(2)
      ->delimiter(',')
      ->capture_default_str();
  return [f] { return Evaluate(*f); };
}

}  // namespace juggle
