// Generalized advantage estimation over fixed-length unrolls, with termination and time-limit
// truncation kept apart. Plain C++ so it can be checked against hand-computed values.
#ifndef JUGGLE_LEARNER_ADVANTAGES_H_
#define JUGGLE_LEARNER_ADVANTAGES_H_

#include <cstddef>
#include <cstdint>
#include <vector>

namespace juggle {

struct AdvantageInputs {
  int num_unrolls = 0;
  int unroll_length = 0;
  const float* rewards = nullptr;         // [U, T]
  const uint8_t* done = nullptr;          // [U, T] terminated: no bootstrap
  const uint8_t* truncated = nullptr;     // [U, T] time limit: bootstrap from truncated_values
  const float* values = nullptr;          // [U, T] V(s_t)
  const float* bootstrap_values = nullptr;  // [U] V(s_T) after the unroll
  const float* truncated_values = nullptr;  // [num truncated] V(final obs), in (u, t) order
};

// δ_t = r_t + γ·V_next·(1 − done_t) − V(s_t), where V_next is V(s_{t+1}), the bootstrap value
// at t = T−1, or the truncated episode's final value; A_t = δ_t + γλ·A_{t+1}, with the
// recursion cut at done and truncated steps. Returns A [U, T]; returns_out = A + V.
std::vector<float> ComputeAdvantages(const AdvantageInputs& in, double gamma, double lambda,
                                     std::vector<float>* returns_out);

}  // namespace juggle

#endif  // JUGGLE_LEARNER_ADVANTAGES_H_
