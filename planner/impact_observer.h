// Measures the impact acceleration (ImpactTracker, planner/soccer_juggle/impact_tracker.h) of every kick an
// evaluation executes, by wrapping the controller that acts: each Act call sees every running
// env after its previous step, which is when the tracker looks. What `juggle eval` reports as
// impact_*. Envs that are not soccer envs pass through unmeasured. The step that ends an
// episode is never acted on, so a touch in it is not measured. Thread-compatible.
#ifndef JUGGLE_PLANNER_IMPACT_OBSERVER_H_
#define JUGGLE_PLANNER_IMPACT_OBSERVER_H_

#include <string>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "eval/controller.h"
#include "planner/soccer_juggle/impact_tracker.h"

namespace juggle::planner {

class ImpactObservingController final : public Controller {
 public:
  // `inner` acts and must outlive this controller.
  explicit ImpactObservingController(Controller* inner) : inner_(inner) {}
  void Act(const Env* const* envs, const float* obs, int n, float* actions) override;
  std::string name() const override { return inner_->name(); }
  // The measured kicks' accelerations (m/s²), in the order they were measured.
  const std::vector<double>& accelerations() const { return accelerations_; }
  // The soccer envs seen (0: nothing to report).
  int envs_measured() const { return static_cast<int>(trackers_.size()); }

 private:
  Controller* inner_;
  // One tracker per env seen, begun at the first Act that sees it.
  absl::flat_hash_map<const Env*, ImpactTracker> trackers_;
  std::vector<double> accelerations_;
};

// The measured accelerations as key=value pairs for the summary line: " impact_kicks=N" and,
// when N > 0, impact_p10/median/p90 (m/s²) and impact_in_band (the fraction in [lo, hi]).
std::string ImpactSummary(const std::vector<double>& accelerations, double lo, double hi);

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_IMPACT_OBSERVER_H_
