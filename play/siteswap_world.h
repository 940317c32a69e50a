// The two-arm toss runtime (envs/toss/juggler.h) as the live page plays it: the config's base
// controllers (and its policies, when the config trains residuals on them: none here) juggle
// a siteswap; the page chooses the next pattern (taken at the first beat not yet prepared for,
// through the shortest passage: JuggleSchedule::SwitchAt), sets the wind and pokes the highest
// ball in flight. A run ends at a drop or a missed beat; Restart starts the last chosen pattern
// again. Thread-compatible.
#ifndef JUGGLE_PLAY_SITESWAP_WORLD_H_
#define JUGGLE_PLAY_SITESWAP_WORLD_H_

#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "envs/env.h"
#include "envs/toss/juggler.h"
#include "envs/toss/spec.h"
#include "play/play_world.h"

namespace juggle::play {

class SiteswapWorld final : public PlayWorld {
 public:
  // INVALID_ARGUMENT for a spec of another family or a pattern that does not parse or that
  // the runtime cannot juggle.
  static absl::StatusOr<std::unique_ptr<SiteswapWorld>> Create(std::shared_ptr<const EnvSpec> spec,
                                                               const std::string& pattern,
                                                               uint64_t run_seed);

  std::string family() const override { return "toss"; }
  const mjModel* model() const override { return spec_->model(); }
  const mjData* data() const override { return juggler_->world().data(); }
  double control_dt() const override { return spec_->control_dt(); }
  void Restart(uint64_t seed) override;
  bool Step() override;
  absl::Status Poke(const std::array<double, 3>& impulse) override;
  // A siteswap: INVALID_ARGUMENT for one that does not parse, is invalid, has more balls than
  // the model or no passage from the pattern now in the air.
  absl::Status Choose(const std::string& siteswap) override;
  absl::Status SetWind(double newtons) override;
  nlohmann::json Options() const override;
  void AppendStatus(nlohmann::json* status) const override;

  const toss::TossJuggler& juggler() const { return *juggler_; }

 private:
  SiteswapWorld(std::shared_ptr<const toss::TossSpec> spec, toss::Siteswap pattern,
                uint64_t run_seed)
      : spec_(std::move(spec)), pattern_(std::move(pattern)), run_seed_(run_seed) {}

  std::shared_ptr<const toss::TossSpec> spec_;
  toss::Siteswap pattern_;  // the pattern chosen last (what a restart juggles)
  uint64_t run_seed_;
  std::unique_ptr<toss::TossJuggler> juggler_;
  double wind_ = 0;
  std::string outcome_;
  uint64_t seed_ = 0;
};

}  // namespace juggle::play

#endif  // JUGGLE_PLAY_SITESWAP_WORLD_H_
