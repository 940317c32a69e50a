#include "envs/soccer_juggle/graph_cursor.h"

#include <algorithm>
#include <cmath>

namespace juggle::soccer_juggle {

GraphCursor::GraphCursor(const ControlGraph* graph, double control_dt, double gravity,
                         bool carry_phase)
    : graph_(graph), control_dt_(control_dt), gravity_(gravity), carry_phase_(carry_phase) {}

double GraphCursor::SampleApex(int node, Rng* rng) const {
  const config::NodeSpec& n = graph_->node(node).spec;
  if (!n.has_half_cycle_s() && n.has_apex_height_range()) {
    return rng->Uniform(n.apex_height_range().min(), n.apex_height_range().max());
  }
  return NominalApexHeight(n, gravity_);
}

double GraphCursor::HalfCycleSeconds(int node, double apex) const {
  const config::NodeSpec& n = graph_->node(node).spec;
  if (n.has_half_cycle_s()) return n.half_cycle_s();
  const double drop = std::max(apex - n.contact_height(), 1e-3);
  return std::sqrt(2.0 * drop / gravity_);
}

void GraphCursor::UpdateSpeed(CursorState* s) const {
  if (graph_->node(s->current).stage == config::STALL) {
    s->phase_speed = 0;
    return;
  }
  s->phase_speed = control_dt_ / (2.0 * HalfCycleSeconds(s->current, s->apex_height));
}

void GraphCursor::Reset(const AdaptiveWalk& walk, Rng* rng, CursorState* s) const {
  const std::vector<int>& initial = graph_->initial_nodes();
  ResetAt(initial[rng->UniformInt(initial.size())], walk, rng, s);
}

void GraphCursor::ResetAt(int node, const AdaptiveWalk& walk, Rng* rng, CursorState* s) const {
  *s = CursorState();
  s->current = node;
  s->edge_to_next = walk.SampleEdge(node, rng);
  s->next = graph_->edge(s->edge_to_next).to;
  s->edge_to_next_next = walk.SampleEdge(s->next, rng);
  s->next_next = graph_->edge(s->edge_to_next_next).to;
  s->phase = graph_->node(node).stage == config::DOWN ? 0.0 : 0.5;
  s->apex_height = SampleApex(node, rng);
  UpdateSpeed(s);
}

bool GraphCursor::Advance(const AdaptiveWalk& walk, Rng* rng, CursorState* s,
                          std::vector<EdgeEvent>* events) const {
  const config::Stage stage = graph_->node(s->current).stage;
  s->phase += s->phase_speed;
  const double half_step = 0.5 * s->phase_speed;
  bool transition = false;
  if (stage == config::STALL) {
    transition = true;
    s->phase = 0.5;
  } else if (stage == config::DOWN && s->phase + half_step > 0.5) {
    transition = true;
    if (!carry_phase_) s->phase = 0.5;
  } else if (stage == config::UP && s->phase + half_step > 1.0) {
    transition = true;
    s->phase = carry_phase_ ? s->phase - 1.0 : 0.0;
  }
  if (!transition) return false;

  // The finished node is complete; the sampled edge is taken.
  if (s->entered_by >= 0) events->push_back({s->entered_by, EdgeEventType::kCompleted});
  events->push_back({s->edge_to_next, EdgeEventType::kChosen});
  ++s->completions;
  // A juggle: the ball reached the apex after a touch (UP), or a stall handed it on.
  if (stage == config::UP || (stage == config::STALL && s->next != s->current)) ++s->juggles;

  s->entered_by = s->edge_to_next;
  s->current = s->next;
  s->next = s->next_next;
  s->edge_to_next = s->edge_to_next_next;
  s->edge_to_next_next = walk.SampleEdge(s->next, rng);
  s->next_next = graph_->edge(s->edge_to_next_next).to;

  if (graph_->node(s->current).stage == config::UP) {
    s->apex_height = std::max(SampleApex(s->current, rng), SampleApex(s->next, rng));
  }
  UpdateSpeed(s);
  return true;
}

bool GraphCursor::Resteer(const AdaptiveWalk& walk, CursorState* s) const {
  const std::vector<int>& steering = walk.steering();
  if (steering.empty() || s->next < 0) return false;
  const int e = steering[s->next];
  if (e < 0 || e == s->edge_to_next_next) return false;
  s->edge_to_next_next = e;
  s->next_next = graph_->edge(e).to;
  return true;
}

void GraphCursor::Fail(const CursorState& s, std::vector<EdgeEvent>* events) const {
  if (s.entered_by >= 0) events->push_back({s.entered_by, EdgeEventType::kFailed});
}

double GraphCursor::SecondsFromContact(const CursorState& s, double phase) const {
  if (s.phase_speed <= 0) return 0;
  return (phase - 0.5) / s.phase_speed * control_dt_;
}

BallReference GraphCursor::DesiredBall(const CursorState& s, double phase) const {
  const GraphNode& node = graph_->node(s.current);
  const config::NodeSpec& target_node =
      node.stage == config::UP ? graph_->node(s.next).spec : node.spec;
  BallReference ref;
  ref.x = target_node.ball_target().x();
  ref.y = target_node.ball_target().y();
  const double h = node.spec.contact_height();
  if (node.stage == config::STALL) {
    ref.z = node.spec.stall().has_ball_height() ? node.spec.stall().ball_height() : h;
    return ref;
  }
  const double half_t = 0.5 / s.phase_speed * control_dt_;  // half-cycle seconds
  if (node.stage == config::DOWN) {
    const double t = std::clamp(phase, 0.0, 0.5) / s.phase_speed * control_dt_;
    ref.z = h + 0.5 * gravity_ * (half_t * half_t - t * t);
  } else {
    const double t = std::clamp(phase - 0.5, 0.0, 0.5) / s.phase_speed * control_dt_;
    ref.z = h + gravity_ * half_t * t - 0.5 * gravity_ * t * t;
  }
  return ref;
}

BallReference GraphCursor::DesiredBallVelocity(const CursorState& s, double phase) const {
  const GraphNode& node = graph_->node(s.current);
  BallReference vel;
  if (node.stage == config::STALL) return vel;
  const double half_t = 0.5 / s.phase_speed * control_dt_;
  if (node.stage == config::DOWN) {
    vel.z = -gravity_ * std::clamp(phase, 0.0, 0.5) / s.phase_speed * control_dt_;
  } else {
    vel.z = gravity_ * (half_t - std::clamp(phase - 0.5, 0.0, 0.5) / s.phase_speed * control_dt_);
  }
  return vel;
}

}  // namespace juggle::soccer_juggle
