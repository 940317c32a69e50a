// The TRAP_KICK task's switch from the trap to the kick (proto/envs/football.proto,
// TrapThenKick; docs/football.md, "Trap then kick"): whether the ball lies in the kick's zone.
// Pure functions of the spec and the physics.
#ifndef JUGGLE_ENVS_FOOTBALL_TRAP_KICK_H_
#define JUGGLE_ENVS_FOOTBALL_TRAP_KICK_H_

#include <mujoco/mujoco.h>

namespace juggle::football {

class FootballSpec;

// How far (m) the point (x, y) is outside the kick's zone in the ground plane (0 inside): the
// box ahead of the right foot's standing centre that TrapThenKick describes.
double KickZoneDistance(const FootballSpec& spec, double x, double y);

// The ball in `d` is in the kick's zone, on the turf (its centre at most zone_height_m above
// its contact height: a small hop may go on), horizontally slower than the limit, not rolling
// back toward the foot (faster than 0.05 m/s) and touching nothing of the character but the
// kicking foot (a trapped ball may rest against it): the kick may start.
bool BallKickable(const FootballSpec& spec, const mjData* d);

// Some body of the character touches the ball in `d`.
bool BallTouchesCharacter(const FootballSpec& spec, const mjData* d);

}  // namespace juggle::football

#endif  // JUGGLE_ENVS_FOOTBALL_TRAP_KICK_H_
