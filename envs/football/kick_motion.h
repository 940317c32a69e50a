// The scripted kick the football env's PD tracks (proto/envs/football.proto, KickMotion): the
// standing pose with, where configured, a step of the left foot into the kick, then the right
// leg's back-swing, swing and recovery as functions of the kick's clock (the knee's opening may
// lag the hip's: KickMotion.knee_lag), and its changes by the planner's kick variables (timing,
// hip, abduction, knee, ankle). Pure functions; allocation-free.
#ifndef JUGGLE_ENVS_FOOTBALL_KICK_MOTION_H_
#define JUGGLE_ENVS_FOOTBALL_KICK_MOTION_H_

#include <mujoco/mujoco.h>

#include "envs/football/spec.h"

namespace juggle::football {

// Changes of the scripted kick: `timing_s` earlier (s), and added to the forward swing's hip
// pitch, the hip's abduction (rad, + moves the right foot outward, −y), the knee's opening and
// the ankle's pitch (rad). Zero: the configured kick.
struct KickAdjust {
  double timing_s = 0, hip = 0, abduction = 0, knee = 0, ankle = 0;
};

// The kick's segment times (s of the kick's clock): with a step (KickMotion.step), the weight
// shift from `step` to `step_swing`, the left foot's swing from there to `plant` and the
// weight's transfer onto it from there to `start` (without one all four are equal);
// back-swing from `start` to `swing`, swing to `recover`, recovery to `end`. The timing
// variable moves them all.
struct KickTimes {
  double step = 0, step_swing = 0, plant = 0, start = 0, swing = 0, recover = 0, end = 0;
};
KickTimes KickTimesOf(const config::KickMotion& motion, const KickAdjust& adjust);

// The hips' pitch of a step (rad): each hip takes half the angle a step of `length_m` between
// two straight legs of `leg_length_m` opens (0 without a step).
double StepHipPitch(double length_m, double leg_length_m);
// The legs' roll (rad) that moves the pelvis `hip_half_width_m` sideways over one foot.
double StepHipRoll(double hip_half_width_m, double leg_length_m);

// During a step's weight shift, the share of it done at kick-clock `t` (0 to 1, eased as the
// legs are); 1 after it, 0 before it or without a step.
double StepShiftShare(const KickTimes& times, double t);

// During a step's transfer, the share of it done at kick-clock `t` (0 to 1, eased); 1 after it,
// 0 before it or without a transfer.
double StepTransferShare(const KickTimes& times, double t);

// During a step's swing, how far ahead of the right (standing) foot the stance balance's centre
// of mass target moves at kick-clock `t` (m): from 0 to half the step as the pelvis moves on
// over the swing, eased as the legs are; 0 without a step or outside its swing.
double StepComAhead(const config::KickMotion& motion, const KickTimes& times, double t);

// Where a step's foot is steered: the left hip's pitch and roll (rad, about the pelvis's z and
// x; + roll moves the foot toward world +y) that point a straight left leg from where its hip is
// at a point on the floor, and the pelvis's own pitch and roll from upright (so the ankle can
// hold the sole level in the world).
struct StepPlacement {
  double hip_pitch = 0, hip_roll = 0, pelvis_pitch = 0, pelvis_roll = 0;
  double toe_down = 0;  // the ankle's extra plantar flexion (rad; KickStep.toe_down)
};

// The placement at kick-clock `t` from the env's physics: before the plant toward the step's
// landing point (the left foot's standing place, length_m ahead and outward_m out); from the
// plant on toward where the left foot is, so that the planted foot stays put as the pelvis
// moves over it. Small-angle composition of the pelvis's and the hip's rotations.
StepPlacement StepPlacementOf(const FootballSpec& spec, const mjData& data, const KickTimes& times,
                              double t);

// Writes the reference pose at kick-clock `t` (s) into `pose`. With `place` (a step's, from
// StepPlacementOf) the left leg is steered by it over the second half of the step's swing and
// through the back-swing, the scripted angles blended into the placed ones; without it the
// script alone.
void KickReferencePose(const FootballSpec& spec, double t, const KickAdjust& adjust,
                       CharacterPose* pose, const StepPlacement* place = nullptr);

}  // namespace juggle::football

#endif  // JUGGLE_ENVS_FOOTBALL_KICK_MOTION_H_
