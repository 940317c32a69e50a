// Offline cloning of a demonstration buffer (learner/demo_fit.h): labels that are a smooth
// function of the observation are learned and generalize to the held-out rows; labels that
// are noise are memorized at best and do not; the held-out rows are the newest, also after the
// buffer wrapped.
#include "learner/demo_fit.h"

#include <cmath>
#include <string>

#include "common/eigen_policy.h"
#include "common/rng.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

constexpr int kObs = 4, kAct = 2;

// One labelled unroll of `n` steps: observations uniform in [−1, 1]; labels a smooth function
// of them, or noise independent of them.
UnrollBatch Labelled(int n, bool smooth, uint64_t seed, float first_key = 0) {
  Rng rng(seed);
  UnrollBatch b;
  b.num_unrolls = 1;
  b.unroll_length = n;
  b.obs_dim = kObs;
  b.act_dim = kAct;
  b.labelled = {1};
  for (int i = 0; i < n; ++i) {
    float o[kObs];
    for (float& x : o) x = static_cast<float>(rng.Uniform(-1, 1));
    o[3] = first_key + i;  // a key: where the row came in
    b.obs.insert(b.obs.end(), o, o + kObs);
    if (smooth) {
      b.labels.push_back(0.5f * std::tanh(2 * o[0]) + 0.2f * o[1]);
      b.labels.push_back(0.3f * o[1] * o[2]);
    } else {
      b.labels.push_back(static_cast<float>(rng.Uniform(-0.5, 0.5)));
      b.labels.push_back(static_cast<float>(rng.Uniform(-0.5, 0.5)));
    }
  }
  return b;
}

config::ModelConfig SmallMlp() {
  config::ModelConfig m;
  m.set_architecture(config::MLP);
  m.add_mlp_hidden(64);
  m.add_mlp_hidden(64);
  m.set_init_gain(1.0);
  return m;
}

TEST(DemoFitTest, SmoothLabelsAreLearnedAndGeneralizeToTheNewestRows) {
  DemoBuffer demos(4000, kObs, kAct);
  demos.AddLabelled(Labelled(2000, true, 1));
  DemoFitOptions options;
  options.epochs = 40;
  options.minibatch = 64;
  options.actions = {0, 1};
  absl::StatusOr<std::vector<DemoFitEpoch>> fit = FitDemos(demos, SmallMlp(), options);
  ASSERT_TRUE(fit.ok()) << fit.status();
  ASSERT_EQ(fit->size(), 40u);
  const DemoFitEpoch& first = fit->front(), &last = fit->back();
  EXPECT_LT(last.held_out_error, 0.1 * first.held_out_error + 1e-3);
  EXPECT_LT(last.held_out_error, 0.05);
  EXPECT_GT(last.action_r2[0], 0.9);
  ASSERT_EQ(last.action_rms.size(), 2u);
}

// The fitted actor, exported as a worker's policy (Eigen inference, no torch), scores the
// same held-out error as the fit reports: the saved policy is the fitted network.
TEST(DemoFitTest, TheExportedFitActsAsTheFittedNetwork) {
  DemoBuffer demos(4000, kObs, kAct);
  demos.AddLabelled(Labelled(1000, true, 5));
  DemoFitOptions options;
  options.epochs = 10;
  options.minibatch = 32;
  FlatParameters fitted;
  absl::StatusOr<std::vector<DemoFitEpoch>> fit =
      FitDemos(demos, SmallMlp(), options, nullptr, &fitted);
  ASSERT_TRUE(fit.ok()) << fit.status();
  absl::StatusOr<EigenPolicy> policy = EigenPolicy::Create(SmallMlp(), fitted, kObs, kAct);
  ASSERT_TRUE(policy.ok()) << policy.status();
  // Rows are in the order added (no wrap): the newest 200 are held out.
  const int held = 200, train = 800;
  double mean[kAct] = {0}, var[kAct] = {0};
  for (int i = 0; i < train; ++i) {
    for (int a = 0; a < kAct; ++a) mean[a] += demos.labels()[i * kAct + a] / train;
  }
  for (int i = 0; i < train; ++i) {
    for (int a = 0; a < kAct; ++a) {
      var[a] += std::pow(demos.labels()[i * kAct + a] - mean[a], 2) / train;
    }
  }
  const RowMatrix actions = policy->MeanActions(demos.obs() + train * kObs, held);
  double error = 0;
  for (int i = 0; i < held; ++i) {
    for (int a = 0; a < kAct; ++a) {
      const double w = 1.0 / std::max(var[a], options.min_label_std * options.min_label_std);
      error += w * std::pow(actions(i, a) - demos.labels()[(train + i) * kAct + a], 2);
    }
  }
  error /= held * kAct;
  EXPECT_NEAR(error, fit->back().held_out_error, 1e-4 + 1e-3 * error);
  EXPECT_LT(error, 0.1);
}

