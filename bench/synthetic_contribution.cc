#include "bench/synthetic_contribution.h"

#include "common/rng.h"

namespace juggle {

Contribution SyntheticContribution(int obs_dim, int act_dim, int unrolls, int T, int num_nodes) {
  Contribution c;
  UnrollBatch& b = c.batch;
  b.num_unrolls = unrolls;
  b.unroll_length = T;
  b.obs_dim = obs_dim;
  b.act_dim = act_dim;
  Rng rng(5);
  const size_t n = size_t(unrolls) * T;
  b.obs.resize(n * obs_dim);
  for (float& x : b.obs) x = static_cast<float>(rng.Normal());
  b.actions.resize(n * act_dim);
  for (float& x : b.actions) x = static_cast<float>(rng.Uniform(-0.1, 0.1));
  b.log_probs.assign(n, 10.0f);
  b.rewards.assign(n, 0.05f);
  b.done.assign(n, 0);
  b.truncated.assign(n, 0);
  b.bootstrap_obs.assign(size_t(unrolls) * obs_dim, 0.1f);
  b.policy_version.assign(unrolls, 0);
  c.node.resize(n);
  for (size_t i = 0; i < n; ++i) c.node[i] = static_cast<int32_t>(i % num_nodes);
  return c;
}

}  // namespace juggle
