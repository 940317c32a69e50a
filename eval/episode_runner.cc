#include "eval/episode_runner.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"

namespace juggle {
namespace {

absl::Status StartEpisode(int start_node, const AdaptiveWalk& walk, Env* env) {
  if (start_node < 0) {
    env->Reset(walk);
    return absl::OkStatus();
  }
  if (!env->ResetAt(start_node, walk)) {
    return absl::InvalidArgumentError("this env family cannot start an episode at a given node");
  }
  return absl::OkStatus();
}

// `node` clamped into [0, num_nodes) (families without a graph report node 0).
int NodeIndex(int node, int num_nodes) { return std::clamp(node, 0, num_nodes - 1); }

}  // namespace

TrajectoryBuilder EnvTrajectoryBuilder(const EnvSpec& spec, const std::string& config_path) {
  return TrajectoryBuilder(spec.family(), config_path, spec.control_dt(), spec.model()->nq,
                           spec.outcome_names(), spec.annotation_channels());
}

void CaptureEnv(const Env& env, double time, int episode, Outcome outcome,
                TrajectoryBuilder* builder) {
  std::vector<double> annotations;
  env.AppendAnnotations(&annotations);
  const Trajectory& t = builder->trajectory();
  annotations.resize(t.channels.size() - 3, 0.0);
  builder->Append(time, episode, env.steps() * t.control_dt, outcome, annotations.data(),
                  env.data()->qpos);
}

absl::StatusOr<EpisodeReport> RunEpisodes(std::shared_ptr<const EnvSpec> spec,
                                          Controller* controller, const EpisodeOptions& o) {
  if (o.episodes < 1) {
    return absl::InvalidArgumentError(absl::StrCat("episodes must be >= 1, got ", o.episodes));
  }
  if (o.first_episode < 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("first_episode must be >= 0, got ", o.first_episode));
  }
  const AdaptiveWalk walk(&spec->graph());
  const int n = o.episodes;
  const int obs_dim = spec->obs_dim(), act_dim = spec->act_dim();
  std::vector<std::unique_ptr<Env>> envs;
  std::vector<std::optional<TrajectoryBuilder>> recorders(n);
  for (int i = 0; i < n; ++i) {
    envs.push_back(spec->NewEnv(Rng::ForStream(o.seed, 0, static_cast<uint64_t>(o.first_episode + i))));
    if (absl::Status s = StartEpisode(o.start_node, walk, envs.back().get()); !s.ok()) return s;
    if (o.record) {
      recorders[i].emplace(EnvTrajectoryBuilder(*spec, o.config_path));
      CaptureEnv(*envs[i], 0.0, i, Outcome::kRunning, &*recorders[i]);
    }
  }
  EpisodeReport report;
  report.episodes.resize(n);
  const int num_nodes = std::max(1, spec->graph().num_nodes());
  for (int i = 0; i < n; ++i) {
    EpisodeResult& e = report.episodes[i];
    e.node_visits.assign(num_nodes, 0);
    e.node_completions.assign(num_nodes, 0);
    e.edge_events.Resize(spec->graph().num_edges());
    ++e.node_visits[NodeIndex(envs[i]->node(), num_nodes)];
  }
  // Running envs are compacted into the front of these batches every step.
  std::vector<int> running(n);
  for (int i = 0; i < n; ++i) running[i] = i;
  std::vector<const Env*> batch_envs(n);
  std::vector<float> obs(size_t(n) * obs_dim), actions(size_t(n) * act_dim);
  while (!running.empty()) {
    const int m = static_cast<int>(running.size());
    for (int k = 0; k < m; ++k) {
      batch_envs[k] = envs[running[k]].get();
      envs[running[k]]->WriteObservation(&obs[size_t(k) * obs_dim]);
    }
    controller->Act(batch_envs.data(), obs.data(), m, actions.data());
    std::vector<int> still;
    for (int k = 0; k < m; ++k) {
      const int i = running[k];
      Env& env = *envs[i];
      const int node_before = NodeIndex(env.node(), num_nodes);
      const int completions_before = env.completions();
      const StepResult r = env.Step(&actions[size_t(k) * act_dim], walk);
      EpisodeResult& e = report.episodes[i];
      e.return_sum += r.reward;
      const int completed = env.completions() - completions_before;
      e.node_completions[node_before] += std::max(0, completed);
      const int node_after = NodeIndex(env.node(), num_nodes);
      if (node_after != node_before || completed > 0) ++e.node_visits[node_after];
      for (const EdgeEvent& event : env.events()) e.edge_events.Add(event);
      if (o.record) CaptureEnv(env, env.steps() * spec->control_dt(), i, r.outcome, &*recorders[i]);
      if (r.outcome == Outcome::kRunning) {
        still.push_back(i);
        continue;
      }
      e.outcome = r.outcome;
      e.steps = env.steps();
      e.completions = env.completions();
      e.juggles = env.juggles();
      e.end_node = env.node();
      env.AppendEpisodeMetrics(&e.metrics);
      e.ending_detail = env.EndingDetail();
    }
    running = std::move(still);
  }
  if (o.record) {
    Trajectory all = recorders[0]->Take();
    for (int i = 1; i < n; ++i) AppendEpisode(recorders[i]->trajectory(), i, i, &all);
    report.trajectory = std::move(all);
  }
  return report;
}

absl::StatusOr<Trajectory> RecordRollout(std::shared_ptr<const EnvSpec> spec,
                                         Controller* controller, double seconds, uint64_t seed,
                                         int start_node, const std::string& config_path) {
  const AdaptiveWalk walk(&spec->graph());
  std::unique_ptr<Env> env = spec->NewEnv(Rng::ForStream(seed, 0, 0));
  TrajectoryBuilder recorder = EnvTrajectoryBuilder(*spec, config_path);
  const double dt = spec->control_dt();
  const int total_steps = std::max(0, static_cast<int>(std::ceil(seconds / dt - 1e-9)));
  int episode = 0;
  if (absl::Status s = StartEpisode(start_node, walk, env.get()); !s.ok()) return s;
  CaptureEnv(*env, 0.0, episode, Outcome::kRunning, &recorder);
  std::vector<float> obs(spec->obs_dim()), action(spec->act_dim());
  const Env* self = env.get();
  for (int step = 1; step <= total_steps; ++step) {
    env->WriteObservation(obs.data());
    controller->Act(&self, obs.data(), 1, action.data());
    const StepResult r = env->Step(action.data(), walk);
    CaptureEnv(*env, step * dt, episode, r.outcome, &recorder);
    if (r.outcome != Outcome::kRunning && step < total_steps) {
      ++episode;
      if (absl::Status s = StartEpisode(start_node, walk, env.get()); !s.ok()) return s;
      CaptureEnv(*env, step * dt, episode, Outcome::kRunning, &recorder);
    }
  }
  return recorder.Take();
}

}  // namespace juggle
