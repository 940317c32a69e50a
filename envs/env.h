// The environment interface EnvPool, RolloutCollector and the evaluation loop run, whatever the
// family (envs/registry.h lists them). EnvSpec holds what never changes during a run (the
// compiled model, sizes, the control graph) and makes envs; Env is one episode's mutable state.
#ifndef JUGGLE_ENVS_ENV_H_
#define JUGGLE_ENVS_ENV_H_

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <mujoco/mujoco.h>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"

#include "common/adaptive_walk.h"
#include "common/control_graph.h"
#include "common/outcome.h"
#include "common/rng.h"
#include "envs/env_snapshot.h"
#include "record/trajectory.h"

namespace juggle {

struct StepResult {
  float reward = 0;
  Outcome outcome = Outcome::kRunning;
  // Ended without bootstrapping: every outcome but running and the time limit (a caught ball
  // and a release end toss episodes this way too).
  bool terminated() const { return outcome != Outcome::kRunning && outcome != Outcome::kTimeLimit; }
  bool truncated() const { return outcome == Outcome::kTimeLimit; }
};

// A named number about an episode (e.g. "release_velocity_error") or a recorded channel value.
struct NamedValue {
  std::string name;
  double value = 0;
};

// One environment. Thread-compatible: one thread at a time. Envs do not reset themselves.
class Env {
 public:
  virtual ~Env() = default;
  // Starts an episode; events are cleared.
  virtual void Reset(const AdaptiveWalk& walk) = 0;
  // Starts an episode at graph node `node` (tools: render --node). False, with nothing
  // changed, for families that cannot.
  virtual bool ResetAt(int node, const AdaptiveWalk& walk) { return false; }
  // The walk's steering changed (AdaptiveWalk::SetSteering: the live page's skill choice):
  // families with a graph re-draw the successors not yet committed to. Default: nothing.
  virtual void Resteer(const AdaptiveWalk& walk) {}
  // Advances one control step. REQUIRES: `action` holds act_dim values (clamped to [−1, 1] by
  // the env) and the episode has not ended.
  virtual StepResult Step(const float* action, const AdaptiveWalk& walk) = 0;
  // REQUIRES: `obs` holds obs_dim floats.
  virtual void WriteObservation(float* obs) const = 0;
  // Edge events of the last step (empty for families without a control graph).
  virtual const std::vector<EdgeEvent>& events() const { return no_events_; }
  // Control steps of the current episode.
  virtual int steps() const = 0;
  // Node id the env is in (graph node; 0 for families without a graph).
  virtual int node() const { return 0; }
  // Successes of the current episode so far (nodes completed; toss: 1 after a catch or a
  // release).
  virtual int completions() const = 0;
  // Juggles of the current episode so far: touches that sent the ball on to where it had to go
  // (soccer: completed UP and stall nodes; toss: good throws). The evaluation's headline number.
  virtual int juggles() const { return completions(); }
  // Simulator state, for tests and tools. Mutating it is the caller's risk.
  virtual mjData* data() = 0;
  virtual const mjData* data() const = 0;
  // Named numbers about the episode that just ended (after the step that ended it), e.g. a
  // throw's release errors. The evaluation averages each over the episodes that report it.
  virtual void AppendEpisodeMetrics(std::vector<NamedValue>* out) const {}
  // What ended the episode, in words, where its outcome alone does not say (soccer: the body
  // a bad contact met, "floor" for the turf); empty for nothing more or a running episode.
  virtual std::string EndingDetail() const { return {}; }
  // The family's annotation channels of the current state, in the order of
  // EnvSpec::annotation_channels() (soccer: node, phase; toss: hand modes). Recorded with
  // every trajectory sample (record/trajectory.h).
  virtual void AppendAnnotations(std::vector<double>* out) const {}
  // An exact copy of the episode's state (envs/env_snapshot.h): an env of an equal spec that
  // restores it steps bit for bit as this one would. Null for families without snapshots.
  virtual std::unique_ptr<EnvSnapshot> Snapshot() const { return nullptr; }
  // Replaces this env's state with `snapshot`'s. INVALID_ARGUMENT (nothing changed) for a
  // snapshot of another family, model or config; UNIMPLEMENTED for families without snapshots.
  virtual absl::Status Restore(const EnvSnapshot& snapshot) {
    return absl::UnimplementedError(
        absl::StrCat("the ", snapshot.family(), " snapshot cannot be restored: this env family "
                     "has no snapshots"));
  }

 private:
  std::vector<EdgeEvent> no_events_;
};

class EnvSpec : public std::enable_shared_from_this<EnvSpec> {
 public:
  virtual ~EnvSpec() = default;
  // The family's name, as in RunConfig's `family` oneof ("soccer_juggle", "toss").
  virtual std::string family() const = 0;
  virtual int obs_dim() const = 0;
  virtual int act_dim() const = 0;
  // Seconds of simulated time per env step.
  virtual double control_dt() const = 0;
  // The control graph the adaptive walk runs on (empty for families without one).
  virtual const ControlGraph& graph() const = 0;
  virtual const mjModel* model() const = 0;
  // Names of every outcome value this family's envs return, indexed by value (starts with
  // CommonOutcomeNames()).
  virtual std::vector<std::string> outcome_names() const = 0;
  // The channels Env::AppendAnnotations writes (default: none).
  virtual std::vector<AnnotationChannel> annotation_channels() const { return {}; }
  // A new env drawing from `rng`. REQUIRES: this spec is owned by a shared_ptr.
  virtual std::unique_ptr<Env> NewEnv(Rng rng) const = 0;
  // The family's own summary of an evaluation, appended to `juggle eval`'s last line (e.g.
  // football's "ksr=... kdd_deg=..."), from every episode's Env::AppendEpisodeMetrics in order.
  // Default: empty (nothing appended).
  virtual std::string EvaluationLine(
      const std::vector<std::vector<NamedValue>>& episode_metrics) const {
    return {};
  }
  // Whether an episode's headline count is juggles (Env::juggles): `juggle eval`'s last line
  // then starts with their distribution. False for families whose episode is one attempt
  // (football), whose own EvaluationLine says how it went.
  virtual bool counts_juggles() const { return true; }
  // Identifies the compiled model and the family's config (equal specs, equal fingerprints):
  // snapshots restore only into envs of a spec with the snapshot's fingerprint.
  uint64_t fingerprint() const { return fingerprint_; }

 protected:
  // Called once by the family's builder when the model is final: the fingerprint of the
  // model and of `config_bytes` (the family's serialized config section).
  void SetFingerprint(const std::string& config_bytes) {
    fingerprint_ = Fingerprint(config_bytes, ModelFingerprint(model()));
  }
  // A planning variant (envs/planning_model.h) takes the fingerprint of the spec it stands in
  // for: its envs restore that spec's snapshots.
  void ShareFingerprint(const EnvSpec& exact) { fingerprint_ = exact.fingerprint(); }

 private:
  uint64_t fingerprint_ = 0;
};

}  // namespace juggle

#endif  // JUGGLE_ENVS_ENV_H_
