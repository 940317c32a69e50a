// Planner-guided training end to end (learner + one worker over loopback, the real planner
// labelling real envs): labels reach the demonstration buffer, expert-driven unrolls stay out
// of PPO's samples, pretraining clones and then PPO runs with the scheduled weight, and the run
// log carries it all. Offline demonstrations (imitation.initial_demos_file) seed a run without
// labellers, and a file that is missing or of other dims is refused when the run starts.
#include <string>

#include "common/file_io.h"
#include "common/rng.h"
#include "common/testing/temp_dir.h"
#include "learner/demo_buffer.h"
#include "gtest/gtest.h"
#include "learner/learner_server.h"
#include "learner/run_log.h"
#include "common/eigen_policy.h"
#include "envs/labeller.h"
#include "envs/registry.h"
#include "planner/planner_labeller.h"
#include "tests/one_worker_training.h"

namespace juggle {
namespace {

constexpr int kIterations = 3, kT = 20, kEnvs = 4;  // tests/data/tiny_right_foot.textproto

LearnerOptions GuidedOptions(const std::string& dir) {
  LearnerOptions o = TinyRunOptions(dir, kIterations, /*evaluate_every=*/0);
  config::ImitationConfig* im = o.config.run.mutable_imitation();
  im->set_label_envs(2);
  im->set_expert_envs(1);
  im->set_pretrain_iterations(2);
  im->set_min_buffer(1);
  im->set_clone_steps(3);
  im->set_clone_minibatch(16);
  im->set_weight(0.5);
  im->set_decay(0.9);
  // A small, fast planner: the test checks the plumbing, not the labels' quality.
  config::PlannerConfig* p = o.config.run.mutable_planner();
  p->set_samples(4);
  p->set_iterations(1);
  p->set_horizon_steps(8);
  p->set_body_knot_steps(0);
  p->set_threads(1);
  return o;
}

TEST(GuidedTrainingTest, LabelsFillTheBufferAndPretrainingHandsOverToPpoWithImitation) {
  const std::string dir = MakeTempDir("juggle_guided_training_");
  auto server = LearnerServer::Start(GuidedOptions(dir));
  ASSERT_TRUE(server.ok()) << server.status();
  ASSERT_TRUE(TrainWithOneWorker(**server, MakePlannerLabeller).ok());

  absl::StatusOr<RunLog> log = ReadRunLog(RunLogPath(dir));
  ASSERT_TRUE(log.ok()) << log.status();
  int iterations = 0;
  for (const runlog::RunLogRecord& r : log->records) {
    if (!r.has_iteration()) continue;
    const runlog::IterationRecord& it = r.iteration();
    ++iterations;
    SCOPED_TRACE(it.iteration());
    // Every iteration: 2 labelled unrolls of 4, one of them the expert's.
    EXPECT_DOUBLE_EQ(it.labelled_share(), 2.0 / kEnvs);
    EXPECT_EQ(it.demo_buffer(), 2.0 * kT * it.iteration());
    EXPECT_EQ(it.expert_samples(), double(kT) * it.iteration());
    EXPECT_GT(it.imitation_loss(), 0);
    EXPECT_GT(it.imitation_fresh_error(), 0);  // held-out: the fresh labels of this iteration
    // The loop view: what the planner spent on this iteration's labels.
    EXPECT_EQ(it.expert_labels(), 2.0 * kT);
    EXPECT_GT(it.expert_replans(), 0);
    EXPECT_GT(it.expert_rollout_steps(), it.expert_replans()) << "rollouts of several steps";
    EXPECT_EQ(it.expert_proposal_tried(), 0) << "no policy_prior, no proposal";
    if (it.iteration() <= 2) {
      EXPECT_TRUE(it.cloning_only());
      EXPECT_EQ(it.imitation_weight(), 0);
    } else {
      EXPECT_FALSE(it.cloning_only());
      EXPECT_DOUBLE_EQ(it.imitation_weight(), 0.5);
    }
  }
  EXPECT_EQ(iterations, kIterations);
  EXPECT_EQ((*server)->metrics().Get("juggle_demo_labels_total"), 2.0 * kT * kIterations);
}

// The planner's labeller, recording the mean action at a zero observation of every proposal
// policy it is handed (one per unroll).
class ProposalRecorder final : public Labeller {
 public:
  ProposalRecorder(std::unique_ptr<Labeller> inner, std::vector<std::vector<float>>* seen, int obs_dim)
      : inner_(std::move(inner)), seen_(seen), obs_dim_(obs_dim) {}
  absl::Status Label(const Env& env, float* action) override { return inner_->Label(env, action); }
  absl::Status SetPolicy(const EigenPolicy* policy) override {
    if (policy != nullptr) {
      const std::vector<float> zero(obs_dim_, 0.0f);
      const RowMatrix mean = policy->MeanActions(zero.data(), 1);
      seen_->emplace_back(mean.data(), mean.data() + mean.size());
    }
    return inner_->SetPolicy(policy);
  }
  ExpertCounters TakeCounters() override { return inner_->TakeCounters(); }

