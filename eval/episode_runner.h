// Runs a controller in an env family's envs, without exploration noise and without feeding the
// walk (the edge counts stay at their base weights, so every controller meets the same
// successor distribution): the evaluation loop of `juggle eval`, `juggle render`, the in-run
// evaluation of `juggle train` and the evaluation tables. Family-free; thread-compatible.
#ifndef JUGGLE_EVAL_EPISODE_RUNNER_H_
#define JUGGLE_EVAL_EPISODE_RUNNER_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "envs/env.h"
#include "eval/controller.h"
#include "record/trajectory.h"

namespace juggle {

struct EpisodeResult {
  double return_sum = 0;
  int steps = 0;
  int completions = 0;
  int juggles = 0;
  Outcome outcome = Outcome::kRunning;
  int end_node = 0;                 // the node the episode ended in
  std::vector<NamedValue> metrics;  // Env::AppendEpisodeMetrics
  std::string ending_detail;        // Env::EndingDetail (e.g. the body a bad contact met)
  // Per graph node, indexed by node id (one entry, node 0, for families without a graph),
  // from Env::node() and Env::completions() around every step: a visit starts at the reset and
  // whenever a step changes the node or completes one (a node can follow itself); a completion
  // counts for the node the env was in before the step.
  std::vector<int> node_visits;
  std::vector<int> node_completions;
  // The walk's edge events the env reported (Env::events), per edge of the graph: chosen (the
  // walk entered the edge's target), completed (the target was completed), failed (the
  // episode ended in it). Sized to the graph's edges (none without a graph).
  WalkEventTotals edge_events;
};

struct EpisodeOptions {
  int episodes = 20;
  uint64_t seed = 1000;    // episode i runs in an env drawing from Rng::ForStream(seed, 0,
  int first_episode = 0;   // first_episode + i), so one evaluation can be split into parts
  int start_node = -1;     // >= 0: every episode starts at this graph node (Env::ResetAt)
  bool record = false;     // keep every episode as a trajectory, one after another
  std::string config_path; // for the recording's header
};

struct EpisodeReport {
  std::vector<EpisodeResult> episodes;  // in episode (seed) order
  std::optional<Trajectory> trajectory; // when recorded
};

// Runs options.episodes episodes side by side (one env each, batched inference), each to its
// end (the env's time limit truncates). Errors: INVALID_ARGUMENT for episodes < 1 or a
// start_node the family cannot start at.
absl::StatusOr<EpisodeReport> RunEpisodes(std::shared_ptr<const EnvSpec> spec,
                                          Controller* controller, const EpisodeOptions& options);

// A builder for recordings of `spec`'s envs (its outcome names and annotation channels).
TrajectoryBuilder EnvTrajectoryBuilder(const EnvSpec& spec, const std::string& config_path);
// Appends `env`'s current state to `builder` at recording time `time`.
void CaptureEnv(const Env& env, double time, int episode, Outcome outcome,
                TrajectoryBuilder* builder);

// One env for `seconds` of control (rounded up to whole steps) from stream (seed, 0, 0),
// resetting at episode ends (at `start_node` if >= 0), recorded: the first sample is the reset
// state at time 0. What `juggle render` shows.
absl::StatusOr<Trajectory> RecordRollout(std::shared_ptr<const EnvSpec> spec,
                                         Controller* controller, double seconds, uint64_t seed,
                                         int start_node, const std::string& config_path);

}  // namespace juggle

#endif  // JUGGLE_EVAL_EPISODE_RUNNER_H_
