#include "common/unroll_batch.h"

#include <limits>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;

UnrollBatch GoodBatch() {
  UnrollBatch b;
  b.num_unrolls = 2;
  b.unroll_length = 3;
  b.obs_dim = 4;
  b.act_dim = 2;
  b.obs.assign(2 * 3 * 4, 0.5f);
  b.actions.assign(2 * 3 * 2, 0.1f);
  b.log_probs.assign(6, -1.0f);
  b.rewards.assign(6, 0.05f);
  b.done.assign(6, 0);
  b.truncated.assign(6, 0);
  b.bootstrap_obs.assign(2 * 4, 0.2f);
  b.policy_version.assign(2, 7);
  return b;
}

TEST(UnrollBatchTest, AcceptsAWellFormedBatch) {
  EXPECT_TRUE(ValidateUnrollBatch(GoodBatch(), 4, 2, 7, 0).ok());
}

TEST(UnrollBatchTest, RejectsWrongObservationSize) {
  UnrollBatch b = GoodBatch();
  b.obs.pop_back();
  const absl::Status s = ValidateUnrollBatch(b, 4, 2, 7, 0);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(s.message(), HasSubstr("'obs' has 23 entries, expected 24"));
}

TEST(UnrollBatchTest, RejectsDimensionsOtherThanThePolicys) {
  const absl::Status s = ValidateUnrollBatch(GoodBatch(), 5, 2, 7, 0);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(s.message(), HasSubstr("policy expects 5 and 2"));
}

TEST(UnrollBatchTest, RejectsNanReward) {
  UnrollBatch b = GoodBatch();
  b.rewards[4] = std::numeric_limits<float>::quiet_NaN();
  const absl::Status s = ValidateUnrollBatch(b, 4, 2, 7, 0);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(s.message(), HasSubstr("'rewards' has a non-finite value at index 4"));
}

TEST(UnrollBatchTest, RejectsInfiniteObservation) {
  UnrollBatch b = GoodBatch();
  b.bootstrap_obs[1] = std::numeric_limits<float>::infinity();
  EXPECT_THAT(ValidateUnrollBatch(b, 4, 2, 7, 0).message(), HasSubstr("'bootstrap_obs'"));
}

TEST(UnrollBatchTest, RejectsStepThatIsBothDoneAndTruncated) {
  UnrollBatch b = GoodBatch();
  b.done[2] = b.truncated[2] = 1;
  b.truncated_obs.assign(4, 0.f);
  EXPECT_THAT(ValidateUnrollBatch(b, 4, 2, 7, 0).message(), HasSubstr("both done and truncated"));
}

TEST(UnrollBatchTest, RejectsMissingTruncatedObservation) {
  UnrollBatch b = GoodBatch();
  b.truncated[1] = 1;
  EXPECT_THAT(ValidateUnrollBatch(b, 4, 2, 7, 0).message(),
              HasSubstr("'truncated_obs' has 0 entries, expected 4"));
}

TEST(UnrollBatchTest, RejectsUnknownFutureVersion) {
  UnrollBatch b = GoodBatch();
  b.policy_version[1] = 8;
  const absl::Status s = ValidateUnrollBatch(b, 4, 2, 7, 0);
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(s.message(), HasSubstr("unknown policy version 8"));
}

TEST(UnrollBatchTest, RejectsVersionBeyondTheAllowedLag) {
  UnrollBatch b = GoodBatch();
  b.policy_version[0] = 4;
  EXPECT_EQ(ValidateUnrollBatch(b, 4, 2, 7, 3).code(), absl::StatusCode::kOk);
  const absl::Status s = ValidateUnrollBatch(b, 4, 2, 7, 2);
  EXPECT_EQ(s.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(s.message(), HasSubstr("older than the allowed lag 2"));
}

TEST(UnrollBatchTest, RejectsEmptyBatch) {
  UnrollBatch b;
  EXPECT_EQ(ValidateUnrollBatch(b, 4, 2, 0, 0).code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace juggle
