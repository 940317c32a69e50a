// Exact copies of an env's state, for planners that simulate copies of the present (planner/):
// a snapshot restored into another env of an equal spec makes that env step exactly as the
// original would, bit for bit, for the same actions.
//
// PhysicsSnapshot copies everything of an mjData that the next mj_step or the env reads: the
// whole main buffer (state, controls, applied forces, solver warm start, and the derived
// quantities of the last step that envs read between steps: contacts, body poses, COM) and the
// header's time, sizes and warning counters. MuJoCo's scratch stack and timers are not copied.
// Thread-compatible.
#ifndef JUGGLE_ENVS_ENV_SNAPSHOT_H_
#define JUGGLE_ENVS_ENV_SNAPSHOT_H_

#include <cstdint>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "absl/status/status.h"

namespace juggle {

class PhysicsSnapshot {
 public:
  // Copies `d` (REQUIRES: made by mj_makeData(m)). Reuses this object's memory.
  void Save(const mjModel* m, const mjData* d);
  // Writes the saved state into `d`. REQUIRES: Save was called, and `d` was made for a model
  // with the same sizes (EnvSnapshot checks the model's fingerprint first).
  void Restore(mjData* d) const;
  // True when `d`'s state arrays and header are bitwise those saved (tests, tools).
  bool Equals(const mjData* d) const;
  size_t bytes() const { return buffer_.size(); }

 private:
  std::vector<unsigned char> buffer_;
  // The header fields mj_step reads or envs compare.
  mjWarningStat warning_[mjNWARNING];
  mjSolverStat solver_[mjNSOLVER];
  int solver_iter_ = 0, solver_nnz_ = 0;
  mjtNum solver_fwdinv_[2] = {0, 0};
  int ne_ = 0, nf_ = 0, nefc_ = 0, ncon_ = 0;
  mjtNum time_ = 0;
  mjtNum energy_[2] = {0, 0};
};

// A 64-bit fingerprint of a compiled model (FNV-1a of its mj_saveModel bytes): equal models
// give equal fingerprints.
uint64_t ModelFingerprint(const mjModel* m);
// FNV-1a of `bytes`, continuing from `seed` (0: a fresh hash).
uint64_t Fingerprint(const std::string& bytes, uint64_t seed = 0);

// The state of one env. Each family derives its own (the env's own variables beside the
// physics); Env::Snapshot makes one, Env::Restore reads one.
class EnvSnapshot {
 public:
  virtual ~EnvSnapshot() = default;
  // "soccer_juggle", "toss": the family of the env it was taken from.
  virtual std::string family() const = 0;
  // The spec the env was made from (model and config; EnvSpec::fingerprint()).
  uint64_t spec_fingerprint = 0;
  // The physics, for families that keep it here (soccer). A family may keep it in its own
  // fields instead (toss: TossTaskSnapshot::world, TossLoopSnapshot's runtime): code that is
  // not the family's own reads a snapshot only through Env::Restore.
  PhysicsSnapshot physics;
};

// OK when `snapshot` can be restored into an env of family `family` whose spec has fingerprint
// `spec_fingerprint`; INVALID_ARGUMENT naming the mismatch otherwise.
absl::Status CheckSnapshotMatches(const EnvSnapshot& snapshot, const std::string& family,
                                  uint64_t spec_fingerprint);

}  // namespace juggle

#endif  // JUGGLE_ENVS_ENV_SNAPSHOT_H_
