#include "envs/soccer_juggle/reference_pose.h"

#include <algorithm>
#include <cmath>

#include "envs/humanoid/pose.h"

namespace juggle::soccer_juggle {

const double kUprightQuat[4] = {M_SQRT1_2, M_SQRT1_2, 0, 0};

double RotationSin2(const double* a, const double* b) {
  const double dot = mju_dot(a, b, 4);
  return std::max(0.0, 1.0 - dot * dot);
}

void SetBallJointRotation(const JuggleSpec& spec, JointId j, const double rotvec[3],
                          CharacterPose* pose) {
  humanoid::SetBallJointRotation(spec.joints(), j, rotvec, pose);
}

void SetBallJointAxisRotation(const JuggleSpec& spec, JointId j, int axis, double angle,
                              CharacterPose* pose) {
  double rotvec[3] = {0, 0, 0};
  rotvec[axis] = angle;
  SetBallJointRotation(spec, j, rotvec, pose);
}

void SetHinge(const JuggleSpec& spec, JointId j, double angle, CharacterPose* pose) {
  humanoid::SetHinge(spec.joints(), j, angle, pose);
}

CharacterPose StandingPose(const JuggleSpec& spec) {
  CharacterPose pose = spec.rest_pose();
  pose[0] = 0;
  pose[1] = 0;
  pose[2] = spec.env().root_height();
  std::copy(kUprightQuat, kUprightQuat + 4, pose.begin() + 3);
  return pose;
}

namespace {

constexpr int kX = 0;
constexpr int kZ = 2;

// The swing's share of its peak at phase φ in [0, 1) (config::SwingProfile).
double SwingShape(config::SwingProfile profile, double phi) {
  const double sine = std::sin(M_PI * phi);
  switch (profile) {
    case config::RAISED_COSINE:
      return sine * sine;
    case config::FLAT_TOP: {
      const double cosine = std::cos(M_PI * phi);
      return 1 - cosine * cosine * cosine * cosine;
    }
    default:
      return sine;
  }
}

// Tilting the stance leg toward the kicking side moves the pelvis over the stance foot: a
// rotation by −a about x tilts the limb toward +z (the character's right).
void RollStanceLeg(const JuggleSpec& spec, bool kick_left, double stance_roll,
                   CharacterPose* pose) {
  const double roll = kick_left ? stance_roll : -stance_roll;
  SetBallJointAxisRotation(spec, kick_left ? kRightHip : kLeftHip, kX, roll, pose);
  SetBallJointAxisRotation(spec, kick_left ? kRightAnkle : kLeftAnkle, kX, -roll, pose);
}

void LegSwingPose(const JuggleSpec& spec, const config::LegSwing& g, const SwingAdjust& adjust,
                  double phase, CharacterPose* pose) {
  double phi = phase;
  if (g.phase_lead() != 0 || adjust.phase != 0) {
    phi += g.phase_lead() + adjust.phase;
    phi -= std::floor(phi);  // the swing repeats every cycle
  }
  const double hip_amplitude = g.hip_amplitude() + adjust.hip;
  const double abduction = g.hip_abduction() + adjust.abduction;
  const double s = g.hold_peak() ? 1.0 : SwingShape(g.profile(), phi);
  const bool left = g.side() == config::LEFT;
  const JointId hip = left ? kLeftHip : kRightHip;
  const JointId knee = left ? kLeftKnee : kRightKnee;
  const JointId ankle = left ? kLeftAnkle : kRightAnkle;
  double flexion = g.hip_rest() + (hip_amplitude - g.hip_rest()) * s;
  double outward = abduction * s, knee_bend = 0;
  if (adjust.placing && phase >= 0.5) {
    // The follow-through puts the foot down where the stance changes to it (stance_change.h).
    const double u = (phase - 0.5) / 0.5;
    const double w = std::min(1.0, 2 * u) * (1 - s);
    flexion += w * adjust.place_hip;
    outward += w * adjust.place_abduction;
    knee_bend = spec.env().stance_change().knee_lift() * std::sin(M_PI * u);
  }
  if (outward != 0) {
    // Flexion about z and abduction about x (−x moves a right limb toward +z, outward).
    const double rotvec[3] = {(left ? 1 : -1) * outward, 0, flexion};
    SetBallJointRotation(spec, hip, rotvec, pose);
  } else {
    SetBallJointAxisRotation(spec, hip, kZ, flexion, pose);
  }
  const double knee_amplitude = g.knee_amplitude() + adjust.knee;
  SetHinge(spec, knee, -(g.knee_rest() + (knee_amplitude - g.knee_rest()) * s) - knee_bend, pose);
  if (const double ankle_amplitude = g.ankle_amplitude() + adjust.ankle; ankle_amplitude != 0) {
    SetBallJointAxisRotation(spec, ankle, kZ, ankle_amplitude * s, pose);
  }
  if (g.stance_roll() != 0) RollStanceLeg(spec, left, g.stance_roll(), pose);
}

// Drops the root along a lever of length `lever` swung by `knee` (rad, ≤ 0 when bent).
void LeverRoot(double lever, double knee, CharacterPose* pose) {
  (*pose)[2] -= lever * (1 - std::cos(knee));
  (*pose)[0] += lever * std::sin(-knee);
}

void HeadDipPose(const JuggleSpec& spec, const config::HeadDip& g, const SwingAdjust& adjust,
                 double phase, CharacterPose* pose) {
  if (adjust.lean_pitch != 0 || adjust.lean_roll != 0) {
    // The chest turned from its rest by roll about its x axis and pitch about its z axis.
    const double lean[3] = {adjust.lean_roll, 0, adjust.lean_pitch};
    mju_quatIntegrate(pose->data() + spec.joint(kChest).qpos_adr, lean, 1.0);
  }
  // Set in an UP node before a kick, where the dip is over (its ankles would replace it).
  if (adjust.stance_roll != 0) {
    RollStanceLeg(spec, adjust.stance_roll_left_kick, adjust.stance_roll, pose);
  }
  if (g.hold()) {
    SetBallJointAxisRotation(spec, kNeck, kZ, g.neck_pitch(), pose);
    return;
  }
  // The dip over [push, 0.5 + push) of the cycle: straight legs before it (with a push) and
  // from its end on. (A phase just below 0, from the reference feed-forward's difference,
  // continues the sine without a push.)
  const double dip = phase + adjust.head_phase - g.push();
  if (dip >= 0.5 || (dip < 0 && (g.push() > 0 || adjust.head_phase != 0))) return;
  const double s2 = std::sin(2 * M_PI * dip);
  for (JointId ankle : {kRightAnkle, kLeftAnkle}) {
    SetBallJointAxisRotation(spec, ankle, kZ, g.amplitude() * s2, pose);
  }
  for (JointId knee : {kRightKnee, kLeftKnee}) SetHinge(spec, knee, -g.amplitude() * s2, pose);
  LeverRoot(g.lever(), -g.amplitude() * s2, pose);
}

// A chest node's head feedback (SwingAdjust.lean_pitch, lean_roll) moves the chest by the legs
// (below); BaseController::AddStanceBalance moves the balance's target with it.
void ChestLeanPose(const JuggleSpec& spec, const config::ChestLean& g, const SwingAdjust& adjust,
                   double phase, CharacterPose* pose) {
  const double s = g.hold() || g.steady() ? 1.0 : std::sin(M_PI * phase);
  // The dip over the fall only (φ in [0, 0.5), moved by the feedback's timing); none while
  // holding.
  const double dip_phase = phase + adjust.head_phase;
  const double dip = g.hold() || dip_phase < 0 || dip_phase >= 0.5
                         ? 0.0
                         : g.dip() * std::sin(2 * M_PI * dip_phase);
  const double knee = g.knee() + dip;
  for (JointId ankle : {kRightAnkle, kLeftAnkle}) {
    SetBallJointAxisRotation(spec, ankle, kZ, g.ankle_amplitude() * s + dip, pose);
  }
  for (JointId joint : {kRightKnee, kLeftKnee}) SetHinge(spec, joint, -knee, pose);
  LeverRoot(g.lever(), -knee, pose);
  SetBallJointAxisRotation(spec, kChest, kZ, g.chest_amplitude() * s, pose);
  if (g.neck_pitch() != 0) SetBallJointAxisRotation(spec, kNeck, kZ, g.neck_pitch(), pose);
  if (adjust.lean_roll != 0) {
    // Both legs sway sideways as a parallelogram (the hips roll, the ankles roll back; the feet
    // stay flat): the chest's sphere is 0.12 m above its own joint, too short a lever. Forward
    // and back the balance's target alone moves the body (AddStanceBalance): both hips flexed
    // to tilt the trunk, tried, fell backward more often (docs/planner.md, "The chest"). The
    // feedback's signs are the chest's (HeadDipPose).
    const double sway[3] = {adjust.lean_roll, 0, 0};
    const double back[3] = {-adjust.lean_roll, 0, 0};
    for (JointId hip : {kRightHip, kLeftHip}) {
      mju_quatIntegrate(pose->data() + spec.joint(hip).qpos_adr, sway, 1.0);
    }
    for (JointId ankle : {kRightAnkle, kLeftAnkle}) {
      mju_quatIntegrate(pose->data() + spec.joint(ankle).qpos_adr, back, 1.0);
    }
  }
}

// Interpolates two poses: slerp for quaternions (root and ball joints), lerp otherwise.
void InterpolatePoses(const JuggleSpec& spec, const CharacterPose& a, const CharacterPose& b,
                      double t, CharacterPose* out) {
  for (int i = 0; i < 3; ++i) (*out)[i] = (1 - t) * a[i] + t * b[i];
  auto slerp = [&](int adr) {
    double qa[4] = {a[adr], a[adr + 1], a[adr + 2], a[adr + 3]};
    double qb[4] = {b[adr], b[adr + 1], b[adr + 2], b[adr + 3]};
    if (mju_dot(qa, qb, 4) < 0) mju_scl(qb, qb, -1, 4);
    double dv[3];
    mju_subQuat(dv, qb, qa);  // qa * quat(dv) = qb
    mju_scl3(dv, dv, t);
    double* q = out->data() + adr;
    mju_copy4(q, qa);
    mju_quatIntegrate(q, dv, 1.0);
  };
  slerp(3);
  for (int j = 0; j < kNumJoints; ++j) {
    const ActuatedJoint& joint = spec.joint(j);
    if (joint.dofs == 3) {
      slerp(joint.qpos_adr);
    } else {
      (*out)[joint.qpos_adr] = (1 - t) * a[joint.qpos_adr] + t * b[joint.qpos_adr];
    }
  }
}

// Keyframes.smooth: the cubic Hermite segment from frame `lo` to `lo + 1` at t ∈ [0, 1], with
// Catmull-Rom tangents (p[k+1] − p[k−1]) / (φ[k+1] − φ[k−1]) at interior frames and the
// secant at the first and last. Ball joints and the root's rotation are splined as rotation
// vectors relative to frame `lo`'s rotation (exact at every frame).
void SmoothKeyframePose(const JuggleSpec& spec, const NodeRuntime& rt, size_t lo, double t,
                        CharacterPose* out) {
  const std::vector<double>& ph = rt.keyframe_phase;
  const std::vector<CharacterPose>& frames = rt.keyframe_pose;
  const size_t hi = lo + 1, last = ph.size() - 1;
  const double span = std::max(ph[hi] - ph[lo], 1e-12);
  // Tangent at frame k (per unit phase) of the scalar value(k).
  auto tangent = [&](size_t k, auto value) {
    const size_t a = k == 0 ? 0 : k - 1, b = k == last ? last : k + 1;
    return (value(b) - value(a)) / std::max(ph[b] - ph[a], 1e-12);
  };
  const double t2 = t * t, t3 = t2 * t;
  const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2,
               h11 = t3 - t2;
  auto hermite = [&](auto value) {
    return h00 * value(lo) + h10 * span * tangent(lo, value) + h01 * value(hi) +
           h11 * span * tangent(hi, value);
  };
  auto scalar = [&](int adr) { (*out)[adr] = hermite([&](size_t k) { return frames[k][adr]; }); };
  const size_t first = lo == 0 ? 0 : lo - 1, end = std::min(hi + 1, last) + 1;
  auto rotation = [&](int adr) {
    const double* q0 = frames[lo].data() + adr;
    // Frames first..end−1 as rotation vectors v with q0 · exp(v) = q_k.
    double offsets[4][3];
    for (size_t k = first; k < end; ++k) {
      double qk[4] = {frames[k][adr], frames[k][adr + 1], frames[k][adr + 2], frames[k][adr + 3]};
      if (mju_dot(qk, q0, 4) < 0) mju_scl(qk, qk, -1, 4);
      mju_subQuat(offsets[k - first], qk, q0);
    }
    double v[3];
    for (int axis = 0; axis < 3; ++axis) {
      v[axis] = hermite([&](size_t k) { return offsets[k - first][axis]; });
    }
    double* q = out->data() + adr;
    mju_copy4(q, q0);
    mju_quatIntegrate(q, v, 1.0);
  };
  for (int i = 0; i < 3; ++i) scalar(i);
  rotation(3);
  for (int j = 0; j < kNumJoints; ++j) {
    const ActuatedJoint& joint = spec.joint(j);
    if (joint.dofs == 3) {
      rotation(joint.qpos_adr);
    } else {
      scalar(joint.qpos_adr);
    }
  }
}

void KeyframePose(const JuggleSpec& spec, const NodeRuntime& rt, bool smooth, double phase,
                  CharacterPose* pose) {
  const std::vector<double>& ph = rt.keyframe_phase;
  if (phase <= ph.front()) {
    *pose = rt.keyframe_pose.front();
    return;
  }
  if (phase >= ph.back()) {
    *pose = rt.keyframe_pose.back();
    return;
  }
  const size_t hi = std::upper_bound(ph.begin(), ph.end(), phase) - ph.begin();
  const size_t lo = hi - 1;
  const double t = (phase - ph[lo]) / std::max(ph[hi] - ph[lo], 1e-12);
  if (smooth) {
    SmoothKeyframePose(spec, rt, lo, t, pose);
  } else {
    InterpolatePoses(spec, rt.keyframe_pose[lo], rt.keyframe_pose[hi], t, pose);
  }
}

// Turns ball joint `j` of `pose` by `rotvec` (rad) in its parent's frame.
void TurnBallJointInParent(const JuggleSpec& spec, JointId j, const double rotvec[3],
                           CharacterPose* pose) {
  double axis[3] = {rotvec[0], rotvec[1], rotvec[2]};
  const double angle = mju_normalize3(axis);
  if (angle == 0) return;
  double turn[4];
  mju_axisAngle2Quat(turn, axis, angle);
  double* q = pose->data() + spec.joint(j).qpos_adr;
  double turned[4];
  mju_mulQuat(turned, turn, q);
  mju_normalize4(turned);
  mju_copy4(q, turned);
}

// A keyframed swing moved by the kick feedback as a leg swing is (LegSwingPose): the swinging
// hip's flexion and abduction, the knee's bend and the ankle's pitch, by sin²(πφ) — the whole
// offset at the contact (φ = 0.5), none where the node's cycle wraps, so the authored circle
// is kept and only the foot's place at the contact follows the ball.
void OffsetKeyframedSwing(const JuggleSpec& spec, bool left, const SwingAdjust& adjust,
                          double phase, CharacterPose* pose) {
  const double e = std::pow(std::sin(M_PI * phase), 2);
  const double hip[3] = {(left ? 1 : -1) * adjust.abduction * e, 0, adjust.hip * e};
  TurnBallJointInParent(spec, left ? kLeftHip : kRightHip, hip, pose);
  (*pose)[spec.joint(left ? kLeftKnee : kRightKnee).qpos_adr] -= adjust.knee * e;
  const double ankle[3] = {0, 0, adjust.ankle * e};
  TurnBallJointInParent(spec, left ? kLeftAnkle : kRightAnkle, ankle, pose);
}

}  // namespace

bool SwingingLeg(const config::ReferencePose& pose, config::Side* side) {
  if (pose.has_leg_swing()) {
    *side = pose.leg_swing().side();
    return true;
  }
  if (pose.has_keyframes() && pose.keyframes().has_swing_side()) {
    *side = pose.keyframes().swing_side();
    return true;
  }
  return false;
}

void ComputeReferencePose(const JuggleSpec& spec, int node, double phase, CharacterPose* pose,
                          const SwingAdjust& adjust) {
  const config::ReferencePose& ref = spec.graph().node(node).spec.pose();
  if (ref.has_keyframes()) {
    config::Side side;
    const bool swings = SwingingLeg(ref, &side);
    // Authored frames do not repeat: the shift holds the first or last frame past the ends.
    const double phi = swings ? std::clamp(phase + adjust.phase, 0.0, 1.0) : phase;
    KeyframePose(spec, spec.node_runtime(node), ref.keyframes().smooth(), phi, pose);
    if (swings) OffsetKeyframedSwing(spec, side == config::LEFT, adjust, phase, pose);
    return;
  }
  *pose = StandingPose(spec);
  switch (ref.generator_case()) {
    case config::ReferencePose::kLegSwing:
      LegSwingPose(spec, ref.leg_swing(), adjust, phase, pose);
      break;
    case config::ReferencePose::kHeadDip:
      HeadDipPose(spec, ref.head_dip(), adjust, phase, pose);
      break;
    case config::ReferencePose::kChestLean:
      ChestLeanPose(spec, ref.chest_lean(), adjust, phase, pose);
      break;
    default:
      break;
  }
}

void ComputeCursorPose(const JuggleSpec& spec, const CursorState& cursor, double phase,
                       CharacterPose* pose, const SwingAdjust& adjust) {
  ComputeReferencePose(spec, cursor.current, phase, pose, adjust);
  if (cursor.next < 0 || spec.graph().node(cursor.current).stage != config::UP) return;
  const double lead = spec.graph().node(cursor.next).spec.pose_lead_in();
  if (lead <= 0) return;
  const double start = 1.0 - 0.5 * lead;
  if (phase <= start) return;
  const double u = std::min((phase - start) / (0.5 * lead), 1.0);
  CharacterPose next;
  ComputeReferencePose(spec, cursor.next, 0.0, &next, adjust);
  const CharacterPose own = *pose;
  InterpolatePoses(spec, own, next, u * u * (3 - 2 * u), pose);
}

}  // namespace juggle::soccer_juggle
