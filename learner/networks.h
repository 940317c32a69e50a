// libtorch networks: layer-wise MoE (the paper's), plain MLP and output-blended MoE, with the
// parameter layout of common/network_layout.h so they export to the Eigen inference as is.
// Includes torch: include only from learner .cc files, tests and benchmarks.
#ifndef JUGGLE_LEARNER_NETWORKS_H_
#define JUGGLE_LEARNER_NETWORKS_H_

#include <string>
#include <utility>
#include <vector>

#include <torch/torch.h>

#include "common/flat_parameters.h"
#include "common/network_layout.h"
#include "proto/run_config.pb.h"

namespace juggle {

class TorchNetwork : public torch::nn::Module {
 public:
  // Initializes as the release: expert/MLP weights orthogonal with gain `gain` per expert
  // (`out_gain` on the last layer), biases a random unit-norm row × gain, gate layers with
  // PyTorch's Linear default (uniform ±1/√fan_in). Draws from torch's default generator.
  TorchNetwork(const config::ModelConfig& model, const std::string& prefix, int in_dim,
               int out_dim, bool tanh_output, double gain, double out_gain);

  // x: [B, in] → [B, out]. MoE layers are per-expert products blended by the gate.
  torch::Tensor forward(const torch::Tensor& x);
  // The same function computed by building per-sample blended weight matrices
  // (LAYERWISE_MOE only): memory O(B·in·out). For tests and the benchmark.
  torch::Tensor ForwardWeightBlended(const torch::Tensor& x);
  // Gate weights [B, K] (MoE only).
  torch::Tensor Gate(const torch::Tensor& x);

  // Parameters in layout order, with their layout entries.
  std::vector<std::pair<TensorSpec, torch::Tensor>> LayoutTensors() const;
  bool is_moe() const { return architecture_ != config::MLP; }

 private:
  config::Architecture architecture_;
  bool tanh_output_;
  std::vector<TensorSpec> layout_;
  std::vector<torch::Tensor> gate_w_, gate_b_, w_, b_;  // w_/b_: experts [K,in,out] or MLP [in,out]
};

// Actor (tanh mean), critic (identity), log-std and the observation normalizer as buffers.
class ActorCritic : public torch::nn::Module {
 public:
  ActorCritic(const config::ModelConfig& model, int obs_dim, int act_dim);

  torch::Tensor Normalize(const torch::Tensor& obs);
  // Mean action [B, act_dim] and value [B] of raw observations.
  torch::Tensor Mean(const torch::Tensor& obs) { return actor->forward(Normalize(obs)); }
  torch::Tensor Value(const torch::Tensor& obs) {
    return critic->forward(Normalize(obs)).squeeze(-1);
  }
  // Σ log N(a; μ, exp(log_std)) per row, as common/eigen_policy.h's GaussianLogProb.
  torch::Tensor LogProb(const torch::Tensor& actions, const torch::Tensor& mean);

  std::shared_ptr<TorchNetwork> actor, critic;
  torch::Tensor log_std;        // [act_dim]; a parameter only if learned
  torch::Tensor norm_mean;      // [obs_dim] buffer
  torch::Tensor norm_inv_std;   // [obs_dim] buffer
  bool normalize = false;
  int obs_dim, act_dim;
};

// Appends `t` (float, any shape) under `spec` to a flat layout and its values.
void AppendTensor(const TensorSpec& spec, const torch::Tensor& t, std::vector<TensorSpec>* layout,
                  std::vector<float>* values);

// What a worker needs to act (common/eigen_policy.h's layout): the actor's tensors,
// "actor.log_std" and, with `normalizer`, "obs_norm.mean" / "obs_norm.inv_std".
FlatParameters ExportActorParameters(const ActorCritic& net, int64_t version, bool normalizer);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_NETWORKS_H_
