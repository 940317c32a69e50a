#include "common/network_layout.h"

#include "absl/strings/str_cat.h"

namespace juggle {
namespace {

std::vector<int> OrDefault(const google::protobuf::RepeatedField<int32_t>& v,
                           std::vector<int> fallback) {
  if (v.empty()) return fallback;
  return std::vector<int>(v.begin(), v.end());
}

}  // namespace

std::vector<int> ExpertHidden(const config::ModelConfig& m) { return OrDefault(m.hidden(), {128, 128}); }
std::vector<int> GateHidden(const config::ModelConfig& m) { return OrDefault(m.gate_hidden(), {128, 128}); }
std::vector<int> MlpHidden(const config::ModelConfig& m) { return OrDefault(m.mlp_hidden(), {1024, 1024}); }

std::vector<int> LayerWidths(const config::ModelConfig& m, int in_dim, int out_dim) {
  std::vector<int> widths = {in_dim};
  const std::vector<int> hidden = m.architecture() == config::MLP ? MlpHidden(m) : ExpertHidden(m);
  widths.insert(widths.end(), hidden.begin(), hidden.end());
  widths.push_back(out_dim);
  return widths;
}

std::vector<TensorSpec> NetworkLayout(const config::ModelConfig& m, const std::string& prefix,
                                      int in_dim, int out_dim) {
  std::vector<TensorSpec> layout;
  const std::vector<int> widths = LayerWidths(m, in_dim, out_dim);
  if (m.architecture() == config::MLP) {
    for (size_t l = 0; l + 1 < widths.size(); ++l) {
      layout.push_back({absl::StrCat(prefix, ".w", l), {widths[l], widths[l + 1]}});
      layout.push_back({absl::StrCat(prefix, ".b", l), {widths[l + 1]}});
    }
    return layout;
  }
  std::vector<int> gate = {in_dim};
  for (int h : GateHidden(m)) gate.push_back(h);
  gate.push_back(m.num_experts());
  for (size_t i = 0; i + 1 < gate.size(); ++i) {
    layout.push_back({absl::StrCat(prefix, ".gate_w", i), {gate[i], gate[i + 1]}});
    layout.push_back({absl::StrCat(prefix, ".gate_b", i), {gate[i + 1]}});
  }
  const int64_t k = m.num_experts();
  for (size_t l = 0; l + 1 < widths.size(); ++l) {
    layout.push_back({absl::StrCat(prefix, ".expert_w", l), {k, widths[l], widths[l + 1]}});
    layout.push_back({absl::StrCat(prefix, ".expert_b", l), {k, widths[l + 1]}});
  }
  return layout;
}

}  // namespace juggle
