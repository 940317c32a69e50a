// The rollout collector hands its labeller the acting policy: every label of an unroll is asked
// for with the policy of that unroll set, and none is left set after it (envs/labeller.h).
#include "worker/rollout_collector.h"

#include <vector>

#include "common/testing/constant_policy.h"
#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"
#include "worker/env_pool.h"

namespace juggle {
namespace {

// Labels zeros and records which policy was set at each label and each SetPolicy call.
class RecordingLabeller final : public Labeller {
 public:
  absl::Status Label(const Env&, float* action) override {
    std::fill(action, action + act_dim, 0.0f);
    seen_at_labels.push_back(policy_);
    return absl::OkStatus();
  }
  absl::Status SetPolicy(const EigenPolicy* policy) override {
    policy_ = policy;
    set_calls.push_back(policy);
    return absl::OkStatus();
  }
  int act_dim = 0;
  std::vector<const EigenPolicy*> seen_at_labels, set_calls;

 private:
  const EigenPolicy* policy_ = nullptr;
};

TEST(RolloutCollectorTest, TheLabellerSeesTheActingPolicyDuringItsUnrollOnly) {
  absl::StatusOr<LoadedConfig> config =
      LoadRunConfig(testing::RepoPath("tests/data/tiny_right_foot.textproto"));
  ASSERT_TRUE(config.ok()) << config.status();
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  ASSERT_TRUE(spec.ok()) << spec.status();
  absl::StatusOr<std::unique_ptr<EnvPool>> pool = EnvPool::Create(*spec, 2, 1, 1);
  ASSERT_TRUE(pool.ok()) << pool.status();
  RolloutCollector collector(pool->get(), /*unroll_length=*/5, /*seed=*/1);
  RecordingLabeller labeller;
  labeller.act_dim = (*spec)->act_dim();
  LabelPlan plan;
  plan.labeller = &labeller;
  plan.label_envs = 1;
  collector.set_label_plan(plan);
  const EigenPolicy first =
      testing::ConstantPolicy((*spec)->obs_dim(), (*spec)->act_dim(), 0.1f);
  const EigenPolicy second =
      testing::ConstantPolicy((*spec)->obs_dim(), (*spec)->act_dim(), -0.1f);
  UnrollBatch batch;
  ASSERT_TRUE(collector.Collect(first, &batch).ok());
  ASSERT_TRUE(collector.Collect(second, &batch).ok());
  ASSERT_EQ(labeller.seen_at_labels.size(), 10u);  // 1 labelled env × 5 steps × 2 unrolls
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(labeller.seen_at_labels[i], i < 5 ? &first : &second) << "label " << i;
  }
  EXPECT_EQ(labeller.set_calls,
            (std::vector<const EigenPolicy*>{&first, nullptr, &second, nullptr}));
}

}  // namespace
}  // namespace juggle
