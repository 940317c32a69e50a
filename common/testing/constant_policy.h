// A test policy whose mean action is tanh(bias) for every action, whatever it observes: an MLP
// with zero weights and output bias `bias` (tests that need a policy with a known action).
#ifndef JUGGLE_COMMON_TESTING_CONSTANT_POLICY_H_
#define JUGGLE_COMMON_TESTING_CONSTANT_POLICY_H_

#include <algorithm>
#include <vector>

#include "common/eigen_policy.h"
#include "common/flat_parameters.h"
#include "common/network_layout.h"

namespace juggle::testing {

inline EigenPolicy ConstantPolicy(int obs_dim, int act_dim, float bias) {
  config::ModelConfig model;
  model.set_architecture(config::MLP);
  model.add_mlp_hidden(4);
  std::vector<TensorSpec> layout = NetworkLayout(model, "actor", obs_dim, act_dim);
  layout.push_back({"actor.log_std", {act_dim}});
  int64_t total = 0;
  for (const TensorSpec& t : layout) total += t.numel();
  std::vector<float> values(total, 0.0f);
  int64_t offset = 0;
  for (const TensorSpec& t : layout) {
    if (t.name == "actor.b1") std::fill_n(values.begin() + offset, act_dim, bias);
    offset += t.numel();
  }
  return *EigenPolicy::Create(model, *FlatParameters::Create(1, layout, values), obs_dim, act_dim);
}

}  // namespace juggle::testing

#endif  // JUGGLE_COMMON_TESTING_CONSTANT_POLICY_H_
