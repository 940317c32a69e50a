// The scripted kick the football env's PD tracks (proto/envs/football.proto, KickMotion): the
// standing pose with the right leg's back-swing, swing and recovery as functions of the
// episode's time (the knee's opening may lag the hip's: KickMotion.knee_lag), and its changes by
// the planner's kick variables (timing, hip, abduction, knee, ankle). Pure functions;
// allocation-free.
#ifndef JUGGLE_ENVS_FOOTBALL_KICK_MOTION_H_
#define JUGGLE_ENVS_FOOTBALL_KICK_MOTION_H_

#include "envs/football/spec.h"

namespace juggle::football {

// Changes of the scripted kick: `timing_s` earlier (s), and added to the forward swing's hip
// pitch, the hip's abduction (rad, + moves the right foot outward, −y), the knee's opening and
// the ankle's pitch (rad). Zero: the configured kick.
struct KickAdjust {
  double timing_s = 0, hip = 0, abduction = 0, knee = 0, ankle = 0;
};

// The kick's segment times (s of the episode): back-swing from `start` to `swing`, swing to
// `recover`, recovery to `end`.
struct KickTimes {
  double start = 0, swing = 0, recover = 0, end = 0;
};
KickTimes KickTimesOf(const config::KickMotion& motion, const KickAdjust& adjust);

// Writes the reference pose at episode time `t` (s) into `pose`.
void KickReferencePose(const FootballSpec& spec, double t, const KickAdjust& adjust,
                       CharacterPose* pose);

}  // namespace juggle::football

#endif  // JUGGLE_ENVS_FOOTBALL_KICK_MOTION_H_
