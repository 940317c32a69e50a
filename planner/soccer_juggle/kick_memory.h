// A memory of solved kicks (issue 48, a learned proposal for the next kick's variables): rows of
// (the incoming ball's context, the kick variables the planner executed for it), recorded from
// the planner's own evaluations (`juggle eval --kick-memory-out=FILE`) and read by the soccer
// task (SoccerJugglePlanning.kick_memory), which seeds the search after each release with the
// variables of the nearest remembered contexts. The seeds take the place of random candidates
// in the first iteration, so they cost no rollouts; the search still chooses by simulated cost.
//
// A context is taken while the ball flies from one kick to the next contact: the ballistic
// crossing of the next contact height against the phase clock's nominal contact (timing, s) and
// the node's ball target (dx, dy, m; PredictKickOutcome in planner/soccer_juggle/cost.h), the apex
// error (m) and the root's horizontal velocity (m/s). Distances are measured in units of the
// cost's scales (timing_scale_s, landing_scale, apex_scale, com_speed_scale).
//
// The file is text: '#' comments, then one row per kick of 11 numbers: the 6 context values
// in the order above and the 5 kick variables (timing s, hip, abduction, knee, ankle rad).
#ifndef JUGGLE_PLANNER_SOCCER_JUGGLE_KICK_MEMORY_H_
#define JUGGLE_PLANNER_SOCCER_JUGGLE_KICK_MEMORY_H_

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "envs/soccer_juggle/env.h"
#include "planner/soccer_juggle/plan.h"
#include "proto/planner.pb.h"

namespace juggle::planner {

constexpr int kKickContextSize = 6;
using KickContext = std::array<double, kKickContextSize>;
using KickDecision = std::array<double, kKickVariables>;

// The context of the kick the ball is flying to, or none when the ball is not in free flight
// after a touch of this cycle (on the body, coming down to this cycle's contact, or headed
// nowhere the graph allows).
std::optional<KickContext> KickContextOf(const soccer_juggle::JuggleEnv& env);

// One row of the memory file ("%.6g" values separated by spaces, and a newline).
std::string FormatKickMemoryRow(const KickContext& context, const KickDecision& decision);

class KickMemory {
 public:
  // Reads `path` (format above). INVALID_ARGUMENT "path:line: ..." for a row that is not 11
  // finite numbers; NOT_FOUND for a file that cannot be read; an empty memory is an error too.
  // `cost` gives the context's scales.
  static absl::StatusOr<KickMemory> Load(const std::string& path, const config::PlannerCost& cost);
  // From rows in memory (tests), with the same scales.
  KickMemory(std::vector<std::pair<KickContext, KickDecision>> rows,
             const config::PlannerCost& cost);

  // The decisions of the `k` rows nearest to `context` (scaled Euclidean distance), nearest
  // first; ties keep file order. At most size() of them.
  std::vector<KickDecision> Nearest(const KickContext& context, int k) const;
  int size() const { return static_cast<int>(rows_.size()); }

 private:
  KickContext scales_{};
  std::vector<std::pair<KickContext, KickDecision>> rows_;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_SOCCER_JUGGLE_KICK_MEMORY_H_
