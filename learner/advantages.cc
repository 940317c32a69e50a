#include "learner/advantages.h"

namespace juggle {

std::vector<float> ComputeAdvantages(const AdvantageInputs& in, double gamma, double lambda,
                                     std::vector<float>* returns_out) {
  const int U = in.num_unrolls, T = in.unroll_length;
  std::vector<float> adv(size_t(U) * T);
  // Index of each truncated step's final value, in (u, t) order.
  std::vector<int> trunc_index(size_t(U) * T, -1);
  int next = 0;
  for (int i = 0; i < U * T; ++i) {
    if (in.truncated[i]) trunc_index[i] = next++;
  }
  for (int u = 0; u < U; ++u) {
    double gae = 0;
    for (int t = T - 1; t >= 0; --t) {
      const int i = u * T + t;
      double next_value;
      bool cut = true;
      if (in.done[i]) {
        next_value = 0;
      } else if (in.truncated[i]) {
        next_value = in.truncated_values[trunc_index[i]];
      } else if (t == T - 1) {
        next_value = in.bootstrap_values[u];
      } else {
        next_value = in.values[i + 1];
        cut = false;
      }
      const double delta = in.rewards[i] + gamma * next_value - in.values[i];
      gae = delta + (cut ? 0.0 : gamma * lambda * gae);
      adv[i] = static_cast<float>(gae);
    }
  }
  if (returns_out != nullptr) {
    returns_out->resize(adv.size());
    for (size_t i = 0; i < adv.size(); ++i) (*returns_out)[i] = adv[i] + in.values[i];
  }
  return adv;
}

}  // namespace juggle
