// One soccer-juggling environment: a humanoid and a ball in MuJoCo, driven by stable PD
// tracking of the control graph's reference pose plus the policy's feed-forward torques and
// the base controller's (base_controller.h).
//
// Control step (50 Hz) = `substeps` physics steps (400 Hz). Order within Step():
//   1. the kick feedback's swing change, then the reference pose and ball reference at the
//      current (pre-step) phase; the policy's and the base controller's feed-forward torques;
//   2. per substep: PD + feed-forward torques into qfrc_applied, mj_step, divergence check,
//      ball-contact checks (allowed bodies, timing window, ball height);
//   3. advance the graph cursor (transitions, edge events);
//   4. termination checks and the reward (reward.h: the post-step state vs the step-1
//      reference, and the kick term).
// Episodes start as start_state.h says. The env does not reset itself; EnvPool does.
// Thread-compatible: one thread at a time.
#ifndef JUGGLE_ENVS_SOCCER_JUGGLE_ENV_H_
#define JUGGLE_ENVS_SOCCER_JUGGLE_ENV_H_

#include <array>
#include <memory>
#include <vector>

#include <mujoco/mujoco.h>

#include "common/adaptive_walk.h"
#include "common/rng.h"
#include "envs/env.h"
#include "envs/env_snapshot.h"
#include "envs/mujoco_model.h"
#include "envs/soccer_juggle/base_controller.h"
#include "envs/soccer_juggle/graph_cursor.h"
#include "envs/soccer_juggle/outcomes.h"
#include "envs/soccer_juggle/reference_pose.h"
#include "envs/soccer_juggle/reward.h"
#include "envs/soccer_juggle/spec.h"

namespace juggle::soccer_juggle {

// The env's own variables of an episode (the physics is in its mjData). Copyable: a snapshot
// is this plus the physics.
struct JuggleEnvState {
  Rng rng{0};
  CursorState cursor;
  CharacterPose reference{};  // the PD target
  SwingAdjust swing_adjust;  // env.kick_feedback's change of the current leg swing
  std::vector<EdgeEvent> events;
  int steps = 0;
  // The current cycle's kick: the ball touched an allowed body, and the kick was rewarded.
  bool kick_touched = false;
  bool kick_rewarded = false;
  bool touched_this_step = false;
  int touched_body = -1;  // the body of the step's first allowed touch (−1: none this step)
  // The geom the ball met in the contact that ended the episode as a bad contact (−1: none).
  int bad_contact_geom = -1;
  RewardTerms reward;  // the last step's reward, term by term (zero after a reset)
  // The last step's action as applied (clamped; zeros after a reset).
  std::array<float, kNumActions> previous_action{};
};

class JuggleSnapshot final : public EnvSnapshot {
 public:
  std::string family() const override { return "soccer_juggle"; }
  JuggleEnvState state;
};

class JuggleEnv : public juggle::Env {
 public:
  JuggleEnv(std::shared_ptr<const JuggleSpec> spec, Rng rng);
  JuggleEnv(const JuggleEnv&) = delete;
  JuggleEnv& operator=(const JuggleEnv&) = delete;

  // Starts an episode at a random initial node (start_state.h: character at the reference
  // pose, ball at its apex, both at rest, then varied by env().start()). Events are cleared.
  void Reset(const AdaptiveWalk& walk) override;
  // Starts an episode at DOWN node `node` (REQUIRES: a DOWN node). Returns true.
  bool ResetAt(int node, const AdaptiveWalk& walk) override;

  // The node after the coming one follows the walk's new steering (GraphCursor::Resteer).
  void Resteer(const AdaptiveWalk& walk) override;

  // Advances one control step. REQUIRES: `action` holds kNumActions values in [−1, 1] (clamped
  // here) and the episode has not ended. Events of this step: events().
  StepResult Step(const float* action, const AdaptiveWalk& walk) override;

  // Observation of the current state. REQUIRES: `obs` holds spec().obs_dim() floats.
  void WriteObservation(float* obs) const override;

  const std::vector<EdgeEvent>& events() const override { return s_.events; }
  const CursorState& cursor() const { return s_.cursor; }
  const JuggleSpec& spec() const { return *spec_; }
  int steps() const override { return s_.steps; }
  int node() const override { return s_.cursor.current; }
  int completions() const override { return s_.cursor.completions; }
  // Completed UP and STALL nodes: touches that sent the ball on to the next node's apex (or held
  // it through a stall step).
  int juggles() const override { return s_.cursor.juggles; }
  // Simulator state, for tests and tools (render, record). Mutating it is the caller's risk.
  mjData* data() override { return data_.get(); }
  const mjData* data() const override { return data_.get(); }
  // node, phase (JuggleSpec::annotation_channels).
  void AppendAnnotations(std::vector<double>* out) const override;
  // After a bad contact: the body the ball met (its geom's name for the world's, e.g. "floor").
  std::string EndingDetail() const override;
  // The episode's exact state; Restore continues it bit for bit (envs/env_snapshot.h).
  std::unique_ptr<EnvSnapshot> Snapshot() const override;
  // INVALID_ARGUMENT (nothing changed) for a snapshot of another family, model or config.
  absl::Status Restore(const EnvSnapshot& snapshot) override;
  // The episode's own variables (cursor, kick flags, the kick feedback's swing change, ...).
  const JuggleEnvState& state() const { return s_; }
  // Reference pose the PD tracked during the last step (or set at reset).
  const CharacterPose& reference_pose() const { return s_.reference; }
  // Around-the-world (NodeSpec.around_the_world) while the current node checks its foot–ball
  // angle: the angle's squared chord from the desired one over the bound's (the episode ends
  // above 1); 0 in every other node and step.
  double AroundTheWorldViolation() const;

 private:
  // The episode's counters and kick restart from zero; the physics at the start of the
  // cursor's node (PlaceAtStart).
  void StartEpisode();
  // PD + feed-forward torques and the constant force on the ball (env.ball_force).
  void ApplyTorques(const double* feedforward);
  // Also notes an allowed touch of the ball in s_.touched_this_step.
  Outcome CheckBallContacts(double substep_phase);
  Outcome CheckTermination(const BallReference& ball_ref) const;
  // The around-the-world angle's squared chord from the desired one, or −1 where it is not
  // checked (AroundTheWorldViolation).
  double AroundTheWorldChord2() const;
  // Follows the current cycle's kick — a touch this step sets kick_touched — and returns reward
  // term 5 at its release (the first step after the touch with the ball going up; once per kick,
  // and only with reward.w_kick on), 0 otherwise.
  float TrackKick();
  bool Diverged() const;

  std::shared_ptr<const JuggleSpec> spec_;
  const mjModel* model_;
  MjDataPtr data_;
  BaseController base_;
  // Everything of the episode beside the physics: what a snapshot copies.
  JuggleEnvState s_;
};

}  // namespace juggle::soccer_juggle

#endif  // JUGGLE_ENVS_SOCCER_JUGGLE_ENV_H_
