#include "envs/football/family.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "common/status_macros.h"
#include "envs/football/spec.h"

namespace juggle::football {
namespace {

// Checks between fields; each field's own range is the schema's (proto/envs/football.proto).
absl::Status ValidateFootball(const config::FootballConfig& f, const SourceLocator& where) {
  auto fail = [&](const FieldPath& path, const std::string& rule) {
    return absl::InvalidArgumentError(absl::StrCat(where.Where(path), ": ", rule));
  };
  if (f.task() != config::KICK && f.task() != config::TRAP && f.task() != config::TRAP_KICK) {
    return fail({{"task"}}, "set the task: KICK, TRAP or TRAP_KICK");
  }
  if (f.task() == config::TRAP) return absl::OkStatus();  // the passes: FootballSpec (the model)
  if (f.task() == config::TRAP_KICK) {
    const config::TrapThenKick& z = f.trap_kick();
    if (z.zone_ahead_min_m() > z.zone_ahead_max_m()) {
      return fail({{"trap_kick"}, {"zone_ahead_min_m"}}, "must be <= trap_kick.zone_ahead_max_m");
    }
  }
  const config::KickTargets& k = f.kick();
  if (k.speed_min_mps() > k.speed_max_mps()) {
    return fail({{"kick"}, {"speed_min_mps"}}, "must be <= kick.speed_max_mps");
  }
  if (k.elevation_min_deg() > k.elevation_max_deg()) {
    return fail({{"kick"}, {"elevation_min_deg"}}, "must be <= kick.elevation_max_deg");
  }
  const double control_dt = f.sim_dt() * f.substeps();
  const config::KickMotion& m = f.motion();
  const double touch_latest = m.start_s() + m.backswing_s() + m.swing_s();
  if (f.max_episode_steps() * control_dt < touch_latest + f.settle_s() - 1e-9) {
    return fail({{"max_episode_steps"}},
                absl::StrCat(f.max_episode_steps(), " control steps (",
                             f.max_episode_steps() * control_dt,
                             " s) end before the scripted swing's end plus settle_s (",
                             touch_latest + f.settle_s(), " s)"));
  }
  return absl::OkStatus();
}

class FootballFamily final : public EnvFamily {
 public:
  std::string_view name() const override { return "football"; }
  config::RunConfig::FamilyCase config_case() const override {
    return config::RunConfig::kFootball;
  }
  absl::Status Prepare(LoadedConfig* loaded) const override {
    // No control graph: the empty graph keeps the walk and the wire format uniform.
    loaded->family_locator = loaded->root.Nested({{"football"}});
    return ValidateFootball(loaded->run.football(), loaded->family_locator);
  }
  absl::StatusOr<std::shared_ptr<const EnvSpec>> CreateSpec(
      const LoadedConfig& config, const std::string& model_mjb) const override {
    absl::StatusOr<std::shared_ptr<const FootballSpec>> spec =
        model_mjb.empty() ? FootballSpec::Create(config)
                          : FootballSpec::CreateFromCompiled(config, model_mjb);
    if (!spec.ok()) return spec.status();
    return std::shared_ptr<const EnvSpec>(*std::move(spec));
  }
  void ConfigureForEvaluation(double max_seconds, config::RunConfig* run) const override {
    // An episode is one kick, which ends itself (kicked, fell); `max_seconds` only shortens the
    // config's limit, so `juggle eval`'s 60-s default does not stretch a missed kick to a minute.
    config::FootballConfig* f = run->mutable_football();
    if (max_seconds > 0) {
      const int steps =
          static_cast<int>(std::ceil(max_seconds / (f->sim_dt() * f->substeps()) - 1e-9));
      f->set_max_episode_steps(std::min(f->max_episode_steps(), steps));
    }
  }
};

}  // namespace

const EnvFamily& Family() {
  static const FootballFamily family;
  return family;
}

}  // namespace juggle::football
