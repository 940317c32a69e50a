// `juggle toss`: pattern juggling with a trained catch/throw pair (worker/toss_juggler.h), one
// run or the evaluation protocol (--eval): consecutive throws before the first drop for each
// pattern over seeds, and a wind sweep. The last line is key=value pairs.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "google/protobuf/text_format.h"
#include "app/commands.h"
#include "app/flags.h"
#include "common/config_loader.h"
#include "common/eigen_policy.h"
#include "common/siteswap.h"
#include "learner/learner_state.h"
#include "worker/toss_juggler.h"
#include "worker/toss_spec.h"

namespace juggle {
namespace {

int Fail(const absl::Status& s) {
  std::fprintf(stderr, "error: %s\n", std::string(s.message()).c_str());
  return 1;
}

struct LoadedPolicy {
  LoadedConfig config;
  EigenPolicy policy;
};

// The newest checkpoint of `path` (file or run directory) and the config it was trained with;
// FAILED_PRECONDITION if that config is not a toss config of `task`.
absl::StatusOr<LoadedPolicy> LoadTossPolicy(const std::string& path, config::TossTask task) {
  absl::StatusOr<LoadedCheckpoint> checkpoint = LoadCheckpoint(path);
  if (!checkpoint.ok()) return checkpoint.status();
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(checkpoint->config_path);
  if (!config.ok()) return config.status();
  if (!config->run.has_toss() || config->run.toss().task() != task) {
    return absl::FailedPreconditionError(absl::StrCat(
        checkpoint->path, " was not trained on the toss ", config::TossTask_Name(task),
        " task (config ", checkpoint->config_path, ")"));
  }
  absl::StatusOr<EigenPolicy> policy = PolicyFromCheckpoint(checkpoint->sections, *config);
  if (!policy.ok()) return policy.status();
  std::printf("%s policy: %s\n", config::TossTask_Name(task).c_str(), checkpoint->path.c_str());
  return LoadedPolicy{*std::move(config), *std::move(policy)};
}

// The two tasks must share the body, the gains and the timing the policies were trained with.
// The model file as an absolute, normalized path (configs in different folders may name the
// same model differently).
std::string ModelPath(const LoadedConfig& config) {
  return std::filesystem::weakly_canonical(
             ResolvePath(config.config_dir, config.run.toss().model_file()))
      .string();
}

absl::Status CheckSameWorld(const LoadedConfig& catcher, const LoadedConfig& thrower) {
  const config::TossConfig& a = catcher.run.toss();
  const config::TossConfig& b = thrower.run.toss();
  if (ModelPath(catcher) != ModelPath(thrower) || a.kp() != b.kp() || a.kd() != b.kd() ||
      a.action_scale() != b.action_scale() || a.hand_period_s() != b.hand_period_s() ||
      a.dwell_ratio() != b.dwell_ratio() || a.hand_x() != b.hand_x() || a.hand_z() != b.hand_z()) {
    return absl::FailedPreconditionError(
        "the catch and throw policies were trained with different toss settings (model, gains, "
        "action_scale, hand_period_s, dwell_ratio or home point)");
  }
  return absl::OkStatus();
}

absl::StatusOr<std::shared_ptr<const TossSpec>> SpecWithWind(const LoadedConfig& base,
                                                             double wind) {
  LoadedConfig config = base;
  config.run.mutable_toss()->set_wind_force(wind);
  absl::StatusOr<std::shared_ptr<const TossSpec>> spec = TossSpec::Create(config);
  if (!spec.ok()) return spec.status();
  return *spec;
}

absl::Status WriteFrames(const std::vector<JuggleFrame>& frames, int balls,
                         const std::string& path) {
  std::ofstream out(path);
  if (!out) return absl::PermissionDeniedError(absl::StrCat("cannot write ", path));
  out << "time,neck,r_shoulder,r_elbow,r_wrist,l_shoulder,l_elbow,l_wrist,"
         "r_palm_x,r_palm_z,l_palm_x,l_palm_z";
  for (int b = 0; b < balls; ++b) out << ",ball" << b << "_x,ball" << b << "_z,ball" << b << "_mode";
  out << "\n";
  for (const JuggleFrame& f : frames) {
    out << f.time;
    for (double q : f.joints) out << "," << q;
    for (const Vec2& p : f.palms) out << "," << p.x << "," << p.z;
    for (size_t b = 0; b < f.balls.size(); ++b) {
      out << "," << f.balls[b].x << "," << f.balls[b].z << "," << f.ball_mode[b];
    }
    out << "\n";
  }
  return out ? absl::OkStatus() : absl::DataLossError(absl::StrCat("error writing ", path));
}

// Arm states where the policies took over, gathered over runs for --record-states.
struct StartStates {
  std::vector<TossArmState> catch_starts, throw_starts;
  void Add(const JuggleRunResult& r) {
    catch_starts.insert(catch_starts.end(), r.catch_starts.begin(), r.catch_starts.end());
    throw_starts.insert(throw_starts.end(), r.throw_starts.begin(), r.throw_starts.end());
  }
};

// Writes `states` as a text-format TossArmStates file (TossConfig.start_states_file).
absl::Status WriteArmStates(const std::vector<TossArmState>& states, const std::string& path,
                            const std::string& what) {
  config::TossArmStates message;
  for (const TossArmState& s : states) {
    config::TossArmState* m = message.add_state();
    for (int j = 0; j < kTossJoints; ++j) {
      m->add_angle(s.angle[j]);
      m->add_speed(s.speed[j]);
    }
  }
  std::string text;
  if (!google::protobuf::TextFormat::PrintToString(message, &text)) {
    return absl::InternalError("cannot print the arm states");
  }
  std::ofstream out(path);
  out << "# proto-file: proto/run_config.proto\n# proto-message: juggle.config.TossArmStates\n"
      << "# " << states.size() << " arm states (right arm's frame: neck, shoulder, elbow, wrist; "
      << "rad, rad/s) " << what << ", written by `juggle toss --record-states`.\n"
      << text;
  out.close();
  return out ? absl::OkStatus() : absl::DataLossError(absl::StrCat("error writing ", path));
}

// PREFIX_catch.textproto (states at releases: where the catch policy starts) and
// PREFIX_throw.textproto (states at catches: where the throw policy starts).
absl::Status WriteStartStates(const StartStates& states, const std::string& prefix) {
  const std::string catch_path = prefix + "_catch.textproto";
  const std::string throw_path = prefix + "_throw.textproto";
  if (absl::Status s = WriteArmStates(states.catch_starts, catch_path,
                                      "of throwing hands at their releases");
      !s.ok()) {
    return s;
  }
  if (absl::Status s = WriteArmStates(states.throw_starts, throw_path,
                                      "of catching hands at their catches");
      !s.ok()) {
    return s;
  }
  std::printf("recorded %zu catch start states to %s and %zu throw start states to %s\n",
              states.catch_starts.size(), catch_path.c_str(), states.throw_starts.size(),
              throw_path.c_str());
  return absl::OkStatus();
}

absl::StatusOr<JuggleRunResult> RunOnce(std::shared_ptr<const TossSpec> spec,
                                        const Siteswap& pattern, TossPolicies policies,
                                        int max_throws, uint64_t seed,
                                        std::vector<JuggleFrame>* frames = nullptr) {
  JugglerOptions options;
  options.max_throws = max_throws;
  options.seed = seed;
  absl::StatusOr<std::unique_ptr<TossJuggler>> juggler =
      TossJuggler::Create(std::move(spec), pattern, policies, options);
  if (!juggler.ok()) return juggler.status();
  return (*juggler)->Run(frames);
}

// Median of the throws over seeds first_seed..first_seed + seeds − 1.
absl::StatusOr<int> MedianThrows(std::shared_ptr<const TossSpec> spec, const Siteswap& pattern,
                                 TossPolicies policies, int max_throws, int first_seed, int seeds,
                                 std::vector<int>* all = nullptr,
                                 StartStates* start_states = nullptr) {
  std::vector<int> throws;
  for (int s = first_seed; s < first_seed + seeds; ++s) {
    absl::StatusOr<JuggleRunResult> r = RunOnce(spec, pattern, policies, max_throws, s);
    if (!r.ok()) return r.status();
    throws.push_back(r->throws);
    if (start_states) start_states->Add(*r);
  }
  if (all) *all = throws;
  std::sort(throws.begin(), throws.end());
  const size_t n = throws.size();
  return n % 2 ? throws[n / 2] : (throws[n / 2 - 1] + throws[n / 2]) / 2;
}

int Evaluate(const LoadedConfig& base, TossPolicies policies, const std::string& pattern_list,
             int first_seed, int seeds, int max_throws, double wind_step, double wind_max,
             const std::string& record_states) {
  absl::StatusOr<std::shared_ptr<const TossSpec>> spec =
      SpecWithWind(base, base.run.toss().wind_force());
  if (!spec.ok()) return Fail(spec.status());
  std::string summary;
  StartStates start_states;  // of the pattern runs (not the wind sweep)
  int max_basic = 0;
  bool basic_chain = true;
  std::printf("%-8s %5s %8s  throws per seed (max %d)\n", "pattern", "balls", "median", max_throws);
  for (const std::string& text :
       std::vector<std::string>(absl::StrSplit(pattern_list, ',', absl::SkipEmpty()))) {
    absl::StatusOr<Siteswap> pattern = Siteswap::Parse(text);
    if (!pattern.ok()) return Fail(pattern.status());
    std::vector<int> all;
    absl::StatusOr<int> median = MedianThrows(*spec, *pattern, policies, max_throws, first_seed, seeds, &all,
                                              record_states.empty() ? nullptr : &start_states);
    if (!median.ok()) return Fail(median.status());
    std::string per_seed;
    for (int t : all) absl::StrAppend(&per_seed, " ", t);
    std::printf("%-8s %5d %8d  %s\n", text.c_str(), pattern->balls(), *median, per_seed.c_str());
    std::fflush(stdout);
    absl::StrAppend(&summary, " throws_", text, "=", *median);
    if (pattern->period() == 1 && pattern->balls() >= 3) {
      // Basic patterns count upwards from 3 without a gap.
      if (basic_chain && *median >= 100 && pattern->balls() == std::max(3, max_basic + 1)) {
        max_basic = pattern->balls();
      } else if (*median < 100) {
        basic_chain = false;
      }
    }
  }
  if (!record_states.empty()) {
    if (absl::Status s = WriteStartStates(start_states, record_states); !s.ok()) return Fail(s);
  }
  // Wind sweep: the largest constant horizontal force (N) on balls in flight at which the
  // median over the seeds still reaches 100 throws of "3".
  const Siteswap three = *Siteswap::Parse("3");
  double max_wind = -1;
  for (double wind = 0; wind <= wind_max + 1e-9; wind += wind_step) {
    absl::StatusOr<std::shared_ptr<const TossSpec>> windy = SpecWithWind(base, wind);
    if (!windy.ok()) return Fail(windy.status());
    absl::StatusOr<int> median = MedianThrows(*windy, three, policies, 100, first_seed, seeds);
    if (!median.ok()) return Fail(median.status());
    std::printf("wind %.3f N: median %d throws of 3\n", wind, *median);
    std::fflush(stdout);
    if (*median < 100) break;
    max_wind = wind;
  }
  std::printf("seeds=%d max_throws=%d%s max_basic_pattern=%d max_wind_n=%.3f\n", seeds, max_throws,
              summary.c_str(), max_basic, std::max(0.0, max_wind));
  return 0;
}

}  // namespace

int RunToss(int argc, char** argv, int first) {
  const std::vector<FlagSpec> specs = {
      {"pattern", "3", "vanilla siteswap to juggle (e.g. 3, 531, 441)"},
      {"checkpoint", "runs", "folder holding the toss_catch and toss_throw run directories"},
      {"catch", "", "catch policy: checkpoint file or run directory (default <checkpoint>/toss_catch)"},
      {"throw", "", "throw policy: checkpoint file or run directory (default <checkpoint>/toss_throw)"},
      {"zero-action", "false", "both arms hold their home pose (baseline); needs --config"},
      {"config", "configs/toss_catch.textproto", "toss config for --zero-action"},
      {"seed", "1", "seed of the run (arm and ball start perturbations); with --eval the first "
                    "of its seeds"},
      {"max-throws", "200", "stop after this many throws"},
      {"wind", "-1", "constant horizontal force on balls in flight, N (-1: the config's)"},
      {"record", "", "write the ball and arm trajectories to this CSV file"},
      {"record-states", "", "write the arm states at releases and catches to PREFIX_catch.textproto "
                            "and PREFIX_throw.textproto (TossConfig.start_states_file)"},
      {"eval", "false", "evaluation protocol: patterns x seeds and a wind sweep"},
      {"patterns", "3,4,5,53,441,531,6,7", "patterns of --eval"},
      {"seeds", "10", "seeds per pattern of --eval (seed..seed+seeds-1)"},
      {"wind-step", "0.02", "wind sweep step of --eval, N"},
      {"wind-max", "1.0", "largest wind of the sweep, N"},
  };
  absl::StatusOr<Flags> flags = Flags::Parse(argc, argv, first, specs);
  if (!flags.ok()) return Fail(flags.status());
  if (flags->help()) {
    std::printf("usage: juggle toss [--pattern=531] [--checkpoint=runs | --catch=P --throw=P] "
                "[--eval] [flags]\n%s", Flags::Usage(specs).c_str());
    return 0;
  }
  auto seed = flags->GetInt("seed");
  auto max_throws = flags->GetInt("max-throws");
  auto seeds = flags->GetInt("seeds");
  auto wind = flags->GetDouble("wind");
  auto wind_step = flags->GetDouble("wind-step");
  auto wind_max = flags->GetDouble("wind-max");
  for (const absl::Status& s : {seed.status(), max_throws.status(), seeds.status(), wind.status(),
                                wind_step.status(), wind_max.status()}) {
    if (!s.ok()) return Fail(s);
  }
  if (*seeds < 1 || *max_throws < 1 || *wind_step <= 0) {
    return Fail(absl::InvalidArgumentError("--seeds and --max-throws must be >= 1, --wind-step > 0"));
  }

  std::optional<LoadedPolicy> catcher, thrower;
  LoadedConfig base;
  if (flags->GetBool("zero-action")) {
    absl::StatusOr<LoadedConfig> config = LoadRunConfig(flags->Get("config"));
    if (!config.ok()) return Fail(config.status());
    if (!config->run.has_toss()) {
      return Fail(absl::InvalidArgumentError(flags->Get("config") + " is not a toss config"));
    }
    base = *config;
  } else {
    const std::string dir = flags->Get("checkpoint");
    const std::string catch_path = flags->Get("catch").empty() ? dir + "/toss_catch" : flags->Get("catch");
    const std::string throw_path = flags->Get("throw").empty() ? dir + "/toss_throw" : flags->Get("throw");
    absl::StatusOr<LoadedPolicy> c = LoadTossPolicy(catch_path, config::CATCH);
    if (!c.ok()) return Fail(c.status());
    absl::StatusOr<LoadedPolicy> t = LoadTossPolicy(throw_path, config::THROW);
    if (!t.ok()) return Fail(t.status());
    if (absl::Status s = CheckSameWorld(c->config, t->config); !s.ok()) {
      return Fail(s);
    }
    catcher = *std::move(c);
    thrower = *std::move(t);
    base = catcher->config;
  }
  if (*wind >= 0) base.run.mutable_toss()->set_wind_force(*wind);
  const TossPolicies policies{catcher ? &catcher->policy : nullptr,
                              thrower ? &thrower->policy : nullptr};

  if (flags->GetBool("eval")) {
    return Evaluate(base, policies, flags->Get("patterns"), static_cast<int>(*seed),
                    static_cast<int>(*seeds),
                    static_cast<int>(*max_throws), *wind_step, *wind_max,
                    flags->Get("record-states"));
  }
  absl::StatusOr<Siteswap> pattern = Siteswap::Parse(flags->Get("pattern"));
  if (!pattern.ok()) return Fail(pattern.status());
  absl::StatusOr<std::shared_ptr<const TossSpec>> spec =
      SpecWithWind(base, base.run.toss().wind_force());
  if (!spec.ok()) return Fail(spec.status());
  std::vector<JuggleFrame> frames;
  const bool record = !flags->Get("record").empty();
  absl::StatusOr<JuggleRunResult> r = RunOnce(*spec, *pattern, policies,
                                              static_cast<int>(*max_throws), *seed,
                                              record ? &frames : nullptr);
  if (!r.ok()) return Fail(r.status());
  if (record) {
    if (absl::Status s = WriteFrames(frames, pattern->balls(), flags->Get("record")); !s.ok()) {
      return Fail(s);
    }
    std::printf("recorded %zu frames (%.2f s) to %s\n", frames.size(), r->seconds,
                flags->Get("record").c_str());
  }
  if (!flags->Get("record-states").empty()) {
    StartStates states;
    states.Add(*r);
    if (absl::Status s = WriteStartStates(states, flags->Get("record-states")); !s.ok()) {
      return Fail(s);
    }
  }
  std::printf("pattern=%s balls=%d throws=%d good_throws=%d catches=%d drops=%d end=%s "
              "seconds=%.2f mean_velocity_error=%.3f mean_position_error=%.4f wind_n=%.3f\n",
              flags->Get("pattern").c_str(), pattern->balls(), r->throws, r->good_throws, r->catches,
              r->end == JuggleEnd::kDropped ? 1 : 0, JuggleEndName(r->end), r->seconds,
              r->mean_velocity_error, r->mean_position_error, base.run.toss().wind_force());
  return 0;
}

}  // namespace juggle
