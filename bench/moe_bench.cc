// `juggle bench moe`: forward+backward time of the layer-wise and weight-blended forms of the
// same MoE at several batch sizes, PPO update throughput at the reference's sizes, and Eigen
// inference throughput at a worker-sized batch — all in one run. The last line is key=value
// pairs (layerwise_speedup_b512=, layerwise_speedup_b10000=, ...).
#include <torch/torch.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "bench/bench_clock.h"
#include "bench/benchmarks.h"
#include "common/eigen_policy.h"
#include "common/rng.h"
#include "learner/networks.h"
#include "learner/ppo_trainer.h"

namespace juggle {
namespace {

using Clock = std::chrono::steady_clock;

// Median-free best-of-`reps` time of one forward+backward pass.
double TimeForwardBackward(TorchNetwork* net, int batch, bool blended, int reps) {
  const torch::Tensor x = torch::randn({batch, 157});
  double best = 1e30;
  for (int r = 0; r < reps; ++r) {
    net->zero_grad();
    const auto t0 = Clock::now();
    const torch::Tensor y = blended ? net->ForwardWeightBlended(x) : net->forward(x);
    y.pow(2).sum().backward();
    best = std::min(best, SecondsSince(t0));
  }
  return best;
}

}  // namespace

absl::Status RunMoeBench(const MoeBenchOptions& o) {
  const int reps = o.reps;
  torch::set_num_threads(o.threads);
  torch::manual_seed(1);
  config::ModelConfig model;  // reference: 8 experts, [128, 128], gate [128, 128]
  TorchNetwork net(model, "actor", 157, 28, true, 0.1, 0.1);

  std::string kv;
  std::printf("forward+backward, layer-wise MoE (8 experts, 157-128-128-28) vs weight-blended:\n");
  for (int batch : {64, 512, 10000}) {
    const double layerwise = TimeForwardBackward(&net, batch, false, reps);
    const double blended = TimeForwardBackward(&net, batch, true, reps);
    std::printf("  batch %5d: layer-wise %8.2f ms, weight-blended %8.2f ms, speedup %.1fx\n",
                batch, layerwise * 1e3, blended * 1e3, blended / layerwise);
    std::fflush(stdout);
    absl::StrAppend(&kv, absl::StrFormat("layerwise_ms_b%d=%.3f blended_ms_b%d=%.3f "
                                         "layerwise_speedup_b%d=%.2f ",
                                         batch, layerwise * 1e3, batch, blended * 1e3, batch,
                                         blended / layerwise));
  }

  // PPO update throughput at the reference's network sizes (obs 157, act 28).
  const int n = static_cast<int>(o.ppo_samples);
  config::PpoConfig ppo;
  ppo.set_torch_threads(static_cast<int>(o.threads));
  PpoTrainer trainer(model, ppo, 157, 28, 1);
  UnrollBatch batch;
  batch.num_unrolls = n / 100;
  batch.unroll_length = 100;
  batch.obs_dim = 157;
  batch.act_dim = 28;
  Rng rng(3);
  auto fill = [&](std::vector<float>* v, size_t size, double scale) {
    v->resize(size);
    for (float& x : *v) x = static_cast<float>(scale * rng.Normal());
  };
  fill(&batch.obs, size_t(batch.num_samples()) * 157, 1.0);
  fill(&batch.actions, size_t(batch.num_samples()) * 28, 0.1);
  fill(&batch.rewards, batch.num_samples(), 0.01);
  batch.log_probs.assign(batch.num_samples(), 20.0f);
  batch.done.assign(batch.num_samples(), 0);
  batch.truncated.assign(batch.num_samples(), 0);
  fill(&batch.bootstrap_obs, size_t(batch.num_unrolls) * 157, 1.0);
  batch.policy_version.assign(batch.num_unrolls, 0);
  const auto t0 = Clock::now();
  absl::StatusOr<UpdateStats> stats = trainer.Update(batch);
  const double update_s = SecondsSince(t0);
  if (!stats.ok()) return stats.status();
  const int passes = ppo.epochs() * 2;  // critic epochs + actor epochs
  const double per_epoch = batch.num_samples() * passes / update_s;
  std::printf("PPO update: %ld samples, %d epochs (critic + actor) in %.2f s = %.0f samples/s "
              "per epoch, %.0f samples/s per iteration\n",
              static_cast<long>(batch.num_samples()), passes, update_s, per_epoch,
              batch.num_samples() / update_s);

  // Eigen inference at a worker-sized batch.
  const int wb = static_cast<int>(o.worker_batch);
  const EigenPolicy policy = *EigenPolicy::Create(model, trainer.ExportPolicy(), 157, 28);
  std::vector<float> obs(size_t(wb) * 157);
  for (float& x : obs) x = static_cast<float>(rng.Normal());
  int calls = 0;
  const auto t1 = Clock::now();
  while (SecondsSince(t1) < 1.0) {
    const RowMatrix m = policy.MeanActions(obs.data(), wb);
    calls += m.rows() > 0;
  }
  const double eigen_rate = double(calls) * wb / SecondsSince(t1);
  std::printf("Eigen inference (actor, 1 thread): batch %d, %.0f samples/s\n", wb, eigen_rate);
  absl::StrAppend(&kv, absl::StrFormat("ppo_samples_per_s_per_epoch=%.0f "
                                       "ppo_iteration_samples_per_s=%.0f eigen_samples_per_s_b%d=%.0f",
                                       per_epoch, batch.num_samples() / update_s, wb, eigen_rate));
  std::printf("%s\n", kv.c_str());
  return absl::OkStatus();
}

}  // namespace juggle
