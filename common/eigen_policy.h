// Policy inference on workers with Eigen (no libtorch): the actor's forward pass from flat
// parameters, batched over a worker's envs, and Gaussian sampling with the behaviour
// log-probability computed exactly as the learner computes it (GaussianLogProb).
// Immutable after Create; Forward/Act are const and allocate their temporaries per call, so
// concurrent calls from several threads are safe.
#ifndef JUGGLE_COMMON_EIGEN_POLICY_H_
#define JUGGLE_COMMON_EIGEN_POLICY_H_

#include <string>
#include <vector>

#include <Eigen/Core>

#include "absl/status/statusor.h"
#include "common/flat_parameters.h"
#include "common/rng.h"
#include "proto/run_config.pb.h"

namespace juggle {

using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// log N(a; μ, σ) summed over `dim` entries, σ = exp(log_std), including the −½·log 2π terms.
double GaussianLogProb(const float* action, const float* mean, const float* log_std, int dim);

// One network (actor or critic) of any architecture.
class EigenNetwork {
 public:
  enum class Output { kTanh, kIdentity };
  // Reads the tensors named by NetworkLayout(model, prefix, in_dim, out_dim). NOT_FOUND /
  // INVALID_ARGUMENT when a tensor is missing or has the wrong shape.
  static absl::StatusOr<EigenNetwork> Create(const config::ModelConfig& model,
                                             const FlatParameters& params,
                                             const std::string& prefix, int in_dim, int out_dim,
                                             Output output);
  // x: [batch, in_dim] → returns [batch, out_dim]. If `gate` is given and the network is a
  // MoE, it receives the gate weights [batch, K].
  RowMatrix Forward(const RowMatrix& x, RowMatrix* gate = nullptr) const;

  int in_dim() const { return in_dim_; }
  int out_dim() const { return out_dim_; }

 private:
  struct Dense {
    RowMatrix w;             // [in, out]
    Eigen::RowVectorXf b;    // [out]
  };
  RowMatrix Gate(const RowMatrix& x) const;

  config::Architecture architecture_ = config::LAYERWISE_MOE;
  int in_dim_ = 0, out_dim_ = 0, num_experts_ = 0;
  Output output_ = Output::kIdentity;
  std::vector<Dense> gate_;                     // gating MLP (MoE only)
  std::vector<std::vector<Dense>> experts_;     // [layer][expert] (MLP: one "expert")
};

// Specialization and utilization of a mixture of experts over N gate vectors (paper Eq. 4):
// spec = (1/N) Σ_i Σ_k g_ik² (1 = one expert at a time; higher is more specialized),
// util = Σ_k ((1/N) Σ_i g_ik)² (1/K = all experts used equally; lower is better).
struct GateStatistics {
  double specialization = 0;
  double utilization = 0;
};
// gates: [N, K], rows summing to 1. N = 0 gives zeros.
GateStatistics ComputeGateStatistics(const RowMatrix& gates);

// The actor plus the observation normalizer and log-std: what a worker needs to act.
class EigenPolicy {
 public:
  // REQUIRES `params` to hold NetworkLayout(model, "actor", obs_dim, act_dim) and
  // "actor.log_std" [act_dim]; "obs_norm.mean"/"obs_norm.inv_std" [obs_dim] are optional.
  static absl::StatusOr<EigenPolicy> Create(const config::ModelConfig& model,
                                            const FlatParameters& params, int obs_dim,
                                            int act_dim);
  // obs: [batch, obs_dim] → mean actions [batch, act_dim] (tanh-bounded).
  RowMatrix MeanActions(const float* obs, int batch) const;
  int obs_dim() const { return obs_dim_; }
  int act_dim() const { return act_dim_; }
  // Samples actions clamp(μ + σ·ε, −1, 1) into `actions` [batch, act_dim] and their
  // log-probabilities (of the clamped action, as the learner recomputes it) into `log_probs`.
  void Act(const float* obs, int batch, Rng* rng, float* actions, float* log_probs) const;
  // One sample from mean `mean` [act_dim]: writes the action and returns its log-probability.
  float Sample(const float* mean, Rng* rng, float* action) const;

  int64_t version() const { return version_; }
  const std::vector<float>& log_std() const { return log_std_; }

  // The actor's gate weights [batch, K] (empty for an MLP).
  RowMatrix Gates(const float* obs, int batch) const;

  // Normalized observations (identity if the parameters carry no normalizer).
  RowMatrix Normalize(const float* obs, int batch) const;

 private:
  EigenNetwork actor_;
  std::vector<float> log_std_;
  Eigen::RowVectorXf norm_mean_, norm_inv_std_;
  bool normalize_ = false;
  int obs_dim_ = 0, act_dim_ = 0;
  int64_t version_ = 0;
};

// The policy of an ExportedPolicy (`juggle export-policy`). DATA_LOSS / INVALID_ARGUMENT when
// its parameters do not read or do not fit its model and sizes.
absl::StatusOr<EigenPolicy> PolicyFromExport(const config::ExportedPolicy& exported);

// Observation normalization clip (in standard deviations), shared with the learner.
constexpr float kObsNormClip = 5.0f;

}  // namespace juggle

#endif  // JUGGLE_COMMON_EIGEN_POLICY_H_
