// libFuzzer: a TrajectoryChunk from the wire (any bytes) through the learner's validation and
// assembly — DecodeChunk, then ContributionAssembler with the chunk as several parts and
// sequences, then both batch paths. Invariant: whatever is decoded is a consistent batch.
#include <cstdint>
#include <cstdlib>

#include "common/chunk_codec.h"
#include "learner/contribution_assembler.h"
#include "proto/rollout.pb.h"

namespace {

constexpr int kObsDim = 6, kActDim = 2, kNodes = 3, kEdges = 4, kEnvs = 8;

void Check(bool ok) {
  if (!ok) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  juggle::rpc::TrajectoryChunk chunk;
  if (!chunk.ParseFromArray(data, static_cast<int>(size))) return 0;
  absl::StatusOr<juggle::Contribution> decoded =
      juggle::DecodeChunk(chunk, kObsDim, kActDim, kNodes, kEdges);
  if (!decoded.ok()) return 0;
  const juggle::UnrollBatch& b = decoded->batch;
  Check(juggle::ValidateUnrollBatch(b, kObsDim, kActDim, chunk.policy_version(), 0).ok());
  Check(decoded->node.size() == size_t(b.num_samples()));
  juggle::ContributionAssembler assembler(/*versions_kept=*/2, /*wanted_unrolls=*/kEnvs);
  for (int64_t sequence = 0; sequence < 3; ++sequence) {
    for (int repeat = 0; repeat < 2; ++repeat) {  // a duplicate part is ignored
      juggle::ChunkPart part;
      part.slot = static_cast<int>(sequence % 2);
      part.incarnation = 7;
      part.sequence = sequence;
      part.part = chunk.part();
      part.num_parts = chunk.num_parts();
      part.version = chunk.policy_version();
      part.max_unrolls = kEnvs;
      part.data = *decoded;
      assembler.Add(std::move(part)).IgnoreError();
    }
  }
  Check(assembler.held_unrolls() >= 0 && assembler.evicted_unrolls() >= 0);
  int64_t dropped = 0;
  if (auto batch = assembler.TakeSync(chunk.policy_version(), {0, 1}, &dropped)) {
    Check(batch->batch.obs.size() == size_t(batch->batch.num_samples()) * kObsDim);
  }
  if (auto batch = assembler.TakeAsync(chunk.policy_version(), 1, 1, &dropped)) {
    Check(batch->batch.rewards.size() == size_t(batch->batch.num_samples()));
  }
  return 0;
}
