#include "learner/networks.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "common/eigen_policy.h"

namespace juggle {
namespace {

torch::Tensor OrthogonalWeight(int64_t in, int64_t out, double gain) {
  // Stored [in, out]; torch's orthogonal_ on the [out, in] Linear weight, transposed.
  torch::Tensor w = torch::empty({out, in});
  torch::nn::init::orthogonal_(w, gain);
  return w.t().contiguous();
}

torch::Tensor UnitRowBias(int64_t out, double gain) {
  torch::Tensor b = torch::randn({out});
  return (b / b.norm() * gain).contiguous();
}

}  // namespace

TorchNetwork::TorchNetwork(const config::ModelConfig& model, const std::string& prefix,
                           int in_dim, int out_dim, bool tanh_output, double gain,
                           double out_gain)
    : architecture_(model.architecture()),
      tanh_output_(tanh_output),
      layout_(NetworkLayout(model, prefix, in_dim, out_dim)) {
  torch::NoGradGuard no_grad;
  const int64_t k = model.num_experts();
  const size_t num_layers = LayerWidths(model, in_dim, out_dim).size() - 1;
  size_t layer = 0;
  for (size_t i = 0; i < layout_.size(); i += 2) {
    const TensorSpec& ws = layout_[i];
    const std::string local = ws.name.substr(prefix.size() + 1);  // e.g. "gate_w0"
    const std::string bias_local = layout_[i + 1].name.substr(prefix.size() + 1);
    if (local.rfind("gate_", 0) == 0) {
      const int64_t fan_in = ws.shape[0], fan_out = ws.shape[1];
      const double bound = 1.0 / std::sqrt(double(fan_in));
      gate_w_.push_back(register_parameter(local, torch::empty({fan_in, fan_out}).uniform_(-bound, bound)));
      gate_b_.push_back(register_parameter(bias_local, torch::empty({fan_out}).uniform_(-bound, bound)));
      continue;
    }
    const double g = (layer + 1 == num_layers) ? out_gain : gain;
    ++layer;
    if (ws.shape.size() == 3) {
      std::vector<torch::Tensor> ws_k, bs_k;
      for (int64_t e = 0; e < k; ++e) {
        ws_k.push_back(OrthogonalWeight(ws.shape[1], ws.shape[2], g));
        bs_k.push_back(UnitRowBias(ws.shape[2], g));
      }
      w_.push_back(register_parameter(local, torch::stack(ws_k)));
      b_.push_back(register_parameter(bias_local, torch::stack(bs_k)));
    } else {
      w_.push_back(register_parameter(local, OrthogonalWeight(ws.shape[0], ws.shape[1], g)));
      b_.push_back(register_parameter(bias_local, UnitRowBias(ws.shape[1], g)));
    }
  }
}

torch::Tensor TorchNetwork::Gate(const torch::Tensor& x) {
  torch::Tensor h = x;
  for (size_t i = 0; i < gate_w_.size(); ++i) {
    h = torch::addmm(gate_b_[i], h, gate_w_[i]);
    if (i + 1 < gate_w_.size()) h = torch::relu(h);
  }
  return torch::softmax(h, -1);
}

torch::Tensor TorchNetwork::forward(const torch::Tensor& x) {
  const size_t layers = w_.size();
  auto activate = [&](torch::Tensor y, size_t l) {
    if (l + 1 < layers) return torch::relu(y);
    return tanh_output_ ? torch::tanh(y) : y;
  };
  if (architecture_ == config::MLP) {
    torch::Tensor h = x;
    for (size_t l = 0; l < layers; ++l) h = activate(torch::addmm(b_[l], h, w_[l]), l);
    return h;
  }
  const torch::Tensor gate = Gate(x);  // [B, K]
  if (architecture_ == config::LAYERWISE_MOE) {
    // One GEMM per layer over all experts side by side: [B, in] · [in, K·out] → [B, K, out],
    // then blend by the gate: h_{l+1} = act(Σ_k g_k · (h·W_k + b_k)).
    const torch::Tensor g = gate.unsqueeze(-1);  // [B, K, 1]
    torch::Tensor h = x;
    for (size_t l = 0; l < layers; ++l) {
      const int64_t k = w_[l].size(0), in = w_[l].size(1), out = w_[l].size(2);
      const torch::Tensor side_by_side = w_[l].permute({1, 0, 2}).reshape({in, k * out});
      const torch::Tensor y = h.mm(side_by_side).view({-1, k, out}) + b_[l].unsqueeze(0);
      h = activate((y * g).sum(1), l);
    }
    return h;
  }
  const torch::Tensor g = gate.t().unsqueeze(-1);  // [K, B, 1]
  // Output-blended: K whole expert MLPs, blended at the output.
  torch::Tensor h = x.unsqueeze(0).expand({w_[0].size(0), -1, -1});
  for (size_t l = 0; l < layers; ++l) {
    h = torch::baddbmm(b_[l].unsqueeze(1), h, w_[l]);
    if (l + 1 < layers) h = torch::relu(h);
  }
  torch::Tensor out = (h * g).sum(0);
  return tanh_output_ ? torch::tanh(out) : out;
}

torch::Tensor TorchNetwork::ForwardWeightBlended(const torch::Tensor& x) {
  TORCH_CHECK(architecture_ == config::LAYERWISE_MOE, "weight blending needs LAYERWISE_MOE");
  const torch::Tensor g = Gate(x);  // [B, K]
  torch::Tensor h = x;
  for (size_t l = 0; l < w_.size(); ++l) {
    // Per-sample weights [B, in, out] and biases [B, out].
    const torch::Tensor w = torch::einsum("bk,kio->bio", {g, w_[l]});
    const torch::Tensor b = torch::mm(g, b_[l]);
    torch::Tensor y = torch::bmm(h.unsqueeze(1), w).squeeze(1) + b;
    if (l + 1 < w_.size()) {
      y = torch::relu(y);
    } else if (tanh_output_) {
      y = torch::tanh(y);
    }
    h = y;
  }
  return h;
}

std::vector<std::pair<TensorSpec, torch::Tensor>> TorchNetwork::LayoutTensors() const {
  std::vector<std::pair<TensorSpec, torch::Tensor>> out;
  size_t gate = 0, main = 0;
  for (size_t i = 0; i < layout_.size(); i += 2) {
    const bool is_gate = layout_[i].name.find(".gate_w") != std::string::npos;
    out.emplace_back(layout_[i], is_gate ? gate_w_[gate] : w_[main]);
    out.emplace_back(layout_[i + 1], is_gate ? gate_b_[gate] : b_[main]);
    (is_gate ? gate : main)++;
  }
  return out;
}

ActorCritic::ActorCritic(const config::ModelConfig& model, int obs_dim_in, int act_dim_in)
    : obs_dim(obs_dim_in), act_dim(act_dim_in) {
  actor = register_module("actor", std::make_shared<TorchNetwork>(
                                       model, "actor", obs_dim, act_dim, /*tanh_output=*/true,
                                       model.init_gain(), model.init_gain()));
  critic = register_module("critic", std::make_shared<TorchNetwork>(
                                         model, "critic", obs_dim, 1, /*tanh_output=*/false,
                                         model.init_gain(), /*out_gain=*/1.0));
  torch::Tensor ls = torch::full({act_dim}, model.log_std());
  log_std = model.learn_log_std() ? register_parameter("log_std", ls)
                                  : register_buffer("log_std", ls);
  norm_mean = register_buffer("norm_mean", torch::zeros({obs_dim}));
  norm_inv_std = register_buffer("norm_inv_std", torch::ones({obs_dim}));
}

torch::Tensor ActorCritic::Normalize(const torch::Tensor& obs) {
  if (!normalize) return obs;
  return torch::clamp((obs - norm_mean) * norm_inv_std, -kObsNormClip, kObsNormClip);
}

torch::Tensor ActorCritic::LogProb(const torch::Tensor& actions, const torch::Tensor& mean) {
  constexpr double kHalfLog2Pi = 0.91893853320467274178;
  const torch::Tensor z = (actions - mean) * torch::exp(-log_std);
  return (-0.5 * z * z - log_std - kHalfLog2Pi).sum(-1);
}

void AppendTensor(const TensorSpec& spec, const torch::Tensor& t, std::vector<TensorSpec>* layout,
                  std::vector<float>* values) {
  const torch::Tensor c = t.detach().contiguous();
  layout->push_back(spec);
  values->insert(values->end(), c.data_ptr<float>(), c.data_ptr<float>() + c.numel());
}

FlatParameters ExportActorParameters(const ActorCritic& net, int64_t version, bool normalizer) {
  std::vector<TensorSpec> layout;
  std::vector<float> values;
  for (const auto& [spec, t] : net.actor->LayoutTensors()) AppendTensor(spec, t, &layout, &values);
  AppendTensor({"actor.log_std", {net.act_dim}}, net.log_std, &layout, &values);
  if (normalizer) {
    AppendTensor({"obs_norm.mean", {net.obs_dim}}, net.norm_mean, &layout, &values);
    AppendTensor({"obs_norm.inv_std", {net.obs_dim}}, net.norm_inv_std, &layout, &values);
  }
  return *FlatParameters::Create(version, std::move(layout), std::move(values));
}

}  // namespace juggle
