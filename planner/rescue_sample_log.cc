#include "planner/rescue_sample_log.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace juggle::planner {
namespace {

// A JSON number: shortest round-trip form; non-finite values (a pruned or
// diverged rollout's cost) as null.
std::string Number(double v) {
  if (!std::isfinite(v)) return "null";
  return absl::StrFormat("%.17g", v);
}

template <typename T>
std::string Array(const T* values, int n) {
  std::string out = "[";
  for (int i = 0; i < n; ++i) absl::StrAppend(&out, i > 0 ? "," : "", Number(values[i]));
  return out + "]";
}

}  // namespace

absl::StatusOr<std::unique_ptr<RescueSampleLog>> RescueSampleLog::Open(const std::string& path,
                                                                       int obs_dim) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (file == nullptr) {
    return absl::InvalidArgumentError(absl::StrCat("cannot write the rescue samples to ", path));
  }
  return std::unique_ptr<RescueSampleLog>(new RescueSampleLog(file, obs_dim));
}

RescueSampleLog::~RescueSampleLog() {
  if (file_ != nullptr) std::fclose(file_);
}

void RescueSampleLog::WriteLine(const std::string& line) {
  if (std::fputs(line.c_str(), file_) < 0 || std::fputc('\n', file_) == EOF) failed_ = true;
}

int RescueSampleLog::Begin(uint64_t stream, const Env& env, double troubled_cost) {
  std::vector<float> obs(static_cast<size_t>(obs_dim_));
  env.WriteObservation(obs.data());
  std::lock_guard<std::mutex> lock(mu_);
  const int rescue = ++rescues_;
  WriteLine(absl::StrCat("{\"rescue\":", rescue, ",\"stream\":", stream, ",\"step\":", env.steps(),
                         ",\"troubled_cost\":", Number(troubled_cost),
                         ",\"observation\":", Array(obs.data(), obs_dim_), "}"));
  return rescue;
}

void RescueSampleLog::Rollout(int rescue, const double* theta, int dim,
                              const std::vector<double>& outcome, double cost) {
  std::string line =
      absl::StrCat("{\"rescue\":", rescue, ",\"theta\":", Array(theta, dim),
                   ",\"outcome\":", Array(outcome.data(), static_cast<int>(outcome.size())),
                   ",\"cost\":", Number(cost), "}");
  std::lock_guard<std::mutex> lock(mu_);
  ++rollouts_;
  WriteLine(line);
}

void RescueSampleLog::End(int rescue, double best_cost, int rollouts) {
  std::lock_guard<std::mutex> lock(mu_);
  WriteLine(absl::StrCat("{\"rescue\":", rescue, ",\"best_cost\":", Number(best_cost),
                         ",\"rollouts\":", rollouts, "}"));
}

int RescueSampleLog::rescues() const {
  std::lock_guard<std::mutex> lock(mu_);
  return rescues_;
}

int64_t RescueSampleLog::rollouts() const {
  std::lock_guard<std::mutex> lock(mu_);
  return rollouts_;
}

absl::Status RescueSampleLog::Close() {
  std::lock_guard<std::mutex> lock(mu_);
  if (file_ != nullptr) {
    if (std::fclose(file_) != 0) failed_ = true;
    file_ = nullptr;
  }
  if (failed_) return absl::DataLossError("a write of the rescue samples failed");
  return absl::OkStatus();
}

}  // namespace juggle::planner
