// What the live page plays (`juggle play`, docs/play.md): one simulated world stepped by the
// session's thread (play/play_session.h). Two kinds: an env of any family driven by a
// controller (play/env_world.h: soccer juggling, with the control graph's skill choice) and the
// two-arm toss runtime (play/siteswap_world.h: the siteswap chosen live, wind). Thread-compatible:
// the session calls it from its one thread.
#ifndef JUGGLE_PLAY_PLAY_WORLD_H_
#define JUGGLE_PLAY_PLAY_WORLD_H_

#include <array>
#include <cstdint>
#include <string>

#include <mujoco/mujoco.h>

#include "absl/status/status.h"
#include "nlohmann/json.hpp"

namespace juggle::play {

class PlayWorld {
 public:
  virtual ~PlayWorld() = default;
  virtual std::string family() const = 0;
  virtual const mjModel* model() const = 0;
  // The state now (bodies' world transforms valid after every Step and Restart).
  virtual const mjData* data() const = 0;
  // Simulated seconds per Step.
  virtual double control_dt() const = 0;
  // Starts an episode from start `seed` (the same seed, the same start).
  virtual void Restart(uint64_t seed) = 0;
  // One control step; false once the episode is over (then only Restart).
  virtual bool Step() = 0;
  // Adds `impulse` (N·s, world axes) at the centre of the ball in play (the highest, with
  // several). FAILED_PRECONDITION when no ball is in play.
  virtual absl::Status Poke(const std::array<double, 3>& impulse) = 0;
  // The skill (soccer: a graph node) or siteswap (toss) to take at the next allowed
  // transition; "walk" (soccer) gives the choice back to the adaptive walk. INVALID_ARGUMENT
  // with a message for the page when the world cannot take it.
  virtual absl::Status Choose(const std::string& name) = 0;
  // Wind on the balls in flight (N along x); FAILED_PRECONDITION for worlds without wind.
  virtual absl::Status SetWind(double newtons) {
    return absl::FailedPreconditionError("this world has no wind");
  }
  // What the page offers, once: {"kind": "graph" | "siteswap", ...} (graph: nodes, edges and
  // the steerable nodes; siteswap: the patterns and the wind limit).
  virtual nlohmann::json Options() const = 0;
  // The state the page shows with every frame: juggles, the node or pattern, the episode's
  // outcome once over, and (under the planner) its last re-plan's cost.
  virtual void AppendStatus(nlohmann::json* status) const = 0;
};

// Adds `impulse` at the centre of mass of `body`: Δqvel = M⁻¹ Jᵀ p, with the mass matrix of
// the last step (exact for a free ball, whose mass matrix block is its mass).
void ApplyImpulse(const mjModel* model, mjData* data, int body,
                  const std::array<double, 3>& impulse);

}  // namespace juggle::play

#endif  // JUGGLE_PLAY_PLAY_WORLD_H_
