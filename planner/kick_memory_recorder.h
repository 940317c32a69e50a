// Records a memory of solved kicks (planner/soccer_juggle/kick_memory.h) from an evaluation
// that the planner drives, by wrapping the controller that acts: each Act call sees every
// running env after its previous step. At the first step after a kick leaves the foot it pairs
// the context of the ball that kick met (taken at the previous release) with the kick variables
// of the planner's last plan before the release (its current cycle's set, the one that kicked),
// and takes the context of the new flight. What `juggle eval --kick-memory-out=FILE` writes.
// Envs that are not soccer envs pass through. Thread-compatible.
#ifndef JUGGLE_PLANNER_KICK_MEMORY_RECORDER_H_
#define JUGGLE_PLANNER_KICK_MEMORY_RECORDER_H_

#include <optional>
#include <string>
#include <vector>

#include "absl/container/flat_hash_map.h"
#include "eval/controller.h"
#include "planner/planner_controller.h"
#include "planner/soccer_juggle/kick_memory.h"

namespace juggle::planner {

class KickMemoryRecorder final : public Controller {
 public:
  // `inner` acts; `planner` is the planner controller inside it (may be `inner` itself). Both
  // must outlive the recorder.
  KickMemoryRecorder(Controller* inner, PlannerController* planner)
      : inner_(inner), planner_(planner) {}
  void Act(const Env* const* envs, const float* obs, int n, float* actions) override;
  std::string name() const override { return inner_->name(); }

  // The rows recorded so far, in the order their kicks were released (FormatKickMemoryRow).
  const std::vector<std::string>& rows() const { return rows_; }
  // The memory file: a comment saying what the columns are, then the rows.
  std::string FileText() const;

 private:
  struct Flight {
    int last_step = -1;
    bool released = false;                // the ball was in free flight at the last look
    std::optional<KickContext> incoming;  // the context of the ball the next kick meets
  };
  Controller* inner_;
  PlannerController* planner_;
  absl::flat_hash_map<const Env*, Flight> flights_;
  std::vector<std::string> rows_;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_KICK_MEMORY_RECORDER_H_