 private:
  std::unique_ptr<Labeller> inner_;
  std::vector<std::vector<float>>* seen_;
  int obs_dim_;
};

// Expert iteration on the rollout service (planner.policy_prior): the worker's planner plans on
// top of the policy it was broadcast, its labels reach the learner, and newer policies reach the
// planner as the learner trains; the labels are not those of the planner alone.
TEST(GuidedTrainingTest, ThePlannerProposesWithEachBroadcastPolicyAndItsLabelsReachTheLearner) {
  std::vector<std::string> demos;
  std::vector<std::vector<float>> proposals;
  for (bool prior : {false, true}) {
    SCOPED_TRACE(prior);
    const std::string dir = MakeTempDir("juggle_guided_proposal_");
    LearnerOptions o = GuidedOptions(dir);
    o.config.run.mutable_planner()->set_policy_prior(prior);
    auto server = LearnerServer::Start(o);
    ASSERT_TRUE(server.ok()) << server.status();
    const LabellerFactory recording = [&proposals, prior](std::shared_ptr<const EnvSpec> spec,
                                                          const LoadedConfig& config, int worker)
        -> absl::StatusOr<std::unique_ptr<Labeller>> {
      absl::StatusOr<std::unique_ptr<Labeller>> inner = MakePlannerLabeller(spec, config, worker);
      if (!inner.ok() || !prior) return inner;
      return std::unique_ptr<Labeller>(
          std::make_unique<ProposalRecorder>(*std::move(inner), &proposals, spec->obs_dim()));
    };
    ASSERT_TRUE(TrainWithOneWorker(**server, recording).ok());
    EXPECT_EQ((*server)->metrics().Get("juggle_demo_labels_total"), 2.0 * kT * kIterations);
    // The policy's share of chosen candidates reaches the learner only with the proposal.
    const double tried = (*server)->metrics().Get("juggle_expert_proposal_tried_total");
    const double replans = (*server)->metrics().Get("juggle_expert_replans_total");
    if (prior) {
      EXPECT_GT(tried, 0);
      EXPECT_LE(tried, replans);
      EXPECT_LE((*server)->metrics().Get("juggle_expert_proposal_chosen_total"), tried);
    } else {
      EXPECT_EQ(tried, 0);
    }
    absl::StatusOr<std::string> bytes = ReadFile(dir + "/demos.jgld");
    ASSERT_TRUE(bytes.ok()) << bytes.status();
    demos.push_back(*bytes);
  }
  ASSERT_GE(proposals.size(), size_t(kIterations)) << "one proposal per unroll";
  EXPECT_NE(proposals.front(), proposals.back()) << "newer policies reach the planner";
  EXPECT_NE(demos[0], demos[1]) << "the proposal changes the labels";
}

// A demonstration file of `rows` random (observation, label) pairs of these dims at `path`.
void WriteDemos(const std::string& path, int rows, int obs_dim, int act_dim) {
  DemoBuffer demos(rows, obs_dim, act_dim);
  Rng rng(11);
  std::vector<float> obs, labels;
  for (int i = 0; i < rows * obs_dim; ++i) obs.push_back(float(rng.Normal()));
  for (int i = 0; i < rows * act_dim; ++i) labels.push_back(float(rng.Uniform(-0.5, 0.5)));
  demos.AddPairs(obs.data(), labels.data(), rows);
  ASSERT_TRUE(WriteFileAtomically(path, demos.Serialize()).ok());
}

TEST(GuidedTrainingTest, OfflineDemonstrationsSeedARunWithoutLabellers) {
  const std::string dir = MakeTempDir("juggle_guided_offline_");
  LearnerOptions o = GuidedOptions(dir);
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(o.config);
  ASSERT_TRUE(spec.ok()) << spec.status();
  constexpr int kRows = 300;
  ASSERT_NO_FATAL_FAILURE(
      WriteDemos(dir + "/offline.jgld", kRows, (*spec)->obs_dim(), (*spec)->act_dim()));
  config::ImitationConfig* im = o.config.run.mutable_imitation();
  im->set_label_envs(0);
  im->set_expert_envs(0);
  im->set_initial_demos_file(dir + "/offline.jgld");
  auto server = LearnerServer::Start(o);
  ASSERT_TRUE(server.ok()) << server.status();
  ASSERT_TRUE(TrainWithOneWorker(**server).ok());  // no labeller: none is asked for

  absl::StatusOr<RunLog> log = ReadRunLog(RunLogPath(dir));
  ASSERT_TRUE(log.ok()) << log.status();
  int iterations = 0;
  for (const runlog::RunLogRecord& r : log->records) {
    if (!r.has_iteration()) continue;
    const runlog::IterationRecord& it = r.iteration();
    ++iterations;
    SCOPED_TRACE(it.iteration());
    EXPECT_EQ(it.labelled_share(), 0);
    EXPECT_EQ(it.demo_buffer(), kRows);  // the offline pairs, and nothing more
    EXPECT_GT(it.imitation_loss(), 0);
    EXPECT_EQ(it.cloning_only(), it.iteration() <= 2);
  }
  EXPECT_EQ(iterations, kIterations);

  // Resumed, the run keeps its own buffer (demos.jgld): the file is not added a second time.
  o.resume = true;
  o.max_iterations = kIterations + 1;
  auto resumed = LearnerServer::Start(o);
  ASSERT_TRUE(resumed.ok()) << resumed.status();
  ASSERT_TRUE(TrainWithOneWorker(**resumed).ok());
  log = ReadRunLog(RunLogPath(dir));
  ASSERT_TRUE(log.ok()) << log.status();
  double last_buffer = -1;
  for (const runlog::RunLogRecord& r : log->records) {
    if (r.has_iteration()) last_buffer = r.iteration().demo_buffer();
  }
  EXPECT_EQ(last_buffer, kRows);
}

TEST(GuidedTrainingTest, MissingOrMismatchedOfflineDemonstrationsAreRefusedAtTheStart) {
  const std::string dir = MakeTempDir("juggle_guided_offline_refused_");
  LearnerOptions o = GuidedOptions(dir);
  o.config.run.mutable_imitation()->set_initial_demos_file(dir + "/none.jgld");
  absl::StatusOr<std::unique_ptr<LearnerServer>> server = LearnerServer::Start(o);
  ASSERT_FALSE(server.ok());
  EXPECT_NE(server.status().message().find("imitation.initial_demos_file"), std::string::npos)
      << server.status();
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(o.config);
  ASSERT_TRUE(spec.ok()) << spec.status();
  ASSERT_NO_FATAL_FAILURE(
      WriteDemos(dir + "/wide.jgld", 10, (*spec)->obs_dim() + 1, (*spec)->act_dim()));
  o.config.run.mutable_imitation()->set_initial_demos_file(dir + "/wide.jgld");
  server = LearnerServer::Start(o);
  ASSERT_FALSE(server.ok());
  EXPECT_EQ(server.status().code(), absl::StatusCode::kInvalidArgument) << server.status();
  EXPECT_NE(server.status().message().find("observations"), std::string::npos)
      << server.status();
}

TEST(GuidedTrainingTest, AWorkerWithoutAnExpertRefusesARunThatAsksForLabels) {
  const std::string dir = MakeTempDir("juggle_guided_refused_");
  LearnerOptions o = GuidedOptions(dir);
  auto server = LearnerServer::Start(o);
  ASSERT_TRUE(server.ok()) << server.status();
  std::atomic<bool> stop{false};
  WorkerOptions wo;
  wo.learner_address = absl::StrCat("127.0.0.1:", (*server)->port());
  wo.num_envs = kEnvs;
  wo.num_threads = 1;
  wo.stop = &stop;
  wo.verbose = false;
  const absl::Status s = RunWorker(wo);
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition) << s;
  EXPECT_NE(s.message().find("imitation.label_envs"), std::string::npos) << s;
  (*server)->Shutdown();
}

}  // namespace
}  // namespace juggle
