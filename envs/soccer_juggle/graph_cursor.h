// Where an episode is in the control graph: the current node and the next two (the policy sees
// all three), the phase φ ∈ [0, 1) and its speed, and the apex height of the ball's flight.
//
// Phase (paper §4.1): a DOWN node runs φ 0 → 0.5 (apex to contact), an UP node 0.5 → 1
// (contact to apex), a STALL node holds φ = 0.5 for one control step per visit. A half cycle
// lasts t = √(2(H − h)/g) for apex H and contact height h (or the node's half_cycle_s), so the
// phase speed is control_dt / (2t) per control step. The apex of a cycle is chosen when an UP
// node starts: H = max(apex(UP node), apex(next node)), each sampled if it has a range.
// A DOWN node ends at the control step whose phase is nearest 0.5, an UP node at the step
// nearest 1 (wrapped to 0). The release snaps the phase to exactly 0.5 (and 0) there, which
// drops up to half a step per node: a 1.4 m cycle of 42.8 steps runs in 42, so the clock gains
// 17 ms per cycle on a ball that really flies to 1.4 m. With `carry_phase` the overshoot is
// kept instead (φ continues from 0.5 + δ, 1 + δ → δ), and the clock keeps time with the ball.
//
// GraphCursor holds only immutable parameters; all mutable state is in CursorState.
#ifndef JUGGLE_ENVS_SOCCER_JUGGLE_GRAPH_CURSOR_H_
#define JUGGLE_ENVS_SOCCER_JUGGLE_GRAPH_CURSOR_H_

#include <vector>

#include "common/adaptive_walk.h"
#include "common/control_graph.h"
#include "common/rng.h"

namespace juggle::soccer_juggle {

struct CursorState {
  int current = -1;
  int next = -1;
  int next_next = -1;
  int entered_by = -1;          // edge that led into `current`; -1 for the episode's first node
  int edge_to_next = -1;        // sampled edge current -> next
  int edge_to_next_next = -1;   // sampled edge next -> next_next
  double phase = 0;             // φ ∈ [0, 1)
  double phase_speed = 0;       // φ per control step
  double apex_height = 0;       // H of the current flight (m)
  int completions = 0;          // nodes completed this episode
  // Juggles this episode: UP nodes completed (the ball reached its apex after a touch) and
  // STALL nodes left for another node.
  int juggles = 0;
};

// Desired ball state: x, y relative to the character's root (world axes), z absolute.
struct BallReference {
  double x = 0, y = 0, z = 0;
};

class GraphCursor {
 public:
  // REQUIRES: `graph` outlives this object; control_dt > 0, gravity > 0.
  GraphCursor(const ControlGraph* graph, double control_dt, double gravity,
              bool carry_phase = false);

  // Starts an episode at a uniformly drawn initial node with φ = 0 and samples the next two.
  void Reset(const AdaptiveWalk& walk, Rng* rng, CursorState* s) const;

  // Starts an episode at a given DOWN node (tests, tools); successors are sampled.
  void ResetAt(int node, const AdaptiveWalk& walk, Rng* rng, CursorState* s) const;

  // Advances one control step. On a transition, appends the events it causes to `events`
  // (kCompleted for the edge that entered the finished node, kChosen for the edge taken) and
  // returns true.
  bool Advance(const AdaptiveWalk& walk, Rng* rng, CursorState* s,
               std::vector<EdgeEvent>* events) const;

  // The walk's steering changed (AdaptiveWalk::SetSteering, the live page's skill choice):
  // `next_next` — the node after the coming one, which a DOWN node's kick already aims at — is
  // taken from the steering when it names an edge from `next`. `current` and `next` stay.
  // Returns true if next_next changed.
  bool Resteer(const AdaptiveWalk& walk, CursorState* s) const;

  // Appends the event for an episode that ends in `s` (kFailed for the edge into the current
  // node, if any). Time-limit truncation is not a failure: call nothing.
  void Fail(const CursorState& s, std::vector<EdgeEvent>* events) const;

  // Seconds from the nominal contact (φ = 0.5) at phase `phase`: negative before it. 0 for
  // STALL nodes.
  double SecondsFromContact(const CursorState& s, double phase) const;

  // Desired ball position at phase `phase` of the current node.
  BallReference DesiredBall(const CursorState& s, double phase) const;
  // Its velocity (m/s): vertical only, the derivative of DesiredBall over time.
  BallReference DesiredBallVelocity(const CursorState& s, double phase) const;

  // Half-cycle duration (s) of `node` under apex height `apex`.
  double HalfCycleSeconds(int node, double apex) const;


 private:
  double SampleApex(int node, Rng* rng) const;
  void UpdateSpeed(CursorState* s) const;

  const ControlGraph* graph_;
  double control_dt_;
  double gravity_;
  bool carry_phase_;
};

}  // namespace juggle::soccer_juggle

#endif  // JUGGLE_ENVS_SOCCER_JUGGLE_GRAPH_CURSOR_H_
