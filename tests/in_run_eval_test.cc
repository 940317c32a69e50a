// The in-run evaluation of `juggle train`: it runs when due, reports the juggles distribution,
// and does not change training — the same parameters with it on and off (synchronous mode,
// one worker: a run is reproducible).
#include <vector>

#include "common/testing/temp_dir.h"
#include "envs/registry.h"
#include "gtest/gtest.h"
#include "learner/checkpoint.h"
#include "learner/learner_server.h"
#include "learner/testing/recording_observer.h"
#include "tests/one_worker_training.h"

namespace juggle {
namespace {

struct TrainedRun {
  Sections checkpoint;
  std::vector<runlog::EvaluationRecord> evaluations;
  std::vector<runlog::IterationRecord> iterations;
};

// Trains `iterations` iterations (counted from the run's start) in `dir` (fresh: a new temp
// dir, removed afterwards).
TrainedRun Train(bool evaluate, int iterations, std::string dir = "", bool resume = false) {
  const bool keep = !dir.empty();
  if (!keep) dir = MakeTempDir("juggle_in_run_eval_");
  LearnerOptions o = TinyRunOptions(dir, iterations, /*evaluate_every=*/evaluate ? 1 : 0);
  o.resume = resume;
  RecordingObserver recorded;
  o.observers.push_back(&recorded);
  auto server = LearnerServer::Start(std::move(o));
  EXPECT_TRUE(server.ok()) << server.status();
  EXPECT_TRUE(TrainWithOneWorker(**server).ok());
  absl::StatusOr<CheckpointDir::Loaded> loaded = CheckpointDir(dir + "/checkpoints").LoadLatest();
  EXPECT_TRUE(loaded.ok()) << loaded.status();
  TrainedRun run;
  if (loaded.ok()) run.checkpoint = loaded->sections;
  run.evaluations = recorded.evaluations;
  run.iterations = recorded.iterations;
  if (!keep) std::system(("rm -rf " + dir).c_str());
  return run;
}

TEST(InRunEvalTest, RunsWhenDueAndDoesNotChangeTraining) {
  const TrainedRun with = Train(/*evaluate=*/true, 3);
  const TrainedRun without = Train(/*evaluate=*/false, 3);
  ASSERT_EQ(with.evaluations.size(), 3u);
  EXPECT_TRUE(without.evaluations.empty());
  for (size_t i = 0; i < with.evaluations.size(); ++i) {
    const runlog::EvaluationRecord& e = with.evaluations[i];
    EXPECT_EQ(e.iteration(), static_cast<int>(i + 1));
    EXPECT_EQ(e.episodes(), 3);
    EXPECT_GT(e.samples(), 0);
    EXPECT_EQ(e.juggles_size(), 3);
    EXPECT_GT(e.mean_episode_s(), 0);
    EXPECT_LE(e.mean_episode_s(), 2.0 + 1e-9);
  }
  // Everything the trainer and the walk hold is bit-identical: the networks, the normalizer,
  // the counters, the RNG and the edge counts. Not compared: the config and progress sections
  // (they record the evaluation settings and wall time) and the optimizer sections, whose torch
  // archives differ in bytes even between two identical runs (measured).
  ASSERT_FALSE(with.checkpoint.empty());
  int compared = 0;
  for (const auto& [name, bytes] : with.checkpoint) {
    if (name == "run_config" || name == "config_path" || name == "run_progress" ||
        name == "actor_opt" || name == "critic_opt") {
      continue;
    }
    ASSERT_TRUE(without.checkpoint.count(name)) << name;
    EXPECT_TRUE(bytes == without.checkpoint.at(name)) << "section " << name << " differs";
    ++compared;
  }
  EXPECT_GE(compared, 3);
}

TEST(InRunEvalTest, SamplesAndTrainingTimeAreCumulativeAcrossResume) {
  const std::string dir = MakeTempDir("juggle_resume_progress_");
  const TrainedRun first = Train(/*evaluate=*/false, 2, dir);
  ASSERT_EQ(first.iterations.size(), 2u);
  const TrainedRun resumed = Train(/*evaluate=*/false, 4, dir, /*resume=*/true);
  ASSERT_EQ(resumed.iterations.size(), 2u);
  const runlog::IterationRecord& last_before = first.iterations.back();
  const runlog::IterationRecord& first_after = resumed.iterations.front();
  EXPECT_EQ(first_after.iteration(), 3);
  EXPECT_EQ(first_after.samples(), last_before.samples() + first_after.iteration_samples());
  EXPECT_GT(first_after.train_s(), last_before.train_s());
  std::system(("rm -rf " + dir).c_str());
}

}  // namespace
}  // namespace juggle
