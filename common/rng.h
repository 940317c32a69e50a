// Deterministic random numbers. Every stream derives from (run seed, worker, env index);
// nothing is seeded from the clock. Thread-compatible: one Rng per thread or env.
#ifndef JUGGLE_COMMON_RNG_H_
#define JUGGLE_COMMON_RNG_H_

#include <cstdint>

namespace juggle {

// xoshiro256** seeded through splitmix64. Small, fast, and identical on every platform
// (std:: distributions are not, so the helpers below are written out).
class Rng {
 public:
  explicit Rng(uint64_t seed);
  // The stream for one env of one worker of a run.
  static Rng ForStream(uint64_t run_seed, uint64_t worker, uint64_t env);

  uint64_t NextU64();
  // Uniform in [0, 1).
  double Uniform();
  // Uniform in [lo, hi).
  double Uniform(double lo, double hi);
  // Uniform integer in [0, n); n > 0.
  uint64_t UniformInt(uint64_t n);
  // Standard normal (Box–Muller, no cached second value so the state stays a pure function of
  // the number of calls).
  double Normal();

 private:
  uint64_t s_[4];
};

// splitmix64 step: a good 64-bit mixer for deriving seeds.
uint64_t SplitMix64(uint64_t* state);

}  // namespace juggle

#endif  // JUGGLE_COMMON_RNG_H_
