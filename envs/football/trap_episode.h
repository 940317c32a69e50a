// The TRAP task's episode (proto/envs/football.proto, TrapPasses; docs/football.md, "The trap"):
// the designated parts and the arms as the model's bodies, the pass drawn for an episode, and
// the bookkeeping of touches that scores a trap with PhysicsFC's metrics (metrics.h). Used by
// FootballEnv (env.h); pure functions of the spec, the physics and the episode's state.
#ifndef JUGGLE_ENVS_FOOTBALL_TRAP_EPISODE_H_
#define JUGGLE_ENVS_FOOTBALL_TRAP_EPISODE_H_

#include <array>
#include <vector>

#include <mujoco/mujoco.h>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "common/rng.h"
#include "envs/football/metrics.h"
#include "envs/football/passes.h"
#include "envs/geom_extent.h"
#include "proto/envs/football.pb.h"

namespace juggle::football {

class FootballSpec;

constexpr int kTrapParts = 5;  // indexed by config::TrapPart (0 unused)
constexpr int kRelativeSpeedFrames = 5;  // RBSPT's frames after the touch (seed 002)

// Where the parts are in the model.
struct TrapBodies {
  std::array<int, kTrapParts> geom{};  // -1: the model lacks it
  std::array<int, kTrapParts> body{};
  std::array<GeomBounds, kTrapParts> bounds{};  // envs/geom_extent.h: a boot's box, not its hull
  std::array<std::array<double, 3>, kTrapParts> standing_centre{};  // the bounds' centre, standing
  std::vector<char> is_arm;  // per body: upper arm, forearm or hand
};

// Resolves the parts in `model` standing in `standing_qpos` (the character's nq values).
// INVALID_ARGUMENT "trap.parts[i]: the model has no geom 'head'" (at the config's field) for a
// drawn part the model lacks.
absl::StatusOr<TrapBodies> ResolveTrapBodies(const mjModel* model, const double* standing_qpos,
                                            const config::TrapPasses& passes,
                                            const SourceLocator& where);

// A lob to the foot meets it this much higher than it stands (m): a cushion control in the air
// (a ball landing on a grounded foot would meet the turf as early).
constexpr double kFootLobLift = 0.2;

// The height of a lob's meeting point for `part` before its random raise: the part's standing
// centre (the foot's lifted by kFootLobLift).
double LobMeetingHeight(const TrapBodies& bodies, config::TrapPart part);

// The parts lobs are drawn from (TrapPasses.parts, or all four).
std::vector<config::TrapPart> LobParts(const config::TrapPasses& passes);

// INVALID_ARGUMENT naming the field: a range out of order, or lobs that cannot come down
// through the highest drawn part's meeting point (the fastest, steepest launch peaks below it).
absl::Status ValidateTrapPasses(const config::TrapPasses& passes, const SourceLocator& where,
                                double highest_part_m, double ball_radius, double g);

struct TrapEpisode {
  config::TrapPart part = config::FOOT;
  Pass pass;                      // as at the episode's start: meet_s is episode time
  double meet_point[3] = {0, 0, 0};
  double spin[3] = {0, 0, 0};     // rad/s at the start
  int first_body = -1;            // the character's body that touched the ball first
  double first_touch_s = -1;
  bool turf_before_touch = false; // the ball met the turf before the character
  bool arms_touched = false;
  TrapAttempt attempt;            // scored at the end
  double end_distance_m = -1;     // ball to root, horizontally, at the end (-1: no end yet)
  bool settled = false;
};

// Draws the episode's part and pass (the same number of Rng draws per apex retry).
// REQUIRES: the spec's config passed ValidateTrapPasses.
TrapEpisode DrawTrapEpisode(const FootballSpec& spec, Rng& rng);

// Puts the ball where `episode` starts it, with its velocity and spin (qpos/qvel of `d`).
void PlaceTrapBall(const FootballSpec& spec, const TrapEpisode& episode, mjData* d);

// After a physics step: the first touch, the turf, the arms.
void NoteTrapContacts(const FootballSpec& spec, const mjData* d, TrapEpisode* episode);

// After a control step: the relative speed's frames after the touch, and the trap's end
// (settle_s after the touch), scored into `episode->attempt`.
void AfterTrapControlStep(const FootballSpec& spec, const mjData* d, TrapEpisode* episode);

// Ends the trap now (as AfterTrapControlStep does settle_s after the touch): the end distance
// and the attempt's flags. TRAP_KICK ends it at the switch to the kick. REQUIRES: a touch.
void EndTrap(const FootballSpec& spec, const mjData* d, TrapEpisode* episode);

}  // namespace juggle::football

#endif  // JUGGLE_ENVS_FOOTBALL_TRAP_EPISODE_H_
