#include "common/eigen_policy.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "common/status_macros.h"

namespace juggle {

double GaussianLogProb(const float* action, const float* mean, const float* log_std, int dim) {
  constexpr double kHalfLog2Pi = 0.91893853320467274178;
  double lp = 0;
  for (int i = 0; i < dim; ++i) {
    const double z = (double(action[i]) - mean[i]) / std::exp(double(log_std[i]));
    lp += -0.5 * z * z - log_std[i] - kHalfLog2Pi;
  }
  return lp;
}

absl::StatusOr<EigenNetwork> EigenNetwork::Create(const config::ModelConfig& model,
                                                  const FlatParameters& params,
                                                  const std::string& prefix, int in_dim,
                                                  int out_dim, Output output) {
  EigenNetwork net;
  net.architecture_ = model.architecture();
  net.in_dim_ = in_dim;
  net.out_dim_ = out_dim;
  net.output_ = output;
  net.num_experts_ = model.architecture() == config::MLP ? 1 : model.num_experts();
  const std::vector<TensorSpec> layout = NetworkLayout(model, prefix, in_dim, out_dim);
  for (size_t i = 0; i < layout.size(); i += 2) {
    const TensorSpec& w = layout[i];
    const TensorSpec& b = layout[i + 1];
    ASSIGN_OR_RETURN(const float* wp, params.Find(w.name, w.shape));
    ASSIGN_OR_RETURN(const float* bp, params.Find(b.name, b.shape));
    const bool expert = w.shape.size() == 3;
    const int k = expert ? w.shape[0] : 1;
    const int rows = w.shape[w.shape.size() - 2], cols = w.shape.back();
    std::vector<Dense> layer(k);
    for (int e = 0; e < k; ++e) {
      layer[e].w = Eigen::Map<const RowMatrix>(wp + size_t(e) * rows * cols, rows, cols);
      layer[e].b = Eigen::Map<const Eigen::RowVectorXf>(bp + size_t(e) * cols, cols);
    }
    if (w.name.find(".gate_") != std::string::npos) {
      net.gate_.push_back(std::move(layer[0]));
    } else {
      net.experts_.push_back(std::move(layer));
    }
  }
  return net;
}

RowMatrix EigenNetwork::Gate(const RowMatrix& x) const {
  RowMatrix h = x;
  for (size_t i = 0; i < gate_.size(); ++i) {
    RowMatrix y = h * gate_[i].w;
    y.rowwise() += gate_[i].b;
    if (i + 1 < gate_.size()) y = y.cwiseMax(0.0f);
    h = std::move(y);
  }
  // Softmax over experts, row by row.
  for (int r = 0; r < h.rows(); ++r) {
    const float m = h.row(r).maxCoeff();
    h.row(r) = (h.row(r).array() - m).exp();
    h.row(r) /= h.row(r).sum();
  }
  return h;
}

RowMatrix EigenNetwork::Forward(const RowMatrix& x, RowMatrix* gate_out) const {
  const size_t layers = experts_.size();
  auto activate = [&](RowMatrix* y, size_t l) {
    if (l + 1 < layers) {
      *y = y->cwiseMax(0.0f);
    } else if (output_ == Output::kTanh) {
      *y = y->array().tanh().matrix();
    }
  };
  if (architecture_ == config::MLP) {
    RowMatrix h = x;
    for (size_t l = 0; l < layers; ++l) {
      RowMatrix y = h * experts_[l][0].w;
      y.rowwise() += experts_[l][0].b;
      activate(&y, l);
      h = std::move(y);
    }
    return h;
  }
  const RowMatrix g = Gate(x);
  if (gate_out != nullptr) *gate_out = g;
  if (architecture_ == config::LAYERWISE_MOE) {
    // h_{l+1} = act(Σ_k g_k · (h_l·W_lk + b_lk)): per-expert products blended by the gate.
    RowMatrix h = x;
    for (size_t l = 0; l < layers; ++l) {
      RowMatrix y = RowMatrix::Zero(x.rows(), experts_[l][0].w.cols());
      for (int k = 0; k < num_experts_; ++k) {
        RowMatrix yk = h * experts_[l][k].w;
        yk.rowwise() += experts_[l][k].b;
        y += g.col(k).asDiagonal() * yk;
      }
      activate(&y, l);
      h = std::move(y);
    }
    return h;
  }
  // Output-blended: each expert is a whole MLP; only the last layer's outputs are blended.
  RowMatrix out = RowMatrix::Zero(x.rows(), out_dim_);
  for (int k = 0; k < num_experts_; ++k) {
    RowMatrix h = x;
    for (size_t l = 0; l < layers; ++l) {
      RowMatrix y = h * experts_[l][k].w;
      y.rowwise() += experts_[l][k].b;
      if (l + 1 < layers) y = y.cwiseMax(0.0f);
      h = std::move(y);
    }
    out += g.col(k).asDiagonal() * h;
  }
  if (output_ == Output::kTanh) out = out.array().tanh().matrix();
  return out;
}

absl::StatusOr<EigenPolicy> EigenPolicy::Create(const config::ModelConfig& model,
                                                const FlatParameters& params, int obs_dim,
                                                int act_dim) {
  EigenPolicy p;
  ASSIGN_OR_RETURN(p.actor_, EigenNetwork::Create(model, params, "actor", obs_dim, act_dim,
                                                  EigenNetwork::Output::kTanh));
  ASSIGN_OR_RETURN(const float* log_std, params.Find("actor.log_std", {act_dim}));
  p.log_std_.assign(log_std, log_std + act_dim);
  absl::StatusOr<const float*> mean = params.Find("obs_norm.mean", {obs_dim});
  absl::StatusOr<const float*> inv_std = params.Find("obs_norm.inv_std", {obs_dim});
  if (mean.ok() && inv_std.ok()) {
    p.normalize_ = true;
    p.norm_mean_ = Eigen::Map<const Eigen::RowVectorXf>(*mean, obs_dim);
    p.norm_inv_std_ = Eigen::Map<const Eigen::RowVectorXf>(*inv_std, obs_dim);
  } else if (mean.ok() != inv_std.ok()) {
    return absl::InvalidArgumentError("obs_norm.mean and obs_norm.inv_std must come together");
  }
  p.obs_dim_ = obs_dim;
  p.act_dim_ = act_dim;
  p.version_ = params.version();
  return p;
}

RowMatrix EigenPolicy::Normalize(const float* obs, int batch) const {
  RowMatrix x = Eigen::Map<const RowMatrix>(obs, batch, obs_dim_);
  if (normalize_) {
    x.rowwise() -= norm_mean_;
    x = (x.array().rowwise() * norm_inv_std_.array()).matrix();
    x = x.cwiseMax(-kObsNormClip).cwiseMin(kObsNormClip);
  }
  return x;
}

GateStatistics ComputeGateStatistics(const RowMatrix& gates) {
  GateStatistics s;
  const double n = static_cast<double>(gates.rows());
  if (n == 0) return s;
  s.specialization = gates.cast<double>().array().square().sum() / n;
  const Eigen::RowVectorXd mean = gates.cast<double>().colwise().sum() / n;
  s.utilization = mean.squaredNorm();
  return s;
}

RowMatrix EigenPolicy::Gates(const float* obs, int batch) const {
  RowMatrix gate;
  actor_.Forward(Normalize(obs, batch), &gate);
  return gate;
}

RowMatrix EigenPolicy::MeanActions(const float* obs, int batch) const {
  return actor_.Forward(Normalize(obs, batch));
}

void EigenPolicy::Act(const float* obs, int batch, Rng* rng, float* actions,
                      float* log_probs) const {
  const RowMatrix mean = MeanActions(obs, batch);
  for (int b = 0; b < batch; ++b) {
    log_probs[b] = Sample(mean.row(b).data(), rng, actions + size_t(b) * act_dim_);
  }
}

float EigenPolicy::Sample(const float* mean, Rng* rng, float* action) const {
  for (int i = 0; i < act_dim_; ++i) {
    const double sample = mean[i] + std::exp(double(log_std_[i])) * rng->Normal();
    action[i] = static_cast<float>(std::clamp(sample, -1.0, 1.0));
  }
  return static_cast<float>(GaussianLogProb(action, mean, log_std_.data(), act_dim_));
}

absl::StatusOr<EigenPolicy> PolicyFromExport(const config::ExportedPolicy& exported) {
  absl::StatusOr<FlatParameters> params = FlatParameters::Deserialize(exported.parameters());
  if (!params.ok()) return params.status();
  if (exported.obs_dim() < 1 || exported.act_dim() < 1) {
    return absl::InvalidArgumentError("exported policy without obs_dim / act_dim");
  }
  return EigenPolicy::Create(exported.model(), *params, exported.obs_dim(), exported.act_dim());
}

}  // namespace juggle
