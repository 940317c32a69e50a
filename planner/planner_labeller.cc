#include "planner/planner_labeller.h"

#include <memory>
#include <utility>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/str_cat.h"
#include "planner/planner_controller.h"
#include "planner/rollout_pool.h"
#include "planner/soccer_planner.h"

namespace juggle {
namespace {

using ::juggle::RolloutPool;
using planner::SoccerPlanner;

class PlannerLabeller final : public Labeller {
 public:
  PlannerLabeller(std::shared_ptr<const soccer_juggle::JuggleSpec> spec,
                  const config::PlannerConfig& config, int worker)
      : spec_(std::move(spec)), config_(config), pool_(spec_, config_.threads()),
        worker_(worker) {}

  absl::Status Label(const Env& env, float* action) override {
    const auto* soccer = dynamic_cast<const soccer_juggle::JuggleEnv*>(&env);
    if (soccer == nullptr) {
      return absl::InvalidArgumentError("the planner labels soccer_juggle envs only");
    }
    auto [it, added] = planner_of_.try_emplace(&env, static_cast<int>(planners_.size()));
    if (added) {
      const uint64_t stream = (uint64_t(worker_) << 16) + planners_.size();
      planners_.push_back(std::make_unique<SoccerPlanner>(spec_, config_, &pool_, stream));
    }
    return planners_[it->second]->Act(*soccer, action);
  }

 private:
  std::shared_ptr<const soccer_juggle::JuggleSpec> spec_;
  config::PlannerConfig config_;
  ::juggle::RolloutPool pool_;
  int worker_;
  std::vector<std::unique_ptr<SoccerPlanner>> planners_;
  absl::flat_hash_map<const Env*, int> planner_of_;
};

}  // namespace

absl::StatusOr<std::unique_ptr<Labeller>> MakePlannerLabeller(std::shared_ptr<const EnvSpec> spec,
                                                              const LoadedConfig& config,
                                                              int worker) {
  if (absl::Status s = planner::ValidatePlannerConfig(config); !s.ok()) return s;
  auto soccer = std::dynamic_pointer_cast<const soccer_juggle::JuggleSpec>(spec);
  if (soccer == nullptr) {
    return absl::InvalidArgumentError(absl::StrCat(
        "imitation: the planner labels soccer_juggle envs, not ", spec->family()));
  }
  return std::unique_ptr<Labeller>(
      std::make_unique<PlannerLabeller>(std::move(soccer), config.run.planner(), worker));
}

}  // namespace juggle
