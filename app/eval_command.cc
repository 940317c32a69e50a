// `juggle eval`: runs a trained policy without exploration noise (the mean action) for a fixed
// set of seeded episodes, or the zero-action baseline, and reports episode statistics. The last
// line is key=value pairs including mean_completions= and mean_episode_s=.
#include <cstdio>
#include <optional>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "app/commands.h"
#include "app/flags.h"
#include "common/config_loader.h"
#include "common/eigen_policy.h"
#include "learner/learner_state.h"
#include "render/trajectory.h"
#include "common/env_family.h"
#include "worker/env_registry.h"
#include "worker/juggle_env.h"
#include "worker/toss_env.h"

namespace juggle {
namespace {

int Fail(const absl::Status& s) {
  std::fprintf(stderr, "error: %s\n", std::string(s.message()).c_str());
  return 1;
}

}  // namespace

int RunEval(int argc, char** argv, int first) {
  const std::vector<FlagSpec> specs = {
      {"checkpoint", "", "checkpoint file (.jglc) or run directory (newest readable checkpoint)"},
      {"config", "", "run config (default: the one recorded in the checkpoint)"},
      {"zero-action", "false", "evaluate the zero-action policy instead (baseline)"},
      {"episodes", "20", "episodes, one per env seed"},
      {"seed", "1000", "seed of the episode set"},
      {"record", "", "write every episode, one after another, as a trajectory (docs/recording.md)"},
  };
  absl::StatusOr<Flags> flags = Flags::Parse(argc, argv, first, specs);
  if (!flags.ok()) return Fail(flags.status());
  const bool zero = flags->GetBool("zero-action");
  if (flags->help() || (flags->Get("checkpoint").empty() && !zero)) {
    std::printf("usage: juggle eval --checkpoint=PATH | --zero-action --config=FILE [flags]\n%s",
                Flags::Usage(specs).c_str());
    return flags->help() ? 0 : 2;
  }
  std::optional<LoadedCheckpoint> checkpoint;
  if (!zero) {
    absl::StatusOr<LoadedCheckpoint> loaded = LoadCheckpoint(flags->Get("checkpoint"));
    if (!loaded.ok()) return Fail(loaded.status());
    checkpoint = std::move(*loaded);
    std::printf("checkpoint %s\n", checkpoint->path.c_str());
  }
  std::string config_path = flags->Get("config");
  if (config_path.empty() && checkpoint) config_path = checkpoint->config_path;
  if (config_path.empty()) return Fail(absl::InvalidArgumentError("--config is required"));
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(config_path);
  if (!config.ok()) return Fail(config.status());
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  if (!spec.ok()) return Fail(spec.status());
  const int obs_dim = (*spec)->obs_dim(), act_dim = (*spec)->act_dim();
  const bool record = !flags->Get("record").empty();
  if (record && EnvFamilyOf(config->run) != EnvFamily::kSoccer) {
    return Fail(absl::InvalidArgumentError(
        "--record writes soccer trajectories; for toss juggling use `juggle toss --record`"));
  }
  std::optional<EigenPolicy> policy;
  if (checkpoint) {
    absl::StatusOr<EigenPolicy> p = PolicyFromCheckpoint(checkpoint->sections, *config);
    if (!p.ok()) return Fail(p.status());
    policy = std::move(*p);
  }

  // Edge counts at their base weights: the same successor distribution for every policy.
  const AdaptiveWalk walk(&(*spec)->graph());
  const int episodes = static_cast<int>(*flags->GetInt("episodes"));
  const uint64_t seed = *flags->GetInt("seed");
  std::vector<std::unique_ptr<Env>> envs;
  for (int i = 0; i < episodes; ++i) {
    envs.push_back((*spec)->NewEnv(Rng::ForStream(seed, 0, i)));
    envs.back()->Reset(walk);
  }
  std::vector<float> obs(size_t(episodes) * obs_dim);
  std::vector<float> actions(size_t(episodes) * act_dim, 0.0f);
  std::vector<double> returns(episodes, 0);
  std::vector<int> lengths(episodes, 0), completions(episodes, 0);
  std::vector<Outcome> outcomes(episodes, Outcome::kRunning);
  const double dt = ControlDt(*config);
  std::vector<std::vector<TrajectorySample>> recorded(record ? episodes : 0);
  auto capture = [&](int i) { return CaptureSample(static_cast<const JuggleEnv&>(*envs[i])); };
  for (int i = 0; record && i < episodes; ++i) recorded[i].push_back(capture(i));
  int running = episodes;
  std::vector<Eigen::RowVectorXf> gate_rows;
  while (running > 0) {
    for (int i = 0; i < episodes; ++i) envs[i]->WriteObservation(&obs[size_t(i) * obs_dim]);
    if (policy) {
      const RowMatrix mean = policy->MeanActions(obs.data(), episodes);
      std::copy(mean.data(), mean.data() + mean.size(), actions.begin());
      // Gate statistics (paper Eq. 4) over the steps of running episodes.
      const RowMatrix g = policy->Gates(obs.data(), episodes);
      for (int i = 0; i < episodes && g.cols() > 0; ++i) {
        if (outcomes[i] == Outcome::kRunning) gate_rows.push_back(g.row(i));
      }
    }
    for (int i = 0; i < episodes; ++i) {
      if (outcomes[i] != Outcome::kRunning) continue;
      const StepResult r = envs[i]->Step(&actions[size_t(i) * act_dim], walk);
      returns[i] += r.reward;
      if (record) {
        TrajectorySample sample = capture(i);
        sample.episode_time = envs[i]->steps() * dt;
        sample.outcome = r.outcome;
        recorded[i].push_back(sample);
      }
      if (r.outcome != Outcome::kRunning) {
        outcomes[i] = r.outcome;
        lengths[i] = envs[i]->steps();
        completions[i] = envs[i]->completions();
        --running;
      }
    }
  }
  double ret = 0, len = 0, comp = 0;
  std::vector<int> outcome_counts(static_cast<int>(Outcome::kNumOutcomes), 0);
  for (int i = 0; i < episodes; ++i) {
    ret += returns[i];
    len += lengths[i];
    comp += completions[i];
    ++outcome_counts[static_cast<int>(outcomes[i])];
  }
  if (record) {
    // Episodes one after another on the recording's clock.
    Trajectory t;
    t.config_path = config_path;
    t.control_dt = dt;
    for (int n = 0; n < (*spec)->graph().num_nodes(); ++n) {
      t.node_names.push_back((*spec)->graph().node(n).name);
    }
    double offset = 0;
    for (int i = 0; i < episodes; ++i) {
      for (TrajectorySample sample : recorded[i]) {
        sample.episode = i;
        sample.time = offset + sample.episode_time;
        t.samples.push_back(sample);
      }
      offset += recorded[i].back().episode_time;
    }
    if (absl::Status s = WriteTrajectory(t, flags->Get("record")); !s.ok()) return Fail(s);
    std::printf("recorded %d episodes (%.2f s) to %s\n", episodes, offset,
                flags->Get("record").c_str());
  }
  std::string outcome_text;
  for (int o = 1; o < static_cast<int>(Outcome::kNumOutcomes); ++o) {
    if (outcome_counts[o]) {
      absl::StrAppend(&outcome_text, " ", OutcomeName(static_cast<Outcome>(o)), "=",
                      outcome_counts[o]);
    }
  }
  // Throw task: how far the releases were from the target point and velocity.
  double position_error = 0, velocity_error = 0;
  int releases = 0;
  for (int i = 0; i < episodes; ++i) {
    const auto* toss = dynamic_cast<const TossEnv*>(envs[i].get());
    if (toss == nullptr || outcomes[i] != Outcome::kReleased) continue;
    position_error += toss->release_position_error();
    velocity_error += toss->release_velocity_error();
    ++releases;
  }
  if (releases > 0) {
    absl::StrAppend(&outcome_text,
                    absl::StrFormat(" mean_release_position_error=%.4f mean_release_velocity_error=%.4f",
                                    position_error / releases, velocity_error / releases));
  }
  if (!gate_rows.empty()) {
    RowMatrix gates(gate_rows.size(), gate_rows[0].size());
    for (size_t i = 0; i < gate_rows.size(); ++i) gates.row(i) = gate_rows[i];
    const GateStatistics g = ComputeGateStatistics(gates);
    absl::StrAppend(&outcome_text, absl::StrFormat(" gate_specialization=%.3f gate_utilization=%.3f",
                                                   g.specialization, g.utilization));
  }
  std::printf("policy=%s episodes=%d mean_return=%.4f mean_completions=%.3f mean_episode_s=%.3f%s\n",
              zero ? "zero_action" : "checkpoint", episodes, ret / episodes, comp / episodes,
              len / episodes * dt, outcome_text.c_str());
  return 0;
}

}  // namespace juggle
