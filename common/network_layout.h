// The parameter layout of a policy or value network, shared by the libtorch learner and the
// Eigen inference on workers: tensor names, shapes and order for each architecture.
//
// Naming (`prefix` is "actor" or "critic"):
//   MoE (both kinds):  prefix.gate_w{i} [in_i, out_i], prefix.gate_b{i} [out_i]  (gating MLP,
//                      last layer outputs K logits), prefix.expert_w{l} [K, in_l, out_l],
//                      prefix.expert_b{l} [K, out_l]
//   MLP:               prefix.w{l} [in_l, out_l], prefix.b{l} [out_l]
// Weights are stored [in, out] (y = x·W + b), row-major float32.
#ifndef JUGGLE_COMMON_NETWORK_LAYOUT_H_
#define JUGGLE_COMMON_NETWORK_LAYOUT_H_

#include <cstdint>
#include <string>
#include <vector>

#include "proto/run_config.pb.h"

namespace juggle {

struct TensorSpec {
  std::string name;
  std::vector<int64_t> shape;
  int64_t numel() const {
    int64_t n = 1;
    for (int64_t d : shape) n *= d;
    return n;
  }
};

// Effective sizes with the documented defaults applied.
std::vector<int> ExpertHidden(const config::ModelConfig& m);   // default {128, 128}
std::vector<int> GateHidden(const config::ModelConfig& m);     // default {128, 128}
std::vector<int> MlpHidden(const config::ModelConfig& m);      // default {1024, 1024}

// Layer widths in -> hidden... -> out for the network's main path.
std::vector<int> LayerWidths(const config::ModelConfig& m, int in_dim, int out_dim);

// The tensors of one network, in canonical order.
std::vector<TensorSpec> NetworkLayout(const config::ModelConfig& m, const std::string& prefix,
                                      int in_dim, int out_dim);

}  // namespace juggle

#endif  // JUGGLE_COMMON_NETWORK_LAYOUT_H_
