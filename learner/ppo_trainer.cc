#include "learner/ppo_trainer.h"

#include <algorithm>
#include <cstring>
#include <functional>
#include <map>
#include <sstream>
#include <vector>

#include <ATen/CPUGeneratorImpl.h>
#include <torch/torch.h>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "common/status_macros.h"
#include "learner/advantages.h"
#include "learner/demo_buffer.h"
#include "learner/networks.h"
#include "learner/obs_normalizer.h"

namespace juggle {

struct PpoTrainer::Impl {
  config::ModelConfig model;
  std::shared_ptr<ActorCritic> net;
  std::unique_ptr<torch::optim::Adam> actor_opt, critic_opt;
  ObsNormalizer normalizer;
  std::unique_ptr<torch::optim::Adam> clone_opt;  // pretraining's, kept across iterations

  std::vector<torch::Tensor> ActorParams() const {
    std::vector<torch::Tensor> p = net->actor->parameters();
    if (model.learn_log_std()) p.push_back(net->log_std);
    return p;
  }
};

namespace {

torch::Tensor FromVector(const std::vector<float>& v, std::vector<int64_t> shape) {
  return torch::from_blob(const_cast<float*>(v.data()), shape, torch::kFloat32).clone();
}

std::string ArchiveBytes(const std::function<void(torch::serialize::OutputArchive&)>& fill) {
  torch::serialize::OutputArchive archive;
  fill(archive);
  std::ostringstream out;
  archive.save_to(out);
  return out.str();
}

void ClipGradients(const std::vector<torch::Tensor>& params, double max_norm) {
  if (max_norm > 0) torch::nn::utils::clip_grad_norm_(params, max_norm);
}

// A random minibatch of `n` demonstration rows: (observations, labels), views copied out.
std::pair<torch::Tensor, torch::Tensor> DemoMinibatch(const DemoBuffer& demos, int64_t n) {
  const int64_t size = demos.size();
  const torch::Tensor all_obs = torch::from_blob(const_cast<float*>(demos.obs()),
                                                 {size, demos.obs_dim()}, torch::kFloat32);
  const torch::Tensor all_labels = torch::from_blob(const_cast<float*>(demos.labels()),
                                                    {size, demos.act_dim()}, torch::kFloat32);
  const torch::Tensor idx = torch::randint(size, {n}, torch::kLong);
  return {all_obs.index_select(0, idx), all_labels.index_select(0, idx)};
}

// The weighted label error of `mean` against `labels` (ImitationTerm::action_weights).
torch::Tensor LabelError(const torch::Tensor& mean, const torch::Tensor& labels,
                         const torch::Tensor& weights) {
  const torch::Tensor sq = (mean - labels).pow(2);
  return weights.defined() ? (sq * weights).mean() : sq.mean();
}

}  // namespace

PpoTrainer::PpoTrainer(const config::ModelConfig& model, const config::PpoConfig& ppo,
                       int obs_dim, int act_dim, uint64_t seed)
    : impl_(std::make_unique<Impl>()),
      ppo_(ppo),
      obs_dim_(obs_dim),
      act_dim_(act_dim),
      actor_lr_(ppo.actor_lr()) {
  torch::manual_seed(seed);
  torch::set_num_threads(std::max(1, ppo.torch_threads()));
  impl_->model = model;
  impl_->net = std::make_shared<ActorCritic>(model, obs_dim, act_dim);
  impl_->net->normalize = ppo.normalize_observations();
  impl_->normalizer = ObsNormalizer(obs_dim);
}

PpoTrainer::~PpoTrainer() = default;

std::vector<float> PpoTrainer::Values(const float* obs, int64_t n) const {
  if (n == 0) return {};
  torch::NoGradGuard no_grad;
  torch::Tensor x = torch::from_blob(const_cast<float*>(obs), {n, obs_dim_}, torch::kFloat32);
  torch::Tensor v = impl_->net->Value(x).contiguous();
  return std::vector<float>(v.data_ptr<float>(), v.data_ptr<float>() + n);
}

std::vector<float> PpoTrainer::ActorGates(const float* obs, int64_t n, int* num_experts) const {
  *num_experts = 0;
  if (n == 0 || !impl_->net->actor->is_moe()) return {};
  torch::NoGradGuard no_grad;
  torch::Tensor x = torch::from_blob(const_cast<float*>(obs), {n, obs_dim_}, torch::kFloat32);
  torch::Tensor g = impl_->net->actor->Gate(impl_->net->Normalize(x)).contiguous();
  *num_experts = static_cast<int>(g.size(1));
  return std::vector<float>(g.data_ptr<float>(), g.data_ptr<float>() + g.numel());
}

double PpoTrainer::ImitationError(const DemoBuffer& demos,
                                  const std::vector<float>& action_weights) const {
  const int64_t n = demos.size();
  if (n == 0) return 0;
  torch::NoGradGuard no_grad;
  const torch::Tensor obs = torch::from_blob(const_cast<float*>(demos.obs()),
                                             {n, demos.obs_dim()}, torch::kFloat32);
  const torch::Tensor labels = torch::from_blob(const_cast<float*>(demos.labels()),
                                                {n, demos.act_dim()}, torch::kFloat32);
  torch::Tensor weights;
  if (static_cast<int>(action_weights.size()) == demos.act_dim()) {
    weights = FromVector(action_weights, {demos.act_dim()});
  }
  return LabelError(impl_->net->Mean(obs), labels, weights).item<double>();
}

// One update's view of a validated batch, as tensors (n = num_samples rows).
struct PpoTrainer::UpdateBatch {
  int64_t n = 0;
  int minibatches = 1;          // per epoch, for the critic and the actor alike
  torch::Tensor obs;            // [n, obs_dim], raw observations
  torch::Tensor actions;        // [n, act_dim]
  torch::Tensor old_log_probs;  // [n], of the policy that acted
  torch::Tensor returns;        // [n], GAE's returns: the critic's targets
  torch::Tensor advantages;     // [n], GAE's; after FinalizeAdvantages, what the actor uses
  torch::Tensor label_weights;  // [act_dim], or undefined: unweighted label error
  bool has_demos = false;       // the imitation term has demonstration rows
};

namespace {

// `epochs` passes over the rows [0, n) in `minibatches` minibatches each: per epoch one
// torch::randperm draw, then fn(idx) per minibatch with idx [≤ max(1, n / minibatches)] int64
// row indices of that permutation. Returns the number of calls.
int ForEachMinibatch(int64_t n, int epochs, int minibatches,
                     const std::function<void(const torch::Tensor& idx)>& fn) {
  const int64_t mb_size = std::max<int64_t>(1, n / minibatches);
  int calls = 0;
  for (int epoch = 0; epoch < epochs; ++epoch) {
    const torch::Tensor perm = torch::randperm(n, torch::kLong);
    for (int m = 0; m < minibatches; ++m) {
      fn(perm.slice(0, m * mb_size, std::min(n, (m + 1) * mb_size)));
      ++calls;
    }
  }
  return calls;
}

}  // namespace

absl::StatusOr<UpdateStats> PpoTrainer::Update(const UnrollBatch& batch, int64_t max_policy_lag,
                                               const ImitationTerm& imitation) {
  RETURN_IF_ERROR(ValidateUnrollBatch(batch, obs_dim_, act_dim_, version_, max_policy_lag));
  RETURN_IF_ERROR(ValidateImitation(imitation));
  UpdateBatch b = MakeUpdateBatch(batch, imitation);
  PrepareOptimizers();
  UpdateStats stats;
  stats.samples = b.n;
  stats.actor_lr = actor_lr_;
  stats.value_loss = UpdateCritic(b);
  FinalizeAdvantages(&b, &stats);
  if (imitation.clone_only) {
    // Pretraining: the actor only clones the demonstrations; the learning rate waits.
    CloneActor(b, imitation, &stats);
  } else {
    UpdateActor(b, imitation, &stats);
    DecayLearningRate();
  }
  FinishUpdate(batch);
  return stats;
}

absl::Status PpoTrainer::ValidateImitation(const ImitationTerm& imitation) const {
  if (!imitation.action_weights.empty() &&
      static_cast<int>(imitation.action_weights.size()) != act_dim_) {
    return absl::InvalidArgumentError("imitation action weights do not match the actions");
  }
  const DemoBuffer* demos = imitation.demos;
  if (demos != nullptr && demos->size() > 0 &&
      (demos->obs_dim() != obs_dim_ || demos->act_dim() != act_dim_)) {
    return absl::InvalidArgumentError("the demonstrations' dimensions differ from the policy's");
  }
  return absl::OkStatus();
}

PpoTrainer::UpdateBatch PpoTrainer::MakeUpdateBatch(const UnrollBatch& batch,
                                                    const ImitationTerm& imitation) const {
  UpdateBatch b;
  b.n = batch.num_samples();
  b.minibatches = std::max(1, ppo_.num_minibatches());
  b.has_demos = imitation.demos != nullptr && imitation.demos->size() > 0;
  if (!imitation.action_weights.empty()) {
    b.label_weights = FromVector(imitation.action_weights, {act_dim_});
  }
  b.obs = FromVector(batch.obs, {b.n, obs_dim_});
  b.actions = FromVector(batch.actions, {b.n, act_dim_});
  b.old_log_probs = FromVector(batch.log_probs, {b.n});
  // Values for GAE: V(s_t), V(bootstrap), V(final obs of truncated episodes).
  const std::vector<float> values = Values(batch.obs.data(), b.n);
  const std::vector<float> boot = Values(batch.bootstrap_obs.data(), batch.num_unrolls);
  const std::vector<float> trunc = Values(batch.truncated_obs.data(), batch.num_truncated());
  AdvantageInputs in;
  in.num_unrolls = batch.num_unrolls;
  in.unroll_length = batch.unroll_length;
  in.rewards = batch.rewards.data();
  in.done = batch.done.data();
  in.truncated = batch.truncated.data();
  in.values = values.data();
  in.bootstrap_values = boot.data();
  in.truncated_values = trunc.data();
  std::vector<float> returns;
  const std::vector<float> advantages =
      ComputeAdvantages(in, ppo_.gamma(), ppo_.gae_lambda(), &returns);
  b.returns = FromVector(returns, {b.n});
  b.advantages = FromVector(advantages, {b.n});
  return b;
}

void PpoTrainer::PrepareOptimizers() {
  const double critic_lr = actor_lr_ * ppo_.critic_lr_factor();
  if (ppo_.reset_optimizer_each_iteration() || !impl_->actor_opt) {
    impl_->actor_opt = std::make_unique<torch::optim::Adam>(
        impl_->ActorParams(), torch::optim::AdamOptions(actor_lr_));
    impl_->critic_opt = std::make_unique<torch::optim::Adam>(
        impl_->net->critic->parameters(), torch::optim::AdamOptions(critic_lr));
    return;
  }
  for (auto& g : impl_->actor_opt->param_groups()) {
    static_cast<torch::optim::AdamOptions&>(g.options()).lr(actor_lr_);
  }
  for (auto& g : impl_->critic_opt->param_groups()) {
    static_cast<torch::optim::AdamOptions&>(g.options()).lr(critic_lr);
  }
}

double PpoTrainer::UpdateCritic(const UpdateBatch& b) {
  ActorCritic& net = *impl_->net;
  double loss_sum = 0;
  const int updates =
      ForEachMinibatch(b.n, ppo_.epochs(), b.minibatches, [&](const torch::Tensor& idx) {
        const torch::Tensor v = net.Value(b.obs.index_select(0, idx));
        const torch::Tensor loss = 0.5 * (v - b.returns.index_select(0, idx)).pow(2).mean();
        impl_->critic_opt->zero_grad();
        loss.backward();
        ClipGradients(net.critic->parameters(), ppo_.max_grad_norm());
        impl_->critic_opt->step();
        loss_sum += loss.item<double>();
      });
  return updates ? loss_sum / updates : 0;
}

void PpoTrainer::FinalizeAdvantages(UpdateBatch* b, UpdateStats* stats) const {
  if (ppo_.advantages_after_critic()) {
    torch::NoGradGuard no_grad;
    b->advantages = b->returns - impl_->net->Value(b->obs);
  }
  stats->mean_advantage = b->advantages.mean().item<double>();
  if (ppo_.normalize_advantages()) {
    b->advantages = (b->advantages - b->advantages.mean()) / (b->advantages.std() + 1e-8);
  }
}

void PpoTrainer::CloneActor(const UpdateBatch& b, const ImitationTerm& imitation,
                            UpdateStats* stats) {
  stats->cloned_only = true;
  if (!b.has_demos) return;
  if (!impl_->clone_opt) {
    impl_->clone_opt = std::make_unique<torch::optim::Adam>(
        impl_->net->actor->parameters(), torch::optim::AdamOptions(imitation.clone_lr));
  }
  for (auto& g : impl_->clone_opt->param_groups()) {
    static_cast<torch::optim::AdamOptions&>(g.options()).lr(imitation.clone_lr);
  }
  ActorCritic& net = *impl_->net;
  for (int step = 0; step < imitation.clone_steps; ++step) {
    auto [demo_obs, demo_labels] =
        DemoMinibatch(*imitation.demos, std::max(1, imitation.clone_minibatch));
    const torch::Tensor loss = LabelError(net.Mean(demo_obs), demo_labels, b.label_weights);
    impl_->clone_opt->zero_grad();
    loss.backward();
    ClipGradients(net.actor->parameters(), ppo_.max_grad_norm());
    impl_->clone_opt->step();
    stats->imitation_loss += loss.item<double>();
  }
  if (imitation.clone_steps > 0) stats->imitation_loss /= imitation.clone_steps;
}

void PpoTrainer::UpdateActor(const UpdateBatch& b, const ImitationTerm& imitation,
                             UpdateStats* stats) {
  const double weight = b.has_demos ? imitation.weight : 0;
  stats->imitation_weight = weight;
  torch::Tensor start_mean;  // the policy the iteration started from (adaptive learning rate)
  if (ppo_.desired_kl() > 0) {
    torch::NoGradGuard no_grad;
    start_mean = impl_->net->Mean(b.obs);
  }
  const int updates =
      ForEachMinibatch(b.n, ppo_.epochs(), b.minibatches, [&](const torch::Tensor& idx) {
        ActorMinibatchStep(b, idx, imitation.demos, weight, start_mean, stats);
      });
  if (updates) {
    stats->policy_loss /= updates;
    stats->approx_kl /= updates;
    stats->clip_fraction /= updates;
    stats->imitation_loss /= updates;
  }
}

void PpoTrainer::ActorMinibatchStep(const UpdateBatch& b, const at::Tensor& idx,
                                    const DemoBuffer* demos, double weight,
                                    const at::Tensor& start_mean, UpdateStats* stats) {
  ActorCritic& net = *impl_->net;
  const double clip = ppo_.clip();
  const torch::Tensor mean = net.Mean(b.obs.index_select(0, idx));
  const torch::Tensor log_prob = net.LogProb(b.actions.index_select(0, idx), mean);
  const torch::Tensor old = b.old_log_probs.index_select(0, idx);
  const torch::Tensor adv = b.advantages.index_select(0, idx);
  const torch::Tensor ratio = torch::exp(log_prob - old);
  const torch::Tensor surrogate =
      torch::min(ratio * adv, torch::clamp(ratio, 1 - clip, 1 + clip) * adv);
  torch::Tensor loss = -surrogate.mean() + ppo_.action_reg() * mean.pow(2).mean();
  if (weight > 0) {
    auto [demo_obs, demo_labels] = DemoMinibatch(*demos, idx.size(0));
    const torch::Tensor clone = LabelError(net.Mean(demo_obs), demo_labels, b.label_weights);
    stats->imitation_loss += clone.item<double>();
    loss = loss + weight * clone;
  }
  impl_->actor_opt->zero_grad();
  loss.backward();
  ClipGradients(impl_->ActorParams(), ppo_.max_grad_norm());
  impl_->actor_opt->step();
  stats->policy_loss += loss.item<double>();
  stats->approx_kl += (old - log_prob).mean().item<double>();
  if (start_mean.defined()) AdaptLearningRate(mean.detach(), start_mean.index_select(0, idx));
  stats->clip_fraction += ((ratio - 1).abs() > clip).to(torch::kFloat32).mean().item<double>();
}

void PpoTrainer::DecayLearningRate() {
  if (ppo_.desired_kl() > 0) return;  // the rate adapts per minibatch instead
  actor_lr_ = actor_lr_ > ppo_.min_actor_lr() ? actor_lr_ * ppo_.lr_decay() : ppo_.min_actor_lr();
  actor_lr_ = std::max(actor_lr_, ppo_.min_actor_lr());
}

void PpoTrainer::FinishUpdate(const UnrollBatch& batch) {
  ActorCritic& net = *impl_->net;
  const int64_t n = batch.num_samples();
  if (ppo_.normalize_observations()) {
    // After the update, so this iteration trained with the statistics the workers used.
    impl_->normalizer.Update(batch.obs.data(), n);
    torch::NoGradGuard no_grad;
    const std::vector<float> mean = impl_->normalizer.Mean();
    const std::vector<float> inv = impl_->normalizer.InvStd();
    net.norm_mean.copy_(FromVector(mean, {obs_dim_}));
    net.norm_inv_std.copy_(FromVector(inv, {obs_dim_}));
  }
  ++version_;
  ++iteration_;
}

void PpoTrainer::AdaptLearningRate(const torch::Tensor& mean, const torch::Tensor& start_mean) {
  // KL(π_start || π) of diagonal Gaussians with the same σ: Σ (μ − μ_start)² / (2σ²).
  torch::NoGradGuard no_grad;
  const torch::Tensor var = torch::exp(2 * impl_->net->log_std.detach());
  const double kl = ((mean - start_mean).pow(2) / (2 * var)).sum(-1).mean().item<double>();
  if (kl > 2 * ppo_.desired_kl()) {
    actor_lr_ = std::max(ppo_.min_actor_lr(), actor_lr_ / 1.5);
  } else if (kl < ppo_.desired_kl() / 2) {
    actor_lr_ = std::min(ppo_.max_actor_lr(), actor_lr_ * 1.5);
  }
  for (auto& g : impl_->actor_opt->param_groups()) {
    static_cast<torch::optim::AdamOptions&>(g.options()).lr(actor_lr_);
  }
  for (auto& g : impl_->critic_opt->param_groups()) {
    static_cast<torch::optim::AdamOptions&>(g.options()).lr(actor_lr_ * ppo_.critic_lr_factor());
  }
}

FlatParameters PpoTrainer::ExportPolicy() const {
  return ExportActorParameters(*impl_->net, version_, ppo_.normalize_observations());
}

FlatParameters PpoTrainer::ExportAll() const {
  FlatParameters policy = ExportPolicy();
  std::vector<TensorSpec> layout = policy.layout();
  std::vector<float> values = policy.values();
  for (const auto& [spec, t] : impl_->net->critic->LayoutTensors()) {
    AppendTensor(spec, t, &layout, &values);
  }
  return *FlatParameters::Create(version_, std::move(layout), std::move(values));
}

std::map<std::string, std::string> PpoTrainer::SaveState() const {
  std::map<std::string, std::string> s;
  s["model"] = ArchiveBytes([&](auto& a) { impl_->net->save(a); });
  if (impl_->actor_opt) {
    s["actor_opt"] = ArchiveBytes([&](auto& a) { impl_->actor_opt->save(a); });
    s["critic_opt"] = ArchiveBytes([&](auto& a) { impl_->critic_opt->save(a); });
  }
  s["normalizer"] = impl_->normalizer.Serialize();
  s["counters"] = absl::StrCat(version_, " ", iteration_, " ", absl::StrFormat("%.17g", actor_lr_));
  const torch::Tensor rng = at::detail::getDefaultCPUGenerator().get_state();
  s["torch_rng"] = std::string(static_cast<const char*>(rng.data_ptr()), rng.numel());
  return s;
}

namespace {

// The "counters" section: "version iteration actor_lr". DATA_LOSS if malformed.
absl::Status ParseCounters(const std::string& text, int64_t* version, int64_t* iteration,
                           double* lr) {
  const std::vector<std::string> counters = absl::StrSplit(text, ' ');
  if (counters.size() != 3 || !absl::SimpleAtoi(counters[0], version) ||
      !absl::SimpleAtoi(counters[1], iteration) || !absl::SimpleAtod(counters[2], lr)) {
    return absl::DataLossError("learner state: bad counters");
  }
  return absl::OkStatus();
}

// Loads the "model" section into `net`. INVALID_ARGUMENT if a tensor's shape differs from
// `net`'s (a checkpoint of another model config), DATA_LOSS if the archive is unreadable.
absl::Status LoadNetwork(const std::string& bytes, ActorCritic* net) {
  try {
    torch::serialize::InputArchive archive;
    std::istringstream in(bytes);
    archive.load_from(in);
    // Loading takes the archive's shapes: a checkpoint of other networks (another model config)
    // must fail here, not in a later export.
    std::map<std::string, std::vector<int64_t>> shapes;
    for (const auto& t : net->named_parameters()) shapes[t.key()] = t.value().sizes().vec();
    for (const auto& t : net->named_buffers()) shapes[t.key()] = t.value().sizes().vec();
    net->load(archive);
    for (const auto& group : {net->named_parameters(), net->named_buffers()}) {
      for (const auto& t : group) {
        if (t.value().sizes().vec() != shapes[t.key()]) {
          return absl::InvalidArgumentError(absl::StrCat(
              "learner state: tensor ", t.key(), " has shape [",
              absl::StrJoin(t.value().sizes().vec(), ","), "], but this config's networks need [",
              absl::StrJoin(shapes[t.key()], ","), "] (the checkpoint was trained under another "
              "model config)"));
        }
      }
    }
  } catch (const c10::Error& e) {
    return absl::DataLossError(absl::StrCat("learner state: ", e.what_without_backtrace()));
  }
  return absl::OkStatus();
}

// Builds Adam optimizers over `impl`'s actor and critic parameters at rate `lr` and loads
// their state from `actor_bytes` and `critic_bytes`. DATA_LOSS if either is unreadable.
absl::Status LoadOptimizers(const PpoTrainer::Impl& impl, double lr,
                            const std::string& actor_bytes, const std::string& critic_bytes,
                            std::unique_ptr<torch::optim::Adam>* actor_opt,
                            std::unique_ptr<torch::optim::Adam>* critic_opt) {
  try {
    *actor_opt = std::make_unique<torch::optim::Adam>(impl.ActorParams(),
                                                      torch::optim::AdamOptions(lr));
    *critic_opt = std::make_unique<torch::optim::Adam>(impl.net->critic->parameters(),
                                                       torch::optim::AdamOptions(lr));
    torch::serialize::InputArchive a, c;
    std::istringstream ain(actor_bytes), cin(critic_bytes);
    a.load_from(ain);
    c.load_from(cin);
    (*actor_opt)->load(a);
    (*critic_opt)->load(c);
  } catch (const c10::Error& e) {
    return absl::DataLossError(absl::StrCat("learner state: ", e.what_without_backtrace()));
  }
  return absl::OkStatus();
}

// Sets torch's default CPU generator to the "torch_rng" section. DATA_LOSS if rejected.
absl::Status RestoreTorchRng(const std::string& rng) {
  torch::Tensor rng_state = torch::empty({int64_t(rng.size())}, torch::kUInt8);
  std::memcpy(rng_state.data_ptr(), rng.data(), rng.size());
  try {
    at::Generator generator = at::detail::getDefaultCPUGenerator();
    generator.set_state(rng_state);
  } catch (const c10::Error& e) {
    return absl::DataLossError(absl::StrCat("learner state: torch RNG: ", e.what_without_backtrace()));
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status PpoTrainer::RestoreState(const std::map<std::string, std::string>& sections) {
  for (const char* required : {"model", "normalizer", "counters", "torch_rng"}) {
    if (!sections.count(required)) {
      return absl::DataLossError(absl::StrCat("learner state lacks section '", required, "'"));
    }
  }
  // Parse everything into fresh objects first: on any error the trainer stays as it was.
  int64_t version = 0, iteration = 0;
  double lr = 0;
  RETURN_IF_ERROR(ParseCounters(sections.at("counters"), &version, &iteration, &lr));
  ASSIGN_OR_RETURN(ObsNormalizer normalizer, ObsNormalizer::Deserialize(sections.at("normalizer")));
  if (normalizer.dim() != obs_dim_) {
    return absl::InvalidArgumentError("learner state: normalizer dimension differs");
  }
  auto net = std::make_shared<ActorCritic>(impl_->model, obs_dim_, act_dim_);
  net->normalize = ppo_.normalize_observations();
  RETURN_IF_ERROR(LoadNetwork(sections.at("model"), net.get()));
  std::unique_ptr<torch::optim::Adam> actor_opt, critic_opt;
  if (sections.count("actor_opt")) {
    const Impl probe{impl_->model, net, nullptr, nullptr, ObsNormalizer(0), nullptr};
    RETURN_IF_ERROR(LoadOptimizers(probe, lr, sections.at("actor_opt"), sections.at("critic_opt"),
                                   &actor_opt, &critic_opt));
  }
  RETURN_IF_ERROR(RestoreTorchRng(sections.at("torch_rng")));
  impl_->net = net;
  impl_->clone_opt.reset();  // it held the old network's parameters
  impl_->actor_opt = std::move(actor_opt);
  impl_->critic_opt = std::move(critic_opt);
  impl_->normalizer = std::move(normalizer);
  version_ = version;
  iteration_ = iteration;
  actor_lr_ = lr;
  return absl::OkStatus();
}

}  // namespace juggle
