#include "envs/football/kick_motion.h"

#include <algorithm>

#include "envs/humanoid/pose.h"

namespace juggle::football {
namespace {

// The right leg's angles at a key of the motion.
struct LegKey {
  double hip = 0, abduction = 0, knee = 0, ankle = 0;
};

double Smoothstep(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * (3 - 2 * u);
}

LegKey Blend(const LegKey& a, const LegKey& b, double u) {
  const double s = Smoothstep(u);
  return {a.hip + s * (b.hip - a.hip), a.abduction + s * (b.abduction - a.abduction),
          a.knee + s * (b.knee - a.knee), a.ankle + s * (b.ankle - a.ankle)};
}

}  // namespace

KickTimes KickTimesOf(const config::KickMotion& m, const KickAdjust& adjust) {
  KickTimes t;
  t.start = m.start_s() - adjust.timing_s;
  t.swing = t.start + m.backswing_s();
  t.recover = t.swing + m.swing_s();
  t.end = t.recover + m.recover_s();
  return t;
}

void KickReferencePose(const FootballSpec& spec, double t, const KickAdjust& adjust,
                       CharacterPose* pose) {
  *pose = spec.standing_pose();
  const config::KickMotion& m = spec.football().motion();
  const KickTimes times = KickTimesOf(m, adjust);
  if (t <= times.start || t >= times.end) return;
  const LegKey rest;
  const LegKey back{-m.hip_back(), adjust.abduction, -m.knee_back(), m.ankle_pitch() + adjust.ankle};
  const LegKey forward{m.hip_forward() + adjust.hip, adjust.abduction,
                       -(m.knee_forward() + adjust.knee), m.ankle_pitch() + adjust.ankle};
  LegKey leg;
  if (t < times.swing) {
    leg = Blend(rest, back, (t - times.start) / (times.swing - times.start));
  } else if (t < times.recover) {
    const double u = (t - times.swing) / (times.recover - times.swing);
    leg = Blend(back, forward, u);
    // The knee's own ease, lagging the hip's by knee_lag of the swing.
    const double lag = m.knee_lag();
    if (lag > 0) leg.knee = Blend(back, forward, (u - lag) / (1 - lag)).knee;
  } else {
    leg = Blend(forward, rest, (t - times.recover) / (times.end - times.recover));
  }
  const humanoid::Joints& joints = spec.joints();
  // Flexion about z and abduction about x (−x moves the right limb toward +z, outward).
  const double hip[3] = {-leg.abduction, 0, leg.hip};
  humanoid::SetBallJointRotation(joints, humanoid::kRightHip, hip, pose);
  humanoid::SetHinge(joints, humanoid::kRightKnee, leg.knee, pose);
  const double ankle[3] = {0, 0, leg.ankle};
  humanoid::SetBallJointRotation(joints, humanoid::kRightAnkle, ankle, pose);
}

}  // namespace juggle::football