TEST(DemoFitTest, NoiseLabelsDoNotGeneralize) {
  DemoBuffer demos(4000, kObs, kAct);
  demos.AddLabelled(Labelled(600, false, 2));
  DemoFitOptions options;
  options.epochs = 60;
  options.minibatch = 32;
  options.actions = {0};
  absl::StatusOr<std::vector<DemoFitEpoch>> fit = FitDemos(demos, SmallMlp(), options);
  ASSERT_TRUE(fit.ok()) << fit.status();
  // In units of the label variance, a mean-only predictor scores 1 on the held-out rows; a
  // student cannot do better than that on noise, whatever it does on the rows it saw.
  EXPECT_GT(fit->back().held_out_error, 0.9);
  EXPECT_LT(fit->back().train_error, fit->back().held_out_error);
  EXPECT_LT(fit->back().action_r2[0], 0.05);
}

// --train-rows: a learning curve against one held-out set. Fewer training rows fit the same
// held-out rows worse; a limit beyond the training share changes nothing.
TEST(DemoFitTest, FewerTrainingRowsFitTheSameHeldOutRowsWorse) {
  DemoBuffer demos(4000, kObs, kAct);
  demos.AddLabelled(Labelled(2000, true, 4));
  DemoFitOptions options;
  options.epochs = 30;
  options.minibatch = 16;
  auto held_out = [&](int64_t train_rows) {
    options.train_rows = train_rows;
    absl::StatusOr<std::vector<DemoFitEpoch>> fit = FitDemos(demos, SmallMlp(), options);
    EXPECT_TRUE(fit.ok()) << fit.status();
    return fit.ok() ? fit->back().held_out_error : 0.0;
  };
  const double all = held_out(0), few = held_out(60), beyond = held_out(100000);
  EXPECT_GT(few, 2 * all);
  EXPECT_EQ(beyond, all);
}

TEST(DemoFitTest, TheHeldOutRowsAreTheNewestAlsoAfterTheBufferWrapped) {
  // 150 rows in a buffer of 100: rows 50..149 are held, the oldest at row 50 % 100.
  DemoBuffer demos(100, kObs, kAct);
  demos.AddLabelled(Labelled(150, true, 3));
  ASSERT_EQ(demos.size(), 100);
  EXPECT_EQ(demos.oldest(), 50);
  EXPECT_EQ(demos.obs()[demos.oldest() * kObs + 3], 50.0f);  // the key of the oldest pair
  // Parse without being told the sizes keeps the order.
  absl::StatusOr<DemoBuffer> parsed = DemoBuffer::Parse(demos.Serialize());
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  EXPECT_EQ(parsed->oldest(), 50);
  EXPECT_EQ(parsed->capacity(), 100);
  EXPECT_EQ(parsed->obs_dim(), kObs);
}

TEST(DemoFitTest, TooFewRowsOrAnUnknownActionAreRefused) {
  DemoBuffer demos(10, kObs, kAct);
  demos.AddLabelled(Labelled(2, true, 4));
  DemoFitOptions options;
  EXPECT_EQ(FitDemos(demos, SmallMlp(), options).status().code(),
            absl::StatusCode::kInvalidArgument);
  demos.AddLabelled(Labelled(8, true, 5));
  options.rows = 2;  // the oldest 2 of 10: too few again
  EXPECT_EQ(FitDemos(demos, SmallMlp(), options).status().code(),
            absl::StatusCode::kInvalidArgument);
  options.rows = 0;
  options.obs_prefix = kObs + 1;
  EXPECT_EQ(FitDemos(demos, SmallMlp(), options).status().code(),
            absl::StatusCode::kInvalidArgument);
  options.obs_prefix = 0;
  options.actions = {kAct};
  EXPECT_EQ(FitDemos(demos, SmallMlp(), options).status().code(),
            absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(DemoBuffer::Parse(std::string("JGLDEMO1")).status().code(),
            absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace juggle
