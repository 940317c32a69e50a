#include "envs/soccer_juggle/base_controller.h"

#include <algorithm>
#include <cmath>

#include "envs/ballistic.h"
#include "envs/humanoid/reference_dynamics.h"
#include "envs/humanoid/stance_balance.h"
#include "envs/soccer_juggle/stance_change.h"

namespace juggle::soccer_juggle {

BaseController::BaseController(const JuggleSpec& spec)
    : spec_(spec), model_(spec.model()) {
  if (spec_.env().reference_feedforward() != 0) id_data_.reset(mj_makeData(model_));
}

void BaseController::UpdateSwingAdjust(const mjData& data, const CursorState& cursor,
                                       bool kick_touched, SwingAdjust* adjust) const {
  const GraphNode& node = spec_.graph().node(cursor.current);
  adjust->placing = spec_.env().has_stance_change() && HandsStanceOver(spec_.graph(), cursor);
  if (adjust->placing) {
    PlaceKickingFoot(spec_, data, node.spec.pose().leg_swing().side() == config::LEFT, adjust);
  }
  if (node.spec.has_head_feedback()) UpdateHeadLean(data, cursor, kick_touched, adjust);
  adjust->stance_roll = 0;
  bool next_kicks_left = false;
  if (spec_.env().has_stance_change() && spec_.env().stance_change().header_roll() > 0 &&
      KickFollowsBothFeet(spec_.graph(), cursor, &next_kicks_left)) {
    const config::LegSwing& next = spec_.graph().node(cursor.next).spec.pose().leg_swing();
    adjust->stance_roll =
        HeaderRollShare(spec_.env().stance_change(), cursor.phase) * next.stance_roll();
    adjust->stance_roll_left_kick = next_kicks_left;
  }
  // A node's own feedback, else the env's (proto/control_graph.proto, NodeSpec.kick_feedback).
  const bool own = node.spec.has_kick_feedback();
  if (!own && !spec_.env().has_kick_feedback()) return;
  config::Side side;
  if (node.stage != config::DOWN || kick_touched || !SwingingLeg(node.spec.pose(), &side)) return;
  const double* qpos = data.qpos;
  const double* ball = qpos + spec_.ball_qpos();
  const double* ball_vel = data.qvel + spec_.ball_dof();
  if (ball[2] - node.spec.contact_height() <= 0) return;  // at the contact height already: hold
  const BallisticCrossing c =
      DescendingCrossing(ball, ball_vel, spec_.env().gravity(), node.spec.contact_height());
  const double ex = c.x - qpos[0] - node.spec.ball_target().x();
  const double ey = c.y - qpos[1] - node.spec.ball_target().y();
  const config::KickFeedback& f = own ? node.spec.kick_feedback() : spec_.env().kick_feedback();
  const bool left = side == config::LEFT;
  adjust->hip = f.hip_per_m() * ex;
  adjust->knee = f.knee_per_m() * ex;
  adjust->abduction = f.abduction_per_m() * ey * (left ? 1 : -1);
  adjust->phase = TimingShift(cursor, c.t, f.timing());
  if (!node.spec.pose().has_leg_swing()) adjust->phase = std::clamp(adjust->phase, -0.1, 0.1);
}

double BaseController::TimingShift(const CursorState& cursor, double crossing_s,
                                   double gain) const {
  const double late = crossing_s + spec_.cursor().SecondsFromContact(cursor, cursor.phase);
  const double cycle_s = spec_.control_dt() / cursor.phase_speed;
  return -gain * late / cycle_s;
}

void BaseController::UpdateHeadLean(const mjData& data, const CursorState& cursor,
                                    bool kick_touched, SwingAdjust* adjust) const {
  const config::NodeSpec& node = spec_.graph().node(cursor.current).spec;
  const config::HeadFeedback& f = node.head_feedback();
  if (node.stage() == config::DOWN && kick_touched) return;  // hold from the touch on
  if (node.stage() == config::UP) {
    adjust->head_phase = 0;  // the dip is over
    if (!spec_.graph().node(cursor.next).spec.has_head_feedback()) {
      adjust->lean_pitch = adjust->lean_roll = 0;  // the next touch is not a header: upright
      return;
    }
  }
  const double* qpos = data.qpos;
  const double* ball = qpos + spec_.ball_qpos();
  const double* ball_vel = data.qvel + spec_.ball_dof();
  const double g = spec_.env().gravity();
  const double h = node.contact_height();
  if (ball[2] < h && ball_vel[2] <= 0) return;  // below the head and falling: hold
  const BallisticCrossing c = DescendingCrossing(ball, ball_vel, g, h);
  if (node.stage() == config::DOWN && f.timing() > 0 && cursor.phase_speed > 0) {
    adjust->head_phase = std::clamp(TimingShift(cursor, c.t, f.timing()), -0.15, 0.15);
  }
  // The crossing's offset from this node's target (where the head goes), and the horizontal
  // speed that brings the ball to the receiving node's target over one cycle (up to the apex
  // and down to the contact height again): before the touch the DOWN node after the coming UP
  // one, after it the next node.
  const int receiving = node.stage() == config::DOWN && cursor.next_next >= 0
                            ? cursor.next_next
                            : (cursor.next >= 0 ? cursor.next : cursor.current);
  const config::BallTarget& to = spec_.graph().node(receiving).spec.ball_target();
  const double e[2] = {c.x - qpos[0] - node.ball_target().x(),
                       c.y - qpos[1] - node.ball_target().y()};
  const double pass[2] = {c.x - qpos[0] - to.x(), c.y - qpos[1] - to.y()};
  const double rise = std::max(cursor.apex_height - h, 0.01);
  const double flight_s = 2 * std::sqrt(2 * rise / g);
  const double w = std::max(g * c.t - ball_vel[2], 0.1);  // downward speed at the crossing
  double shift[2];
  for (int i = 0; i < 2; ++i) {
    const double normal = (-pass[i] / flight_s - ball_vel[i]) / ((1 + f.restitution()) * w);
    shift[i] = e[i] - f.redirect() * f.contact_radius_m() * normal;
  }
  const double norm = std::hypot(shift[0], shift[1]);
  const double scale = norm > f.max_shift_m() ? f.max_shift_m() / norm : 1.0;
  // The chest's pitch about its z axis leans it back, its roll about x to the right (−y).
  adjust->lean_pitch = -f.lean_per_m() * scale * shift[0];
  adjust->lean_roll = -f.lean_per_m() * scale * shift[1];
}

void BaseController::AddFeedforward(const CursorState& cursor, const CharacterPose& reference,
                                    const SwingAdjust& adjust, mjData* data,
                                    double* feedforward) {
  if (id_data_ != nullptr) AddReferenceFeedforward(cursor, reference, adjust, *data, feedforward);
  if (spec_.env().has_stance_balance()) {
    AddStanceBalance(cursor, adjust, data, feedforward);
  }
}

void BaseController::AddReferenceFeedforward(const CursorState& cursor,
                                             const CharacterPose& reference,
                                             const SwingAdjust& adjust, const mjData& data,
                                             double* feedforward) {
  // The reference ± half a control step (humanoid::ReferenceInverseDynamics).
  const double dt = 0.5 * spec_.control_dt();
  const double dphase = 0.5 * cursor.phase_speed;
  CharacterPose before, after;
  ComputeCursorPose(spec_, cursor, cursor.phase - dphase, &before, adjust);
  ComputeCursorPose(spec_, cursor, cursor.phase + dphase, &after, adjust);
  double tau[kCharacterNv];
  humanoid::ReferenceInverseDynamics(spec_.joints(), model_, data, before, reference, after, dt,
                                     id_data_.get(), tau);
  const double gain = spec_.env().reference_feedforward();
  for (int j = 0; j < kNumJoints; ++j) {
    const ActuatedJoint& joint = spec_.joint(j);
    for (int k = joint.dof_adr; k < joint.dof_adr + joint.dofs; ++k) {
      feedforward[k] += gain * tau[k];
    }
  }
}

void BaseController::AddStanceBalance(const CursorState& cursor, const SwingAdjust& adjust,
                                      mjData* data, double* feedforward) const {
  const config::NodeSpec& node = spec_.graph().node(cursor.current).spec;
  const config::ReferencePose& ref = node.pose();
  config::StanceBalance gains = spec_.env().stance_balance();
  const bool changing = spec_.env().has_stance_change();
  const config::StanceChange& change = spec_.env().stance_change();
  config::Side swing = config::RIGHT;
  if (!SwingingLeg(ref, &swing)) {
    // Headers, chest traps, stalls: both feet are down. Without it the PD alone tips the
    // character over within about a second of headers (envs/soccer_juggle/stance_test.cc).
    bool next_kicks_left = false;
    if (changing && KickFollowsBothFeet(spec_.graph(), cursor, &next_kicks_left)) {
      // Toward the next kick's standing ankle (stance_change.h).
      const double* left = AnklePosition(*data, humanoid::kLeftAnkle);
      const double* right = AnklePosition(*data, humanoid::kRightAnkle);
      const double* stance = next_kicks_left ? right : left;
      const double share = HeaderShiftShare(change, cursor.phase);
      gains.set_com_x(gains.com_x() + share * (stance[0] - (left[0] + right[0]) / 2));
      gains.set_com_y(gains.com_y() + share * (stance[1] - (left[1] + right[1]) / 2));
    }
    if (ref.has_chest_lean() && node.head_feedback().lean_per_m() > 0) {
      // The chest's feedback: the balance's target moves by its shift, forward and back alone,
      // sideways with the legs' sway (ChestLeanPose), which it would otherwise pull back.
      const double per_m = node.head_feedback().lean_per_m();
      gains.set_com_x(gains.com_x() - adjust.lean_pitch / per_m);
      gains.set_com_y(gains.com_y() - adjust.lean_roll / per_m);
    }
    humanoid::AddDoubleStanceBalance(spec_.joints(), gains, spec_.root_body(),
                                     spec_.env().action_torque(), model_, data, feedforward);
    return;
  }
  const bool kick_left = swing == config::LEFT;
  if (adjust.placing) {  // the stance goes to the kicking foot next (UpdateSwingAdjust)
    gains.set_com_y(gains.com_y() + LeanTowardKick(change, kick_left, cursor.phase));
  }
  humanoid::AddStanceBalance(spec_.joints(), gains,
                             kick_left ? humanoid::Foot::kRight : humanoid::Foot::kLeft,
                             spec_.root_body(), spec_.env().action_torque(), model_, data,
                             feedforward);
}

const double* BaseController::AnklePosition(const mjData& data, humanoid::JointId ankle) const {
  return data.xpos + 3 * model_->dof_bodyid[spec_.joint(ankle).dof_adr];
}

}  // namespace juggle::soccer_juggle
