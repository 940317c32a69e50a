#include "planner/impact_observer.h"

#include <cmath>

#include "absl/strings/str_format.h"
#include "envs/soccer_juggle/env.h"
#include "eval/summary.h"

namespace juggle::planner {

void ImpactObservingController::Act(const Env* const* envs, const float* obs, int n,
                                    float* actions) {
  for (int k = 0; k < n; ++k) {
    const auto* env = dynamic_cast<const soccer_juggle::JuggleEnv*>(envs[k]);
    if (env == nullptr) continue;
    auto [it, is_new] = trackers_.try_emplace(envs[k]);
    if (is_new) {
      it->second.Begin(*env);
      continue;
    }
    const double a = it->second.AfterStep(*env);
    if (std::isfinite(a)) accelerations_.push_back(a);
  }
  inner_->Act(envs, obs, n, actions);
}

std::string ImpactSummary(const std::vector<double>& a, double lo, double hi) {
  std::string out = absl::StrFormat(" impact_kicks=%d", static_cast<int>(a.size()));
  if (a.empty()) return out;
  int in_band = 0;
  for (double x : a) in_band += (x >= lo && x <= hi) ? 1 : 0;
  return out + absl::StrFormat(" impact_p10=%.2f impact_median=%.2f impact_p90=%.2f "
                               "impact_in_band=%.3f",
                               Percentile(a, 0.1), Percentile(a, 0.5), Percentile(a, 0.9),
                               static_cast<double>(in_band) / a.size());
}

}  // namespace juggle::planner
