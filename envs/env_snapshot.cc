#include "envs/env_snapshot.h"

#include <cstring>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "envs/mujoco_model.h"

namespace juggle {

void PhysicsSnapshot::Save(const mjModel*, const mjData* d) {
  buffer_.resize(d->nbuffer);
  std::memcpy(buffer_.data(), d->buffer, d->nbuffer);
  std::memcpy(warning_, d->warning, sizeof(warning_));
  std::memcpy(solver_, d->solver, sizeof(solver_));
  solver_iter_ = d->solver_iter;
  solver_nnz_ = d->solver_nnz;
  solver_fwdinv_[0] = d->solver_fwdinv[0];
  solver_fwdinv_[1] = d->solver_fwdinv[1];
  ne_ = d->ne;
  nf_ = d->nf;
  nefc_ = d->nefc;
  ncon_ = d->ncon;
  time_ = d->time;
  energy_[0] = d->energy[0];
  energy_[1] = d->energy[1];
}

void PhysicsSnapshot::Restore(mjData* d) const {
  std::memcpy(d->buffer, buffer_.data(), buffer_.size());
  std::memcpy(d->warning, warning_, sizeof(warning_));
  std::memcpy(d->solver, solver_, sizeof(solver_));
  d->solver_iter = solver_iter_;
  d->solver_nnz = solver_nnz_;
  d->solver_fwdinv[0] = solver_fwdinv_[0];
  d->solver_fwdinv[1] = solver_fwdinv_[1];
  d->ne = ne_;
  d->nf = nf_;
  d->nefc = nefc_;
  d->ncon = ncon_;
  d->time = time_;
  d->energy[0] = energy_[0];
  d->energy[1] = energy_[1];
}

bool PhysicsSnapshot::Equals(const mjData* d) const {
  return static_cast<size_t>(d->nbuffer) == buffer_.size() &&
         std::memcmp(d->buffer, buffer_.data(), buffer_.size()) == 0 &&
         std::memcmp(d->warning, warning_, sizeof(warning_)) == 0 && d->ne == ne_ &&
         d->nf == nf_ && d->nefc == nefc_ && d->ncon == ncon_ &&
         std::memcmp(&d->time, &time_, sizeof(time_)) == 0;
}

uint64_t Fingerprint(const std::string& bytes, uint64_t seed) {
  uint64_t h = seed == 0 ? 1469598103934665603ull : seed;
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

uint64_t ModelFingerprint(const mjModel* m) { return Fingerprint(SaveModel(m)); }

absl::Status CheckSnapshotMatches(const EnvSnapshot& snapshot, const std::string& family,
                                  uint64_t spec_fingerprint) {
  if (snapshot.family() != family) {
    return absl::InvalidArgumentError(absl::StrCat("a snapshot of a ", snapshot.family(),
                                                   " env cannot be restored into a ", family,
                                                   " env"));
  }
  if (snapshot.spec_fingerprint != spec_fingerprint) {
    return absl::InvalidArgumentError(absl::StrFormat(
        "the snapshot was taken from an env of another model or config (spec fingerprint "
        "%016x, this env's %016x)",
        snapshot.spec_fingerprint, spec_fingerprint));
  }
  return absl::OkStatus();
}

}  // namespace juggle
