#include "envs/toss/family.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "common/policy_file.h"
#include "common/status_macros.h"
#include "envs/toss/dims.h"
#include "envs/toss/spec.h"

namespace juggle::toss {
namespace {

absl::Status ValidateToss(const config::TossConfig& t, const SourceLocator& where) {
  auto fail = [&](const char* field, const char* rule) {
    return absl::InvalidArgumentError(absl::StrCat(where.Where({{field}}), ": ", rule));
  };
  if (t.task() == config::TOSS_TASK_UNSPECIFIED) return fail("task", "must be CATCH or THROW");
  if (!(t.kp() > 0)) return fail("kp", "must be > 0");
  if (!(t.kd() >= 0)) return fail("kd", "must be >= 0");
  if (!(t.action_scale() > 0)) return fail("action_scale", "must be > 0");
  if (!(t.hand_period_s() > 0)) return fail("hand_period_s", "must be > 0");
  if (!(t.dwell_ratio() > 0 && t.dwell_ratio() < 1)) return fail("dwell_ratio", "must lie in (0, 1)");
  if (!(t.catch_radius() > 0)) return fail("catch_radius", "must be > 0");
  if (!(t.drop_z() < t.hand_z())) return fail("drop_z", "must be below hand_z");
  if (t.min_throw() < 1 || t.min_throw() == 2) return fail("min_throw", "must be 1 or >= 3");
  if (t.max_throw() < t.min_throw() || t.max_throw() > 9) {
    return fail("max_throw", "must lie in [min_throw, 9]");
  }
  if (!(t.landing_spread() >= 0)) return fail("landing_spread", "must be >= 0");
  if (!(t.flight_jitter() >= 0 && t.flight_jitter() < 0.5)) {
    return fail("flight_jitter", "must lie in [0, 0.5)");
  }
  if (!(t.catch_timing_jitter_s() >= 0 &&
        t.catch_timing_jitter_s() < t.dwell_ratio() * t.hand_period_s())) {
    return fail("catch_timing_jitter_s", "must lie in [0, dwell_ratio * hand_period_s)");
  }
  if (!(t.arrival_min_s() > 0 && t.arrival_max_s() >= t.arrival_min_s())) {
    return fail("arrival_max_s", "needs 0 < arrival_min_s <= arrival_max_s");
  }
  if (!(t.start_noise() >= 0)) return fail("start_noise", "must be >= 0");
  if (!(t.start_speed_noise() >= 0)) return fail("start_speed_noise", "must be >= 0");
  if (t.max_episode_steps() < 1) return fail("max_episode_steps", "must be >= 1");
  if (!(t.recorded_start_fraction() >= 0 && t.recorded_start_fraction() <= 1)) {
    return fail("recorded_start_fraction", "must lie in [0, 1]");
  }
  if (!(t.recorded_start_noise() >= 0)) return fail("recorded_start_noise", "must be >= 0");
  return absl::OkStatus();
}

// Moves the states of `start_states_file` into `start_state` and checks every state's size.
absl::Status InlineStartStates(const std::string& config_dir, const SourceLocator& where,
                               config::TossConfig* toss) {
  if (toss->has_start_states_file()) {
    const std::string path = ResolvePath(config_dir, toss->start_states_file());
    absl::StatusOr<std::string> text = ReadFile(path);
    if (!text.ok()) {
      return absl::NotFoundError(
          absl::StrCat(where.Where({{"start_states_file"}}), ": ", text.status().message()));
    }
    config::TossArmStates states;
    absl::StatusOr<SourceLocator> parsed = ParseTextMessage(*text, path, &states);
    if (!parsed.ok()) return parsed.status();
    for (config::TossArmState& s : *states.mutable_state()) *toss->add_start_state() = std::move(s);
    toss->clear_start_states_file();
  }
  for (int i = 0; i < toss->start_state_size(); ++i) {
    const config::TossArmState& s = toss->start_state(i);
    if (s.angle_size() != kTossJoints || s.speed_size() != kTossJoints) {
      return absl::InvalidArgumentError(absl::StrCat(
          where.Where({{"start_state"}}), ": start state ", i, " has ", s.angle_size(),
          " angles and ", s.speed_size(), " speeds; each needs ", kTossJoints,
          " (neck, shoulder, elbow, wrist)"));
    }
  }
  return absl::OkStatus();
}

// Reads the policy file (any format, common/policy_file.h) named by `field` into `policy`,
// without its compiled model: the loop runs partners in its own model.
absl::Status InlinePolicyFile(const std::string& config_dir, const SourceLocator& where,
                              const char* field, const std::string& file,
                              config::ExportedPolicy* policy) {
  const std::string path = ResolvePath(config_dir, file);
  absl::StatusOr<std::string> bytes = ReadFile(path);
  if (!bytes.ok()) {
    return absl::NotFoundError(absl::StrCat(where.Where({{field}}), ": ", bytes.status().message(),
                                            " (write it with `juggle export-policy`)"));
  }
  absl::StatusOr<PolicyFile> parsed = ParsePolicyFile(*bytes, path);
  if (!parsed.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat(where.Where({{field}}), ": ", parsed.status().message()));
  }
  *policy = std::move(parsed->policy);
  policy->clear_model_mjb();
  policy->clear_mujoco_version();
  return absl::OkStatus();
}

// In-loop training: both partner policies must be present (files are inlined) unless the base
// controllers stand in for them (toss.base). The patterns
// are checked against the model by TossSpec.
absl::Status PrepareLoop(const std::string& config_dir, const SourceLocator& toss_where,
                         config::TossConfig* toss) {
  if (!toss->has_loop()) return absl::OkStatus();
  const SourceLocator where = toss_where.Nested({{"loop"}});
  config::TossLoopConfig* loop = toss->mutable_loop();
  if (loop->pattern_size() == 0) {
    return absl::InvalidArgumentError(
        absl::StrCat(where.Where({{"pattern"}}), ": name at least one siteswap to juggle"));
  }
  if (loop->max_throws() < 1) {
    return absl::InvalidArgumentError(absl::StrCat(where.Where({{"max_throws"}}), ": must be >= 1"));
  }
  if (!(loop->start_noise() >= 0)) {
    return absl::InvalidArgumentError(absl::StrCat(where.Where({{"start_noise"}}), ": must be >= 0"));
  }
  if (loop->has_catch_policy_file()) {
    RETURN_IF_ERROR(InlinePolicyFile(config_dir, where, "catch_policy_file",
                                     loop->catch_policy_file(), loop->mutable_catch_policy()));
    loop->clear_catch_policy_file();
  }
  if (loop->has_throw_policy_file()) {
    RETURN_IF_ERROR(InlinePolicyFile(config_dir, where, "throw_policy_file",
                                     loop->throw_policy_file(), loop->mutable_throw_policy()));
    loop->clear_throw_policy_file();
  }
  if (!toss->has_base() && (!loop->has_catch_policy() || !loop->has_throw_policy())) {
    return absl::InvalidArgumentError(absl::StrCat(
        where.Where({{loop->has_catch_policy() ? "throw_policy_file" : "catch_policy_file"}}),
        ": the loop needs both partner policies (catch_policy_file and throw_policy_file), or a "
        "toss.base block to let the base controllers drive the partner arm and mode"));
  }
  return absl::OkStatus();
}


class TossFamily final : public EnvFamily {
 public:
  std::string_view name() const override { return "toss"; }
  config::RunConfig::FamilyCase config_case() const override { return config::RunConfig::kToss; }
  absl::Status Prepare(LoadedConfig* loaded) const override {
    // No control graph: the empty graph keeps the walk and the wire format uniform (zero edges,
    // zero counts).
    loaded->family_locator = loaded->root.Nested({{"toss"}});
    config::TossConfig* toss = loaded->run.mutable_toss();
    RETURN_IF_ERROR(ValidateToss(*toss, loaded->family_locator));
    RETURN_IF_ERROR(InlineStartStates(loaded->config_dir, loaded->family_locator, toss));
    return PrepareLoop(loaded->config_dir, loaded->family_locator, toss);
  }
  absl::StatusOr<std::shared_ptr<const EnvSpec>> CreateSpec(
      const LoadedConfig& config, const std::string& model_mjb) const override {
    absl::StatusOr<std::shared_ptr<const TossSpec>> spec =
        model_mjb.empty() ? TossSpec::Create(config) : TossSpec::CreateFromCompiled(config, model_mjb);
    if (!spec.ok()) return spec.status();
    return std::shared_ptr<const EnvSpec>(*std::move(spec));
  }
  void ConfigureForEvaluation(double max_seconds, config::RunConfig* run) const override {
    // The toss model's timestep (10 ms) is its control step (TossSpec checks it). Recorded
    // start states are part of the task's start distribution here (the runtime's states), so
    // they stay.
    if (max_seconds > 0) {
      run->mutable_toss()->set_max_episode_steps(
          static_cast<int>(std::ceil(max_seconds / 0.01 - 1e-9)));
    }
  }
  absl::Status SetConstantBallForce(const double force[3], config::RunConfig* run) const override {
    // Wind (TossConfig.wind_force): horizontal in the arms' plane, + towards the juggler's left
    // (world +x), on balls in flight.
    if (force[1] != 0 || force[2] != 0) {
      return absl::UnimplementedError(
          "the toss family applies only horizontal wind in the arms' plane (x: wind_force)");
    }
    run->mutable_toss()->set_wind_force(force[0]);
    return absl::OkStatus();
  }
};

}  // namespace

const EnvFamily& Family() {
  static const TossFamily family;
  return family;
}

}  // namespace juggle::toss
