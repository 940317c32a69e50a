#include "common/unroll_batch.h"

#include <cmath>

#include "absl/strings/str_cat.h"

namespace juggle {
namespace {

absl::Status CheckSize(const char* name, size_t got, int64_t want) {
  if (static_cast<int64_t>(got) != want) {
    return absl::InvalidArgumentError(
        absl::StrCat("unroll batch field '", name, "' has ", got, " entries, expected ", want));
  }
  return absl::OkStatus();
}

absl::Status CheckFinite(const char* name, const std::vector<float>& v) {
  for (size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) {
      return absl::InvalidArgumentError(
          absl::StrCat("unroll batch field '", name, "' has a non-finite value at index ", i));
    }
  }
  return absl::OkStatus();
}

}  // namespace

int UnrollBatch::num_truncated() const {
  int n = 0;
  for (uint8_t t : truncated) n += t != 0;
  return n;
}

absl::Status ValidateUnrollBatch(const UnrollBatch& b, int obs_dim, int act_dim,
                                 int64_t current_version, int64_t max_policy_lag) {
  if (b.num_unrolls <= 0 || b.unroll_length <= 0) {
    return absl::InvalidArgumentError(absl::StrCat("empty unroll batch (", b.num_unrolls,
                                                   " unrolls of ", b.unroll_length, " steps)"));
  }
  if (b.obs_dim != obs_dim || b.act_dim != act_dim) {
    return absl::InvalidArgumentError(
        absl::StrCat("unroll batch has obs_dim ", b.obs_dim, " and act_dim ", b.act_dim,
                     "; the policy expects ", obs_dim, " and ", act_dim));
  }
  const int64_t n = b.num_samples();
  absl::Status s;
  for (const absl::Status& check :
       {CheckSize("obs", b.obs.size(), n * obs_dim), CheckSize("actions", b.actions.size(), n * act_dim),
        CheckSize("log_probs", b.log_probs.size(), n), CheckSize("rewards", b.rewards.size(), n),
        CheckSize("done", b.done.size(), n), CheckSize("truncated", b.truncated.size(), n),
        CheckSize("bootstrap_obs", b.bootstrap_obs.size(), int64_t(b.num_unrolls) * obs_dim),
        CheckSize("policy_version", b.policy_version.size(), b.num_unrolls)}) {
    if (!check.ok()) return check;
  }
  for (int64_t i = 0; i < n; ++i) {
    if (b.done[i] > 1 || b.truncated[i] > 1) {
      return absl::InvalidArgumentError(absl::StrCat("flag at step ", i, " is not 0 or 1"));
    }
    if (b.done[i] && b.truncated[i]) {
      return absl::InvalidArgumentError(
          absl::StrCat("step ", i, " is both done and truncated"));
    }
  }
  if (absl::Status c = CheckSize("truncated_obs", b.truncated_obs.size(),
                                 int64_t(b.num_truncated()) * obs_dim);
      !c.ok()) {
    return c;
  }
  for (const auto& [name, v] : {std::pair<const char*, const std::vector<float>*>{"obs", &b.obs},
                                {"actions", &b.actions}, {"log_probs", &b.log_probs},
                                {"rewards", &b.rewards}, {"truncated_obs", &b.truncated_obs},
                                {"bootstrap_obs", &b.bootstrap_obs}}) {
    if (absl::Status c = CheckFinite(name, *v); !c.ok()) return c;
  }
  for (int u = 0; u < b.num_unrolls; ++u) {
    const int64_t v = b.policy_version[u];
    if (v > current_version) {
      return absl::FailedPreconditionError(absl::StrCat(
          "unroll ", u, " has unknown policy version ", v, " (current ", current_version, ")"));
    }
    if (v < current_version - max_policy_lag) {
      return absl::FailedPreconditionError(
          absl::StrCat("unroll ", u, " has policy version ", v, ", older than the allowed lag ",
                       max_policy_lag, " behind ", current_version));
    }
  }
  return absl::OkStatus();
}

}  // namespace juggle
