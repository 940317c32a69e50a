#include "learner/demo_fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <torch/torch.h>

#include "absl/strings/str_cat.h"
#include "learner/networks.h"

namespace juggle {
namespace {

// Rows of `demos` in the order they were added, as [n, dim] tensors.
std::pair<torch::Tensor, torch::Tensor> InAddedOrder(const DemoBuffer& demos) {
  const int64_t n = demos.size();
  const torch::Tensor obs = torch::from_blob(const_cast<float*>(demos.obs()),
                                             {n, demos.obs_dim()}, torch::kFloat32);
  const torch::Tensor labels = torch::from_blob(const_cast<float*>(demos.labels()),
                                                {n, demos.act_dim()}, torch::kFloat32);
  const torch::Tensor order =
      torch::remainder(torch::arange(n, torch::kLong) + demos.oldest(), n);
  return {obs.index_select(0, order), labels.index_select(0, order)};
}

}  // namespace

absl::StatusOr<std::vector<DemoFitEpoch>> FitDemos(
    const DemoBuffer& demos, const config::ModelConfig& model, const DemoFitOptions& options,
    const std::function<void(const DemoFitEpoch&)>& progress, FlatParameters* fitted) {
  const int64_t n = options.rows > 0 ? std::min(options.rows, demos.size()) : demos.size();
  const int64_t held = static_cast<int64_t>(std::llround(options.held_out * n));
  int64_t train = n - held;
  if (held < 1 || train < 2) {
    return absl::InvalidArgumentError(absl::StrCat(
        "the demonstration buffer holds ", n, " rows: too few to hold out ", options.held_out,
        " of them and train on the rest"));
  }
  for (const int a : options.actions) {
    if (a < 0 || a >= demos.act_dim()) {
      return absl::InvalidArgumentError(
          absl::StrCat("action ", a, " is not one of the buffer's ", demos.act_dim()));
    }
  }
  torch::set_num_threads(std::max(1, options.threads));
  torch::manual_seed(options.seed);
  const auto started = std::chrono::steady_clock::now();
  auto [obs, labels] = InAddedOrder(demos);
  obs = obs.slice(0, 0, n);
  labels = labels.slice(0, 0, n);
  int obs_dim = demos.obs_dim();
  if (options.obs_prefix > 0) {
    if (options.obs_prefix > obs_dim) {
      return absl::InvalidArgumentError(absl::StrCat(
          "an observation prefix of ", options.obs_prefix, " floats; the buffer holds ", obs_dim));
    }
    obs_dim = options.obs_prefix;
    obs = obs.slice(1, 0, obs_dim);
  }
  if (options.previous_label_unroll > 0) {
    if (demos.oldest() != 0) {
      return absl::InvalidArgumentError(
          "the previous label needs a buffer that has not wrapped (its unrolls start at row 0)");
    }
    torch::Tensor previous = torch::zeros_like(labels);
    previous.slice(0, 1).copy_(labels.slice(0, 0, n - 1));
    const torch::Tensor first =
        torch::arange(0, n, options.previous_label_unroll, torch::kLong);
    previous.index_fill_(0, first, 0.0);
    obs = torch::cat({obs, previous}, 1);
    obs_dim += demos.act_dim();
  }
  if (options.random_split) {
    const torch::Tensor perm = torch::randperm(n, torch::kLong);
    obs = obs.index_select(0, perm);
    labels = labels.index_select(0, perm);
  }
  const torch::Tensor weights =
      1.0 / torch::clamp(labels.slice(0, 0, train).var(0, /*unbiased=*/false),
                         options.min_label_std * options.min_label_std);
  const torch::Tensor held_obs = obs.slice(0, train), held_labels = labels.slice(0, train);
  const int64_t first = options.train_rows > 0 ? std::max<int64_t>(0, train - options.train_rows) : 0;
  const torch::Tensor train_obs = obs.slice(0, first, train);
  const torch::Tensor train_labels = labels.slice(0, first, train);
  train -= first;

  ActorCritic net(model, obs_dim, demos.act_dim());
  // The observation normalizer from the training rows.
  net.normalize = true;
  net.norm_mean.copy_(train_obs.mean(0));
  net.norm_inv_std.copy_(1.0 / torch::clamp(train_obs.std(0, /*unbiased=*/false), 1e-2));
  auto error = [&](const torch::Tensor& mean, const torch::Tensor& target) {
    return ((mean - target).pow(2) * weights).mean();
  };
  torch::optim::Adam adam(net.actor->parameters(), torch::optim::AdamOptions(options.lr));
  const int64_t batch = std::max<int64_t>(1, std::min<int64_t>(options.minibatch, train));
  std::vector<DemoFitEpoch> reports;
  for (int epoch = 1; epoch <= options.epochs; ++epoch) {
    const torch::Tensor perm = torch::randperm(train, torch::kLong);
    for (int64_t start = 0; start < train; start += batch) {
      const torch::Tensor idx = perm.slice(0, start, std::min(train, start + batch));
      const torch::Tensor loss =
          error(net.Mean(train_obs.index_select(0, idx)), train_labels.index_select(0, idx));
      adam.zero_grad();
      loss.backward();
      adam.step();
    }
    torch::NoGradGuard guard;
    DemoFitEpoch r;
    r.epoch = epoch;
    r.train_error = error(net.Mean(train_obs), train_labels).item<double>();
    const torch::Tensor held_mean = net.Mean(held_obs);
    r.held_out_error = error(held_mean, held_labels).item<double>();
    for (const int a : options.actions) {
      const torch::Tensor y = held_labels.select(1, a), p = held_mean.select(1, a);
      const double sse = (p - y).pow(2).sum().item<double>();
      const double sst = (y - y.mean()).pow(2).sum().item<double>();
      r.action_rms.push_back(std::sqrt(sse / held));
      r.action_r2.push_back(sst > 0 ? 1 - sse / sst : 0);
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    if (progress) progress(r);
    reports.push_back(std::move(r));
  }
  if (fitted != nullptr) *fitted = ExportActorParameters(net, 1, /*normalizer=*/true);
  return reports;
}

}  // namespace juggle
