// Networks: the layer-wise MoE equals the weight-blended formulation (outputs and gradients),
// the Eigen inference equals libtorch for every architecture, and the sizes match the release.
#include "learner/networks.h"

#include <vector>

#include "common/eigen_policy.h"
#include "gtest/gtest.h"
#include "learner/ppo_trainer.h"

namespace juggle {
namespace {

config::ModelConfig Model(config::Architecture arch, int experts = 4) {
  config::ModelConfig m;
  m.set_architecture(arch);
  m.set_num_experts(experts);
  m.add_hidden(32);
  m.add_hidden(24);
  m.add_gate_hidden(16);
  m.add_gate_hidden(16);
  m.add_mlp_hidden(48);
  m.add_mlp_hidden(40);
  return m;
}

TEST(NetworksTest, LayerwiseAndWeightBlendedMoeGiveSameOutputsAndGradients) {
  torch::manual_seed(1);
  TorchNetwork net(Model(config::LAYERWISE_MOE), "actor", 10, 6, true, 1.0, 1.0);
  const torch::Tensor x = torch::randn({17, 10});
  const torch::Tensor y1 = net.forward(x);
  const torch::Tensor y2 = net.ForwardWeightBlended(x);
  EXPECT_TRUE(torch::allclose(y1, y2, 1e-5, 1e-6));

  const torch::Tensor target = torch::randn({17, 6});
  auto grads = [&](bool layerwise) {
    net.zero_grad();
    const torch::Tensor y = layerwise ? net.forward(x) : net.ForwardWeightBlended(x);
    ((y - target).pow(2).sum()).backward();
    std::vector<torch::Tensor> g;
    for (const torch::Tensor& p : net.parameters()) g.push_back(p.grad().clone());
    return g;
  };
  const std::vector<torch::Tensor> g1 = grads(true), g2 = grads(false);
  ASSERT_EQ(g1.size(), g2.size());
  for (size_t i = 0; i < g1.size(); ++i) {
    EXPECT_TRUE(torch::allclose(g1[i], g2[i], 1e-4, 1e-6)) << "parameter " << i;
    EXPECT_GT(g1[i].abs().sum().item<double>(), 0.0) << "parameter " << i << " got no gradient";
  }
}

class EigenParityTest : public ::testing::TestWithParam<config::Architecture> {};

TEST_P(EigenParityTest, EigenActorMatchesLibtorchWithin1e5Relative) {
  config::ModelConfig model = Model(GetParam());
  config::PpoConfig ppo;
  ppo.set_normalize_observations(false);
  PpoTrainer trainer(model, ppo, 12, 5, /*seed=*/3);
  const FlatParameters params = trainer.ExportAll();

  torch::manual_seed(4);
  const torch::Tensor x = torch::randn({33, 12}) * 2;
  ActorCritic reference(model, 12, 5);
  // Load the exported values into a fresh libtorch network through the layout: an
  // independent path from the trainer's own modules.
  {
    torch::NoGradGuard no_grad;
    for (auto* net : {reference.actor.get(), reference.critic.get()}) {
      for (auto& [spec, t] : net->LayoutTensors()) {
        const float* v = *params.Find(spec.name, spec.shape);
        t.copy_(torch::from_blob(const_cast<float*>(v), t.sizes(), torch::kFloat32));
      }
    }
  }
  const torch::Tensor torch_mean = reference.Mean(x).detach();
  const torch::Tensor torch_value = reference.Value(x).detach();

  auto policy = EigenPolicy::Create(model, params, 12, 5);
  ASSERT_TRUE(policy.ok()) << policy.status();
  const torch::Tensor xc = x.contiguous();
  const RowMatrix eigen_mean = policy->MeanActions(xc.data_ptr<float>(), 33);
  auto critic = EigenNetwork::Create(model, params, "critic", 12, 1, EigenNetwork::Output::kIdentity);
  ASSERT_TRUE(critic.ok()) << critic.status();
  const RowMatrix eigen_value = critic->Forward(Eigen::Map<const RowMatrix>(xc.data_ptr<float>(), 33, 12));
  for (int b = 0; b < 33; ++b) {
    for (int i = 0; i < 5; ++i) {
      const float t = torch_mean[b][i].item<float>();
      EXPECT_NEAR(eigen_mean(b, i), t, 1e-5 * std::max(1.0f, std::abs(t)));
    }
    const float v = torch_value[b].item<float>();
    EXPECT_NEAR(eigen_value(b, 0), v, 1e-5 * std::max(1.0f, std::abs(v)));
  }
}

INSTANTIATE_TEST_SUITE_P(AllArchitectures, EigenParityTest,
                         ::testing::Values(config::LAYERWISE_MOE, config::MLP, config::OUTPUT_MOE));

TEST(NetworksTest, ReferenceSizesGive693268Parameters) {
  config::ModelConfig model;  // defaults: 8 experts, [128, 128], gate [128, 128]
  ActorCritic net(model, 157, 28);
  int64_t count = 0;
  for (const torch::Tensor& p : net.parameters()) count += p.numel();
  // The release's count includes its (unused) 28-entry log_std; here log_std is a buffer
  // unless learned.
  EXPECT_EQ(count + 28, 693268);
}

TEST(NetworksTest, OutputBlendedMoeHasTheLayerwiseParameterCount) {
  config::ModelConfig layerwise, output;
  output.set_architecture(config::OUTPUT_MOE);
  int64_t a = 0, b = 0;
  for (const torch::Tensor& p : ActorCritic(layerwise, 157, 28).parameters()) a += p.numel();
  for (const torch::Tensor& p : ActorCritic(output, 157, 28).parameters()) b += p.numel();
  EXPECT_EQ(a, b);
}

TEST(NetworksTest, TorchLogProbEqualsWorkerGaussianLogProb) {
  config::ModelConfig model;
  ActorCritic net(model, 4, 3);
  const torch::Tensor mean = torch::tensor({{0.1f, -0.2f, 0.3f}});
  const torch::Tensor action = torch::tensor({{0.15f, -0.1f, 0.2f}});
  const double torch_lp = net.LogProb(action, mean).item<double>();
  const std::vector<float> m = {0.1f, -0.2f, 0.3f}, a = {0.15f, -0.1f, 0.2f};
  const std::vector<float> ls(3, static_cast<float>(model.log_std()));
  EXPECT_NEAR(torch_lp, GaussianLogProb(a.data(), m.data(), ls.data(), 3), 1e-4);
}

TEST(NetworksTest, GateRowsAreDistributionsOverExperts) {
  TorchNetwork net(Model(config::LAYERWISE_MOE, 5), "actor", 7, 2, true, 1.0, 1.0);
  const torch::Tensor g = net.Gate(torch::randn({9, 7}));
  EXPECT_EQ(g.size(1), 5);
  EXPECT_TRUE(torch::allclose(g.sum(1), torch::ones({9}), 1e-5, 1e-6));
  EXPECT_GE(g.min().item<float>(), 0.0f);
}

TEST(NetworksTest, GateStatisticsMatchTheirDefinitionOnTorchGates) {
  // One-hot gates: specialization 1; all experts equally used: utilization 1/K.
  RowMatrix onehot = RowMatrix::Zero(8, 4);
  for (int i = 0; i < 8; ++i) onehot(i, i % 4) = 1;
  GateStatistics s = ComputeGateStatistics(onehot);
  EXPECT_NEAR(s.specialization, 1.0, 1e-12);
  EXPECT_NEAR(s.utilization, 0.25, 1e-12);
  // Uniform gates: specialization 1/K, utilization 1/K.
  s = ComputeGateStatistics(RowMatrix::Constant(5, 4, 0.25f));
  EXPECT_NEAR(s.specialization, 0.25, 1e-7);
  EXPECT_NEAR(s.utilization, 0.25, 1e-7);

  // The Eigen policy's gates equal libtorch's, and Eq. 4 on them equals a direct torch sum.
  config::ModelConfig model = Model(config::LAYERWISE_MOE);
  config::PpoConfig ppo;
  PpoTrainer trainer(model, ppo, 12, 5, 8);
  const FlatParameters params = trainer.ExportPolicy();
  ActorCritic reference(model, 12, 5);
  {
    torch::NoGradGuard no_grad;
    for (auto& [spec, t] : reference.actor->LayoutTensors()) {
      const float* v = *params.Find(spec.name, spec.shape);
      t.copy_(torch::from_blob(const_cast<float*>(v), t.sizes(), torch::kFloat32));
    }
  }
  const torch::Tensor x = torch::randn({40, 12}).contiguous();
  const torch::Tensor g = reference.actor->Gate(x).detach();
  const double torch_spec = g.pow(2).sum(1).mean().item<double>();
  const double torch_util = g.mean(0).pow(2).sum().item<double>();
  auto policy = EigenPolicy::Create(model, params, 12, 5);
  ASSERT_TRUE(policy.ok());
  const GateStatistics eigen = ComputeGateStatistics(policy->Gates(x.data_ptr<float>(), 40));
  EXPECT_NEAR(eigen.specialization, torch_spec, 1e-5);
  EXPECT_NEAR(eigen.utilization, torch_util, 1e-5);
}

}  // namespace
}  // namespace juggle
