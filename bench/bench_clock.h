// The benchmarks' wall clock: seconds elapsed since a steady-clock time point.
#ifndef JUGGLE_BENCH_BENCH_CLOCK_H_
#define JUGGLE_BENCH_BENCH_CLOCK_H_

#include <chrono>

namespace juggle {

inline double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace juggle

#endif  // JUGGLE_BENCH_BENCH_CLOCK_H_
