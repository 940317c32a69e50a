#include "planner/soccer_juggle/plan.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "absl/algorithm/container.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "envs/soccer_juggle/reference_pose.h"
#include "planner/pose_action.h"

namespace juggle::planner {

static_assert(kKickVariables - 1 == soccer_juggle::kMaxNodeKickVariables,
              "a node declares at most the plan's angle variables");

using soccer_juggle::ActuatedJoint;
using soccer_juggle::CharacterPose;
using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;
using soccer_juggle::kNumJoints;
using soccer_juggle::SwingAdjust;

absl::StatusOr<std::vector<int>> BodyActionIndices(
    const google::protobuf::RepeatedPtrField<std::string>& names) {
  // The first action of each joint and its axes, in the model's dof order.
  int first[kNumJoints];
  for (int j = 0, a = 0; j < kNumJoints; ++j) {
    first[j] = a;
    a += (j == soccer_juggle::kRightElbow || j == soccer_juggle::kLeftElbow ||
          j == soccer_juggle::kRightKnee || j == soccer_juggle::kLeftKnee)
             ? 1
             : 3;
  }
  auto axes = [](int j) {
    return (j == soccer_juggle::kRightElbow || j == soccer_juggle::kLeftElbow ||
            j == soccer_juggle::kRightKnee || j == soccer_juggle::kLeftKnee)
               ? 1
               : 3;
  };
  std::vector<int> out;
  if (names.empty()) {
    for (int a = 0; a < kNumActions; ++a) out.push_back(a);
    return out;
  }
  for (const std::string& entry : names) {
    const size_t colon = entry.find(':');
    const std::string joint = entry.substr(0, colon);
    int j = 0;
    while (j < kNumJoints && joint != soccer_juggle::kJointNames[j]) ++j;
    if (j == kNumJoints) {
      return absl::InvalidArgumentError(absl::StrCat("'", entry, "' names no joint"));
    }
    if (colon == std::string::npos) {
      for (int k = 0; k < axes(j); ++k) out.push_back(first[j] + k);
      continue;
    }
    const std::string axis = entry.substr(colon + 1);
    if (axes(j) != 3 || axis.size() != 1 || axis[0] < 'x' || axis[0] > 'z') {
      return absl::InvalidArgumentError(
          absl::StrCat("'", entry, "': an axis (x, y or z) of a ball joint"));
    }
    out.push_back(first[j] + (axis[0] - 'x'));
  }
  return out;
}

SoccerPlanLayout MakeSoccerPlanLayout(const config::PlannerConfig& config,
                                      const config::KickVariables& kick) {
  SoccerPlanLayout layout;
  absl::StatusOr<std::vector<int>> actions = BodyActionIndices(config.body_actions());
  if (actions.ok()) layout.body_actions = *std::move(actions);
  layout.kick_sets = kick.enabled() ? kick.cycles() : 0;
  layout.later_kicks_by_base = kick.later_kicks_by_base();
  layout.hold_follow_through = kick.enabled() && kick.hold_follow_through();
  layout.hold_after = kick.hold_after_replans();
  layout.hold_in_rescue = layout.hold_follow_through && kick.hold_in_rescue();
  layout.act_from_phase = kick.act_from_phase();
  layout.horizon = config.horizon_steps();
  layout.knot_steps = config.body_knot_steps();
  if (layout.knot_steps > 0) {
    // From an origin up to knot_steps − 1 past knot 0 to the horizon's last step, plus the
    // knot after it.
    layout.body_knots = (layout.knot_steps + layout.horizon - 2) / layout.knot_steps + 2;
  }
  return layout;
}

double SoccerPlanLayout::kick_ramp(double phase) const {
  if (act_from_phase <= 0 || phase >= 0.5) return 1;
  if (phase < act_from_phase) return 0;
  const double s = std::sin(0.5 * M_PI * (phase - act_from_phase) / (0.5 - act_from_phase));
  return s * s;
}

SearchSpace MakeSoccerSearchSpace(const SoccerPlanLayout& layout,
                                  const config::PlannerConfig& config,
                                  const config::KickVariables& kick) {
  SearchSpace space;
  auto add = [&space](double limit, double sigma) {
    space.lower.push_back(-limit);
    space.upper.push_back(limit);
    space.sigma.push_back(sigma);
  };
  for (int s = 0; s < layout.kick_sets; ++s) {
    add(kick.phase_limit_s(), kick.phase_sigma_s());
    for (int a = 1; a < kKickVariables; ++a) {
      const bool held = absl::c_linear_search(kick.held_angles(), a);
      add(held ? 0 : kick.angle_limit(), held ? 0 : kick.angle_sigma());
    }
  }
  for (int i = 0; i < layout.body_knots * layout.knot_size(); ++i) {
    add(config.body_limit(), config.body_sigma());
  }
  for (int i = 0; i < layout.held_dim(); ++i) add(0, 0);  // set by the task, never searched
  return space;
}

double BodySplineValue(const SoccerPlanLayout& layout, const double* theta, int step, int i) {
  const int knots = layout.body_knots;
  const int k = std::clamp(step / layout.knot_steps, 0, knots - 1);
  if (k == knots - 1) return theta[layout.knot(k) + i];
  const double f = static_cast<double>(step - k * layout.knot_steps) / layout.knot_steps;
  return (1 - f) * theta[layout.knot(k) + i] + f * theta[layout.knot(k + 1) + i];
}

namespace {

// Rotates ball joint `j` of `pose` by `angle` about its local `axis` (y-up joint frames: z is
// pitch, x roll toward the character's right) or moves hinge `j` by `angle`.
void AddRotation(const JuggleSpec& spec, soccer_juggle::JointId j, int axis, double angle,
                 CharacterPose* pose) {
  const ActuatedJoint& joint = spec.joint(j);
  if (joint.dofs == 3) {
    double rotation[3] = {0, 0, 0};
    rotation[axis] = angle;
    mju_quatIntegrate(pose->data() + joint.qpos_adr, rotation, 1.0);
  } else {
    (*pose)[joint.qpos_adr] += angle;
  }
}

void AddPitch(const JuggleSpec& spec, soccer_juggle::JointId j, double angle, CharacterPose* pose) {
  AddRotation(spec, j, 2, angle, pose);
}

// The contact node's reference changed by the kick variables: the first is the timing; the
// others move the node's declared joint axes (spec.h NodeRuntime::kick_variables) by
// gain · v · e(φ), e = sin²(πφ) (largest at the contact, zero where the cycle wraps) or, for a
// SPEED variable (control_graph.proto KickVariableSpec), −sin(2πφ)/(2π). Without a
// declaration, for a leg swing its amplitudes (reference_pose.h SwingAdjust); for the other
// generators (head, chest) the chest's pitch, the neck's pitch, the chest's and the neck's roll,
// and both knees. The roll replaced the hips' pitch, which moved a header's landing sideways by
// 3 cm for 0.2 rad (docs/planner.md, "Every skill by search").
void KickReferences(const JuggleEnv& env, const double* kick, double cycle_s, CharacterPose* from,
                    CharacterPose* to) {
  const JuggleSpec& spec = env.spec();
  const int node = env.node();
  const double phase = env.cursor().phase;
  const SwingAdjust& base = env.state().swing_adjust;
  const std::vector<std::vector<soccer_juggle::KickVariableMove>>& declared =
      spec.node_runtime(node).kick_variables;
  ComputeCursorPose(spec, env.cursor(), phase, from, base);
  if (spec.graph().node(node).spec.pose().has_leg_swing()) {
    SwingAdjust changed = base;
    changed.phase += kick[0] / cycle_s;
    if (declared.empty()) {
      changed.hip += kick[1];
      changed.abduction += kick[2];
      changed.knee += kick[3];
      changed.ankle += kick[4];
    }
    ComputeCursorPose(spec, env.cursor(), phase, to, changed);
    if (declared.empty()) return;
  } else {
    double shifted = phase + kick[0] / cycle_s;
    shifted -= std::floor(shifted);
    ComputeCursorPose(spec, env.cursor(), shifted, to, base);
  }
  const double envelope = std::pow(std::sin(M_PI * phase), 2);
  if (!declared.empty()) {
    // KickVariableSpec.SPEED: zero at the contact, slope 1 per unit phase there.
    const double speed_envelope = -std::sin(2 * M_PI * phase) / (2 * M_PI);
    for (size_t v = 0; v < declared.size(); ++v) {
      for (const soccer_juggle::KickVariableMove& move : declared[v]) {
        const double e = move.speed ? speed_envelope : envelope;
        AddRotation(spec, move.joint, move.axis, move.gain * kick[1 + v] * e, to);
      }
    }
    return;
  }
  using soccer_juggle::JointId;
  AddPitch(spec, soccer_juggle::kChest, kick[1] * envelope, to);
  AddPitch(spec, soccer_juggle::kNeck, kick[2] * envelope, to);
  for (JointId lean : {soccer_juggle::kChest, soccer_juggle::kNeck}) {
    AddRotation(spec, lean, 0, kick[3] * envelope, to);
  }
  for (JointId knee : {soccer_juggle::kRightKnee, soccer_juggle::kLeftKnee}) {
    AddPitch(spec, knee, kick[4] * envelope, to);
  }
}

// Adds the kick variables' torque (in action units) at `env`'s state to `out`, their moves
// scaled by `ramp` (SoccerPlanLayout::kick_ramp; nothing added at 0). In a stall (the phase
// held at the contact) the angles hold the pose moved at full envelope and the timing moves
// nothing.
void AddKickAction(const JuggleEnv& env, const double* kick, double ramp, double* out) {
  if (ramp == 0) return;
  double ramped[kKickVariables];
  if (ramp != 1) {
    for (int v = 0; v < kKickVariables; ++v) ramped[v] = ramp * kick[v];
    kick = ramped;
  }
  const JuggleSpec& spec = env.spec();
  const soccer_juggle::CursorState& c = env.cursor();
  const double cycle_s = c.phase_speed > 0 ? spec.control_dt() / c.phase_speed
                                           : std::numeric_limits<double>::infinity();
  CharacterPose from, to;
  KickReferences(env, kick, cycle_s, &from, &to);
  AddPoseChangeAction(spec.joints(), from, to, spec.env().action_torque(), out);
}

}  // namespace

void SoccerPlanAction(const JuggleEnv& env, const SoccerPlanLayout& layout, const double* theta,
                      PlanClock clock, float* action, const double* prior) {
  double a[kNumActions] = {0};
  if (prior != nullptr) std::copy_n(prior, kNumActions, a);
  const double ramp = layout.kick_ramp(env.cursor().phase);
  if (layout.follows_held(theta, clock.cycle)) {
    AddKickAction(env, theta + layout.held(), ramp, a);
  } else if (const int set = layout.acting_kick_set(clock.cycle); set >= 0) {
    AddKickAction(env, theta + layout.kick(set), ramp, a);
  }
  if (layout.body_knots > 0) {
    for (int i = 0; i < layout.knot_size(); ++i) {
      a[layout.body_actions[i]] += BodySplineValue(layout, theta, clock.step, i);
    }
  }
  for (int i = 0; i < kNumActions; ++i) action[i] = static_cast<float>(std::clamp(a[i], -1.0, 1.0));
}

std::string FormatKickVariables(const std::vector<double>& d) {
  if (d.size() != kKickVariables) return {};
  return absl::StrFormat("  vars %+.0f ms %+.2f %+.2f %+.2f %+.2f", d[0] * 1000, d[1], d[2], d[3],
                         d[4]);
}

int KnotAtOrBefore(const SoccerPlanLayout& layout, int step) {
  return layout.knot_steps > 0 ? step / layout.knot_steps * layout.knot_steps : step;
}

std::vector<double> ShiftSoccerPlan(const SoccerPlanLayout& layout, const std::vector<double>& theta,
                                    int knots, int cycles) {
  std::vector<double> out(theta.size());
  for (int s = 0; s < layout.kick_sets; ++s) {
    const int from = std::min(s + std::max(cycles, 0), layout.kick_sets - 1);
    std::copy_n(theta.begin() + layout.kick(from), kKickVariables, out.begin() + layout.kick(s));
  }
  for (int k = 0; k < layout.body_knots; ++k) {
    const int from = std::min(k + std::max(knots, 0), layout.body_knots - 1);
    std::copy_n(theta.begin() + layout.knot(from), layout.knot_size(),
                out.begin() + layout.knot(k));
  }
  if (layout.hold_follow_through && cycles <= 0) {  // a new cycle ends the hold (zeros)
    std::copy_n(theta.begin() + layout.held(), layout.held_dim(), out.begin() + layout.held());
  }
  return out;
}

}  // namespace juggle::planner
