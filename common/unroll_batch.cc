#include "common/unroll_batch.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "common/status_macros.h"

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

absl::Status ValidateLabels(const UnrollBatch& b) {
  if (b.labelled.empty()) {
    if (!b.labels.empty() || !b.expert_driven.empty()) {
      return absl::InvalidArgumentError("unroll batch has labels or expert_driven but no labelled mask");
    }
    return absl::OkStatus();
  }
  RETURN_IF_ERROR(CheckSize("labelled", b.labelled.size(), b.num_unrolls));
  int labelled = 0;
  for (uint8_t l : b.labelled) {
    if (l > 1) return absl::InvalidArgumentError("unroll batch field 'labelled' has a flag other than 0 or 1");
    labelled += l;
  }
  RETURN_IF_ERROR(CheckSize("labels", b.labels.size(),
                            int64_t(labelled) * b.unroll_length * b.act_dim));
  RETURN_IF_ERROR(CheckFinite("labels", b.labels));
  if (!b.expert_driven.empty()) {
    RETURN_IF_ERROR(CheckSize("expert_driven", b.expert_driven.size(), b.num_unrolls));
    for (int u = 0; u < b.num_unrolls; ++u) {
      if (b.expert_driven[u] > 1) {
        return absl::InvalidArgumentError("unroll batch field 'expert_driven' has a flag other than 0 or 1");
      }
      if (b.expert_driven[u] && !b.labelled[u]) {
        return absl::InvalidArgumentError(
            absl::StrCat("unroll ", u, " is expert-driven but carries no labels"));
      }
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

int UnrollBatch::num_labelled() const {
  int n = 0;
  for (uint8_t l : labelled) n += l != 0;
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
  RETURN_IF_ERROR(ValidateLabels(b));
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

UnrollBatch WithoutExpertUnrolls(const UnrollBatch& b) {
  UnrollBatch out;
  out.unroll_length = b.unroll_length;
  out.obs_dim = b.obs_dim;
  out.act_dim = b.act_dim;
  const size_t T = b.unroll_length, D = b.obs_dim, A = b.act_dim;
  const bool labels = b.has_labels();
  size_t trunc = 0, label_row = 0;
  for (int u = 0; u < b.num_unrolls; ++u) {
    const size_t s0 = u * T, s1 = (u + 1) * T;
    size_t unroll_truncated = 0;
    for (size_t i = s0; i < s1; ++i) unroll_truncated += b.truncated[i];
    const bool is_labelled = labels && b.labelled[u];
    if (!b.is_expert_driven(u)) {
      auto append = [](auto* to, const auto& from, size_t begin, size_t end) {
        to->insert(to->end(), from.begin() + begin, from.begin() + end);
      };
      ++out.num_unrolls;
      append(&out.obs, b.obs, s0 * D, s1 * D);
      append(&out.actions, b.actions, s0 * A, s1 * A);
      append(&out.log_probs, b.log_probs, s0, s1);
      append(&out.rewards, b.rewards, s0, s1);
      append(&out.done, b.done, s0, s1);
      append(&out.truncated, b.truncated, s0, s1);
      append(&out.truncated_obs, b.truncated_obs, trunc * D, (trunc + unroll_truncated) * D);
      append(&out.bootstrap_obs, b.bootstrap_obs, u * D, (u + 1) * D);
      out.policy_version.push_back(b.policy_version[u]);
      if (labels) {
        out.labelled.push_back(b.labelled[u]);
        if (is_labelled) append(&out.labels, b.labels, label_row * T * A, (label_row + 1) * T * A);
        out.expert_driven.push_back(0);
      }
    }
    trunc += unroll_truncated;
    label_row += is_labelled;
  }
  return out;
}

}  // namespace juggle
