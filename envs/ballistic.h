// A ball in free flight under gravity alone (the models have no air drag): when it comes down
// through a height, where, and its apex. The one home of these formulas for every family
// (soccer: the kick feedback and the kick reward; toss: a throw's landing; the planner's kick
// outcomes). Pure functions, allocation-free.
#ifndef JUGGLE_ENVS_BALLISTIC_H_
#define JUGGLE_ENVS_BALLISTIC_H_

#include <algorithm>
#include <cmath>

namespace juggle {

// Seconds until a ball with vertical velocity vz, under gravity g > 0, is `drop` metres below
// its current height on its way down: the later root of drop + vz·t − g·t²/2 = 0. A negative
// drop is a height above the ball; NaN when the flight never reaches it.
inline double SecondsToFall(double vz, double drop, double g) {
  return (vz + std::sqrt(vz * vz + 2 * g * drop)) / g;
}

struct BallisticCrossing {
  double t = 0;         // s from now (0 if the ball is already below the height)
  double x = 0, y = 0;  // position at that time
};

// The descending crossing of height `h` by a ball at (x, y, z) with velocity (vx, vy, vz)
// under gravity g > 0 (the later root of z + vz·t − g·t²/2 = h). A ball below h that rises
// through it crosses on its way back down; one below h that is falling or never reaches h
// gives t = 0 at its current position.
inline BallisticCrossing DescendingCrossing(const double pos[3], const double vel[3], double g,
                                            double h) {
  const double drop = pos[2] - h;
  double t = 0.0;
  if (drop > 0 || vel[2] > 0) {
    const double later = SecondsToFall(vel[2], drop, g);  // NaN: h is never reached
    if (std::isfinite(later)) t = std::max(later, 0.0);
  }
  return {t, pos[0] + vel[0] * t, pos[1] + vel[1] * t};
}

// The highest point of the flight: z + vz²/(2g) going up, z coming down.
inline double ApexHeight(double z, double vz, double g) {
  return vz > 0 ? z + vz * vz / (2 * g) : z;
}

}  // namespace juggle

#endif  // JUGGLE_ENVS_BALLISTIC_H_
