#include "planner/kick_memory_recorder.h"

#include "absl/strings/str_cat.h"
#include "envs/soccer_juggle/env.h"

namespace juggle::planner {

void KickMemoryRecorder::Act(const Env* const* envs, const float* obs, int n, float* actions) {
  for (int k = 0; k < n; ++k) {
    const auto* env = dynamic_cast<const soccer_juggle::JuggleEnv*>(envs[k]);
    if (env == nullptr) continue;
    Flight& f = flights_[envs[k]];
    if (env->steps() <= f.last_step) f = Flight{};  // a new episode
    f.last_step = env->steps();
    const std::optional<KickContext> context = KickContextOf(*env);
    const bool released = context.has_value();
    if (released && !f.released) {
      const std::vector<double>& decision = planner_->PlannerFor(*env).last_replan().decision;
      if (f.incoming.has_value() && static_cast<int>(decision.size()) == kKickVariables) {
        KickDecision kick;
        std::copy(decision.begin(), decision.end(), kick.begin());
        rows_.push_back(FormatKickMemoryRow(*f.incoming, kick));
      }
      f.incoming = context;
    }
    f.released = released;
  }
  inner_->Act(envs, obs, n, actions);
}

std::string KickMemoryRecorder::FileText() const {
  std::string text =
      "# juggle kick memory (planner/soccer_juggle/kick_memory.h): per kick, the incoming ball's\n"
      "# timing_s landing_dx_m landing_dy_m apex_m root_vx root_vy, then the kick variables\n"
      "# timing_s hip abduction knee ankle the planner executed for it\n";
  for (const std::string& row : rows_) absl::StrAppend(&text, row);
  return text;
}

}  // namespace juggle::planner
