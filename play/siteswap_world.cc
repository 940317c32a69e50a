#include "play/siteswap_world.h"

#include <utility>

#include "absl/strings/str_cat.h"
#include "common/rng.h"

namespace juggle::play {
namespace {

// The patterns the page offers: the evaluation's (docs/toss.md), in its order.
const char* const kPatterns[] = {"3", "4", "5", "53", "441", "531", "6", "7"};
constexpr double kMaxWind = 1.0;  // N: the base holds ~0.75 N (docs/results.md)

}  // namespace

absl::StatusOr<std::unique_ptr<SiteswapWorld>> SiteswapWorld::Create(
    std::shared_ptr<const EnvSpec> spec, const std::string& pattern, uint64_t run_seed) {
  auto toss_spec = std::dynamic_pointer_cast<const toss::TossSpec>(spec);
  if (toss_spec == nullptr) {
    return absl::InvalidArgumentError(
        absl::StrCat("the siteswap world needs a toss config, not ", spec->family()));
  }
  absl::StatusOr<toss::Siteswap> p = toss::Siteswap::Parse(pattern);
  if (!p.ok()) return p.status();
  std::unique_ptr<SiteswapWorld> world(new SiteswapWorld(toss_spec, *p, run_seed));
  world->wind_ = toss_spec->toss().wind_force();
  // A first run to find out whether the runtime takes the pattern.
  toss::JugglerOptions options;
  options.seed = run_seed;
  options.max_throws = 1 << 30;
  absl::StatusOr<std::unique_ptr<toss::TossJuggler>> juggler =
      toss::TossJuggler::Create(toss_spec, toss::JuggleSchedule(*p), {}, options);
  if (!juggler.ok()) return juggler.status();
  world->Restart(0);
  return world;
}

void SiteswapWorld::Restart(uint64_t seed) {
  seed_ = seed;
  toss::JugglerOptions options;
  // Start s of the play page is `juggle toss --seed` run_seed + s.
  options.seed = run_seed_ + seed;
  options.max_throws = 1 << 30;
  juggler_ = *toss::TossJuggler::Create(spec_, toss::JuggleSchedule(pattern_), {}, options);
  juggler_->mutable_world()->set_wind(wind_);
  outcome_.clear();
}

bool SiteswapWorld::Step() {
  if (!outcome_.empty()) return false;
  if (juggler_->Step()) return true;
  outcome_ = toss::JuggleEndName(juggler_->result().end);
  return false;
}

absl::Status SiteswapWorld::Poke(const std::array<double, 3>& impulse) {
  const toss::TossWorld& world = juggler_->world();
  int ball = -1;
  for (int b = 0; b < toss::kTossBalls; ++b) {
    if (world.mode(b) != toss::BallMode::kFree) continue;
    if (ball < 0 || world.ball_position(b).z > world.ball_position(ball).z) ball = b;
  }
  if (ball < 0) return absl::FailedPreconditionError("no ball is in the air to poke");
  const mjModel* m = spec_->model();
  ApplyImpulse(m, juggler_->mutable_world()->data(), m->dof_bodyid[spec_->ball(ball).dof_x],
               impulse);
  return absl::OkStatus();
}

absl::Status SiteswapWorld::Choose(const std::string& siteswap) {
  absl::StatusOr<toss::Siteswap> next = toss::Siteswap::Parse(siteswap);
  if (!next.ok()) return absl::InvalidArgumentError(next.status().message());
  if (!outcome_.empty()) {  // between runs: the next run juggles it from the start
    absl::StatusOr<std::unique_ptr<toss::TossJuggler>> probe = toss::TossJuggler::Create(
        spec_, toss::JuggleSchedule(*next), {}, toss::JugglerOptions{});
    if (!probe.ok()) return absl::InvalidArgumentError(probe.status().message());
    pattern_ = *next;
    return absl::OkStatus();
  }
  absl::StatusOr<int> beat = juggler_->SwitchPattern(*next);
  if (!beat.ok()) return absl::InvalidArgumentError(beat.status().message());
  pattern_ = *next;
  return absl::OkStatus();
}

absl::Status SiteswapWorld::SetWind(double newtons) {
  if (std::abs(newtons) > kMaxWind) {
    return absl::InvalidArgumentError(
        absl::StrCat("wind ", newtons, " N: the page allows up to ", kMaxWind, " N"));
  }
  wind_ = newtons;
  juggler_->mutable_world()->set_wind(newtons);
  return absl::OkStatus();
}

nlohmann::json SiteswapWorld::Options() const {
  nlohmann::json patterns = nlohmann::json::array();
  for (const char* p : kPatterns) patterns.push_back(p);
  return {{"kind", "siteswap"}, {"controller", "base"}, {"patterns", patterns},
          {"max_wind", kMaxWind}};
}

void SiteswapWorld::AppendStatus(nlohmann::json* status) const {
  nlohmann::json& s = *status;
  const toss::JuggleRunResult& r = juggler_->result();
  s["seed"] = seed_;
  s["juggles"] = r.good_throws;
  s["throws"] = r.throws;
  s["catches"] = r.catches;
  s["pattern"] = pattern_.ToString();
  s["schedule"] = juggler_->schedule().Name();
  s["wind"] = wind_;
  if (!outcome_.empty()) s["outcome"] = outcome_;
}

}  // namespace juggle::play
