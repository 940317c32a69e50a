// Well-formed random contributions for the service benchmarks (ingest, broadcast, soak): they
// pass the learner's validation; their values mean nothing.
#ifndef JUGGLE_BENCH_SYNTHETIC_CONTRIBUTION_H_
#define JUGGLE_BENCH_SYNTHETIC_CONTRIBUTION_H_

#include "common/chunk_codec.h"

namespace juggle {

// `unrolls` unrolls of `T` steps with normal observations, small uniform actions, node ids
// cycling over `num_nodes`, policy version 0; the same for the same arguments.
Contribution SyntheticContribution(int obs_dim, int act_dim, int unrolls, int T, int num_nodes);

}  // namespace juggle

#endif  // JUGGLE_BENCH_SYNTHETIC_CONTRIBUTION_H_
