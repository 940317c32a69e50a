// `juggle toss`: pattern juggling with a trained catch/throw pair (envs/toss/juggler.h), one run
// or the evaluation protocol (--eval, envs/toss/eval.h). Policies are checkpoints, run
// directories or exported .jglpolicy files. The last line is key=value pairs.
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "app/commands.h"
#include "app/policy_source.h"
#include "envs/mujoco_model.h"
#include "envs/registry.h"
#include "envs/toss/eval.h"
#include "common/file_io.h"

namespace juggle {
namespace {

using toss::TossPolicies;

struct TossFlags {
  std::string pattern = "3";
  std::string checkpoint = "runs";
  std::string catch_path, throw_path;
  bool zero_action = false;
  std::string config = "configs/toss_catch.textproto";
  // Held out: training draws 64-bit juggler seeds and the checkpoint ranking uses 101-105.
  int64_t seed = 1001;
  int max_throws = 200;
  double wind = -1;
  std::string record, record_states;
  bool eval = false;
  std::string patterns = "3,4,5,53,441,531,6,7";
  int seeds = 10;
  double wind_step = 0.02, wind_max = 1.0;
  std::string json;
  std::string transitions = "3,531,5,7,3";
  bool transitions_set = false;
  int throws_each = 20;
};

// A policy trained on the toss task `task`.
absl::StatusOr<PolicySource> LoadTossPolicy(const std::string& path, config::TossTask task) {
  absl::StatusOr<PolicySource> source = LoadPolicySource(path, "");
  if (!source.ok()) return source.status();
  if (!source->config.run.has_toss() || source->config.run.toss().task() != task) {
    return absl::FailedPreconditionError(absl::StrCat(
        source->path, " was not trained on the toss ", config::TossTask_Name(task), " task"));
  }
  std::printf("%s policy: %s\n", config::TossTask_Name(task).c_str(), source->path.c_str());
  return source;
}

// The two tasks must share the body, the gains and the timing the policies were trained with.
// The bodies are compared as compiled models (stored with the policy or compiled from its
// MJCF), so the same model named from different folders, or stored, compares equal.
absl::Status CheckSameWorld(const PolicySource& catcher, const PolicySource& thrower) {
  const config::TossConfig& a = catcher.config.run.toss();
  const config::TossConfig& b = thrower.config.run.toss();
  if (SaveModel(catcher.spec->model()) != SaveModel(thrower.spec->model()) ||
      a.kp() != b.kp() || a.kd() != b.kd() ||
      a.action_scale() != b.action_scale() || a.hand_period_s() != b.hand_period_s() ||
      a.dwell_ratio() != b.dwell_ratio() || a.hand_x() != b.hand_x() || a.hand_z() != b.hand_z() ||
      a.has_base() != b.has_base() ||
      a.base().SerializeAsString() != b.base().SerializeAsString()) {
    return absl::FailedPreconditionError(
        "the catch and throw policies were trained with different toss settings (model, gains, "
        "action_scale, hand_period_s, dwell_ratio, home point or base controllers)");
  }
  return absl::OkStatus();
}

int Evaluate(const LoadedConfig& base, TossPolicies policies, const TossFlags& f) {
  if (!f.json.empty()) {
    if (absl::Status s = CheckWritable(f.json); !s.ok()) return Fail(s);
  }
  toss::TossEvalOptions o;
  o.patterns = absl::StrSplit(f.patterns, ',', absl::SkipEmpty());
  o.first_seed = static_cast<int>(f.seed);
  o.seeds = f.seeds;
  o.max_throws = f.max_throws;
  o.wind_step = f.wind_step;
  o.wind_max = f.wind_max;
  o.keep_start_states = !f.record_states.empty();
  if (f.transitions != "none") o.transitions = absl::StrSplit(f.transitions, ',', absl::SkipEmpty());
  else o.transitions.clear();
  o.throws_each = f.throws_each;
  std::printf("%-8s %5s %8s  %8s %8s %6s  throws per seed (max %d)\n", "pattern", "balls",
              "median", "v_err", "v_max", "z_cm", f.max_throws);
  std::printf("  (v_err, v_max: mean and largest release-velocity error, m/s; z_cm: mean "
              "catch-height error, cm)\n");
  absl::StatusOr<toss::TossEvalReport> report =
      toss::EvaluateToss(base, policies, o, [](const std::string& line) {
        std::printf("%s\n", line.c_str());
        std::fflush(stdout);
      });
  if (!report.ok()) return Fail(report.status());
  if (!f.record_states.empty()) {
    if (absl::Status s = toss::WriteStartStates(report->start_states, f.record_states); !s.ok()) {
      return Fail(s);
    }
    std::printf("recorded %zu catch and %zu throw start states to %s_catch.textproto and "
                "%s_throw.textproto\n",
                report->start_states.catch_starts.size(), report->start_states.throw_starts.size(),
                f.record_states.c_str(), f.record_states.c_str());
  }
  if (!f.json.empty()) {
    std::string text;
    for (const std::string& line : toss::TossEvalJsonLines(*report, o)) text += line + "\n";
    if (absl::Status s = WriteFile(f.json, text); !s.ok()) return Fail(s);
    std::printf("wrote the evaluation as JSON lines to %s\n", f.json.c_str());
  }
  std::string summary;
  for (const toss::PatternResult& p : report->patterns) {
    absl::StrAppend(&summary, " throws_", p.pattern, "=", p.median_throws);
  }
  if (report->transition) {
    absl::StrAppend(&summary, " transitions=", report->transition->median_throws, "/",
                    report->transition->needed);
  }
  std::printf("seeds=%d max_throws=%d%s max_basic_pattern=%d max_wind_n=%.3f\n", f.seeds,
              f.max_throws, summary.c_str(), report->max_basic_pattern, report->max_wind_n);
  return 0;
}

int Toss(const TossFlags& f) {
  if (!f.json.empty() && !f.eval) return UsageError("--json needs --eval");
  std::optional<PolicySource> catcher, thrower;
  LoadedConfig base;
  if (f.zero_action) {
    absl::StatusOr<LoadedConfig> config = LoadRunConfig(f.config);
    if (!config.ok()) return Fail(config.status());
    if (!config->run.has_toss()) return UsageError(f.config + " is not a toss config");
    base = *config;
  } else {
    const std::string catch_path = f.catch_path.empty() ? f.checkpoint + "/toss_catch" : f.catch_path;
    const std::string throw_path = f.throw_path.empty() ? f.checkpoint + "/toss_throw" : f.throw_path;
    absl::StatusOr<PolicySource> c = LoadTossPolicy(catch_path, config::CATCH);
    if (!c.ok()) return Fail(c.status());
    absl::StatusOr<PolicySource> t = LoadTossPolicy(throw_path, config::THROW);
    if (!t.ok()) return Fail(t.status());
    if (absl::Status s = CheckSameWorld(*c, *t); !s.ok()) return Fail(s);
    catcher = *std::move(c);
    thrower = *std::move(t);
    base = catcher->config;
  }
  if (f.wind >= 0) base.run.mutable_toss()->set_wind_force(f.wind);
  const TossPolicies policies{catcher ? catcher->policy.get() : nullptr,
                              thrower ? thrower->policy.get() : nullptr};
  if (f.eval) return Evaluate(base, policies, f);

  absl::StatusOr<toss::JuggleSchedule> schedule = absl::InternalError("no schedule");
  if (f.transitions_set) {
    std::vector<toss::Siteswap> patterns;
    for (const std::string& text :
         std::vector<std::string>(absl::StrSplit(f.transitions, ',', absl::SkipEmpty()))) {
      absl::StatusOr<toss::Siteswap> p = toss::Siteswap::Parse(text);
      if (!p.ok()) return Fail(p.status());
      patterns.push_back(*p);
    }
    schedule = toss::JuggleSchedule::Transitions(patterns, f.throws_each);
  } else {
    absl::StatusOr<toss::Siteswap> p = toss::Siteswap::Parse(f.pattern);
    if (!p.ok()) return Fail(p.status());
    schedule = toss::JuggleSchedule(*p);
  }
  if (!schedule.ok()) return Fail(schedule.status());
  absl::StatusOr<std::shared_ptr<const toss::TossSpec>> spec =
      toss::SpecWithWind(base, base.run.toss().wind_force());
  if (!spec.ok()) return Fail(spec.status());
  std::optional<TrajectoryBuilder> recording;
  if (!f.record.empty()) {
    recording.emplace(
        toss::TossJuggler::NewRecording(**spec, schedule->max_balls(), RecordedConfigName(base)));
  }
  absl::StatusOr<toss::JuggleRunResult> r =
      toss::RunOnce(*spec, *schedule, policies, f.max_throws, f.seed,
                    recording ? &*recording : nullptr);
  if (!r.ok()) return Fail(r.status());
  if (recording) {
    if (absl::Status s = WriteTrajectory(recording->trajectory(), f.record); !s.ok()) return Fail(s);
    std::printf("recorded %d samples (%.2f s) to %s\n", recording->trajectory().num_samples(),
                r->seconds, f.record.c_str());
  }
  if (!f.record_states.empty()) {
    toss::StartStates states;
    states.Add(*r);
    if (absl::Status s = toss::WriteStartStates(states, f.record_states); !s.ok()) return Fail(s);
    std::printf("recorded %zu catch start states to %s_catch.textproto and %zu throw start states "
                "to %s_throw.textproto\n",
                states.catch_starts.size(), f.record_states.c_str(), states.throw_starts.size(),
                f.record_states.c_str());
  }
  std::printf("pattern=%s balls=%d throws=%d good_throws=%d catches=%d drops=%d end=%s "
              "seconds=%.2f mean_velocity_error=%.3f mean_position_error=%.4f wind_n=%.3f\n",
              schedule->Name().c_str(), schedule->max_balls(), r->throws, r->good_throws, r->catches,
              r->end == toss::JuggleEnd::kDropped ? 1 : 0, toss::JuggleEndName(r->end),
              r->seconds, r->mean_velocity_error, r->mean_position_error,
              base.run.toss().wind_force());
  return 0;
}

}  // namespace

CommandBody AddTossCommand(CLI::App* cmd) {
  auto f = std::make_shared<TossFlags>();
  cmd->add_option("--pattern", f->pattern, "vanilla siteswap to juggle (e.g. 3, 531, 441)")
      ->capture_default_str();
  cmd->add_option("--checkpoint", f->checkpoint,
                  "folder holding the toss_catch and toss_throw run directories")
      ->capture_default_str();
  cmd->add_option("--catch", f->catch_path,
                  "catch policy: checkpoint, run directory or .jglpolicy (default "
                  "<checkpoint>/toss_catch)");
  cmd->add_option("--throw", f->throw_path,
                  "throw policy: checkpoint, run directory or .jglpolicy (default "
                  "<checkpoint>/toss_throw)");
  cmd->add_flag("--zero-action", f->zero_action,
                "no policies: both arms hold their home pose, or run the base controllers alone "
                "when the config has a toss.base block (zero residual); uses --config");
  cmd->add_option("--config", f->config, "toss config for --zero-action")->capture_default_str();
  cmd->add_option("--seed", f->seed,
                  "seed of the run (arm and ball start perturbations); with --eval the first of "
                  "its seeds (the default 1001.. is held out from training and ranking)")
      ->check(AtLeast(0))
      ->capture_default_str();
  cmd->add_option("--max-throws", f->max_throws, "stop after this many throws")
      ->check(Between(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--wind", f->wind,
                  "constant horizontal force on balls in flight, N (-1: the config's)")
      ->check(Between(-1, 100))
      ->capture_default_str();
  cmd->add_option("--record", f->record,
                  "write the run as a trajectory (docs/recording.md): arms, balls, hand modes");
  cmd->add_option("--record-states", f->record_states,
                  "write the arm states at releases and catches to PREFIX_catch.textproto and "
                  "PREFIX_throw.textproto (TossConfig.start_states_file)");
  cmd->add_option("--transitions", f->transitions,
                  "patterns juggled in turn, passing between them by the shortest transition "
                  "(balls brought in or put away as the counts change); with --eval the "
                  "protocol's transition run (none: skip it)")
      ->each([f](const std::string&) { f->transitions_set = true; })
      ->capture_default_str();
  cmd->add_option("--throws-each", f->throws_each, "throws of each pattern of --transitions")
      ->check(AtLeast(1))
      ->capture_default_str();
  cmd->add_flag("--eval", f->eval, "evaluation protocol: patterns x seeds and a wind sweep");
  cmd->add_option("--patterns", f->patterns, "patterns of --eval")->capture_default_str();
  cmd->add_option("--json", f->json,
                  "with --eval: also write the tables as JSON lines (patterns, wind, summary)");
  cmd->add_option("--seeds", f->seeds, "seeds per pattern of --eval (seed..seed+seeds-1)")
      ->check(Between(1, 100000))
      ->capture_default_str();
  cmd->add_option("--wind-step", f->wind_step, "wind sweep step of --eval, N")
      ->check(Between(1e-6, 100))
      ->capture_default_str();
  cmd->add_option("--wind-max", f->wind_max, "largest wind of the sweep, N")
      ->check(Between(0, 100))
      ->capture_default_str();
  return [f] { return Toss(*f); };
}

}  // namespace juggle
