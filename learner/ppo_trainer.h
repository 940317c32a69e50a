// PPO on libtorch for the juggling policy (paper §5.1 as the reference implementation runs it; departures: docs/learning.md): critic epochs, then
// actor epochs with the clipped surrogate and the action-magnitude regularizer; GAE with
// termination and truncation kept apart; learning-rate decay per iteration; optional
// advantage and observation normalization. The torch state is hidden behind a pointer so this
// header stays cheap to include.
// Thread-compatible: one thread drives a trainer.
#ifndef JUGGLE_LEARNER_PPO_TRAINER_H_
#define JUGGLE_LEARNER_PPO_TRAINER_H_

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "common/flat_parameters.h"
#include "common/unroll_batch.h"
#include "proto/run_config.pb.h"

namespace at {
class Tensor;  // libtorch stays out of this header
}  // namespace at

namespace juggle {

class DemoBuffer;

// Planner-guided training's part of an update (docs/learning.md, "Planner-guided training").
struct ImitationTerm {
  const DemoBuffer* demos = nullptr;  // null or empty: no imitation
  // The label error is Σ_a w_a (mean_a − label_a)² / act_dim, averaged over rows, with w_a
  // these weights (empty: all 1).
  std::vector<float> action_weights;
  // Pretraining: the actor learns only by cloning (clone_steps Adam steps at clone_lr on
  // minibatches of clone_minibatch buffer rows); the critic trains on the batch as in PPO.
  bool clone_only = false;
  int clone_steps = 0;
  int clone_minibatch = 0;
  double clone_lr = 0;
  // Otherwise: PPO's actor loss + weight × the squared error of the mean action against the
  // label (averaged over actions) on a buffer minibatch as large as PPO's.
  double weight = 0;
};

struct UpdateStats {
  double value_loss = 0;
  double policy_loss = 0;
  double approx_kl = 0;
  double clip_fraction = 0;
  double mean_advantage = 0;
  double actor_lr = 0;
  int64_t samples = 0;
  // The imitation term: mean squared label error of the minibatches it saw (before their
  // steps; 0 without demonstrations), its weight, and whether the actor only cloned.
  double imitation_loss = 0;
  double imitation_weight = 0;
  bool cloned_only = false;
};

class PpoTrainer {
 public:
  // Seeds torch's default generator with `seed` and builds the networks.
  PpoTrainer(const config::ModelConfig& model, const config::PpoConfig& ppo, int obs_dim,
             int act_dim, uint64_t seed);
  ~PpoTrainer();

  // One PPO iteration on `batch`. The batch is validated first (see ValidateUnrollBatch; the
  // allowed lag is `max_policy_lag`); on error nothing is changed. On success the policy
  // version and the iteration advance by one.
  // With `imitation`, the actor also (or, pretraining, only) learns from the demonstrations;
  // the learning-rate decay waits while it only clones.
  absl::StatusOr<UpdateStats> Update(const UnrollBatch& batch, int64_t max_policy_lag = 0,
                                     const ImitationTerm& imitation = {});
  // The label error of the current actor on all the demonstrations' rows, no gradient: the
  // student's error against its teacher, weighted per action as ImitationTerm::action_weights
  // (empty: the plain mean squared error).
  double ImitationError(const DemoBuffer& demos, const std::vector<float>& action_weights = {}) const;

  // Actor + log-std + normalizer in the flat format workers load (EigenPolicy).
  FlatParameters ExportPolicy() const;
  // Actor and critic (all networks), for parity tests and tools.
  FlatParameters ExportAll() const;

  int64_t version() const { return version_; }
  int64_t iteration() const { return iteration_; }
  double actor_lr() const { return actor_lr_; }
  int obs_dim() const { return obs_dim_; }
  int act_dim() const { return act_dim_; }

  // Full learner state (model, optimizers, normalizer, counters, torch RNG) as named byte
  // sections, and its restoration. Restore: DATA_LOSS / INVALID_ARGUMENT on mismatch; the
  // trainer is unchanged on error.
  std::map<std::string, std::string> SaveState() const;
  absl::Status RestoreState(const std::map<std::string, std::string>& sections);

  // Values V(s) of raw observations [n, obs_dim] (no gradient).
  std::vector<float> Values(const float* obs, int64_t n) const;
  // The actor's gate weights for raw observations [n, obs_dim] (no gradient): [n, K] row-major,
  // K in *num_experts; empty (K = 0) when the actor is not a mixture of experts.
  std::vector<float> ActorGates(const float* obs, int64_t n, int* num_experts) const;

  struct Impl;

 private:
  // One update's batch as tensors, with its advantages and returns (defined in the .cc).
  struct UpdateBatch;

  // The steps of Update, in order. The torch RNG draws (randperm per epoch, randint per
  // demonstration minibatch) happen in this order, so a seed fixes the whole update.
  //
  // INVALID_ARGUMENT if the imitation term's action weights or demonstrations do not match
  // the policy's dimensions.
  absl::Status ValidateImitation(const ImitationTerm& imitation) const;
  // REQUIRES: `batch` validated. Its tensors, GAE advantages and returns under the current
  // critic (no gradient, no RNG draw).
  UpdateBatch MakeUpdateBatch(const UnrollBatch& batch, const ImitationTerm& imitation) const;
  // Actor and critic Adam at this iteration's rates: new on the first update (or every
  // update with reset_optimizer_each_iteration), else the same ones with their rates set.
  void PrepareOptimizers();
  // The critic's epochs: 0.5 × squared error of V(s) against the returns, one Adam step per
  // minibatch. Returns the mean loss over the minibatches (0 if there were none).
  double UpdateCritic(const UpdateBatch& b);
  // The advantages the actor uses: GAE's, or returns − V(s) under the updated critic with
  // advantages_after_critic; sets stats->mean_advantage, then normalizes if asked.
  void FinalizeAdvantages(UpdateBatch* b, UpdateStats* stats) const;
  // Pretraining: clone_steps Adam steps of the actor alone (its own optimizer, at clone_lr)
  // on random minibatches of demonstration rows; the PPO optimizers are untouched. Sets
  // cloned_only and imitation_loss (the mean before each step); nothing more without demos.
  void CloneActor(const UpdateBatch& b, const ImitationTerm& imitation, UpdateStats* stats);
  // The actor's epochs (ActorMinibatchStep each); sets policy_loss, approx_kl, clip_fraction
  // and imitation_loss as means over the minibatches, and imitation_weight.
  void UpdateActor(const UpdateBatch& b, const ImitationTerm& imitation, UpdateStats* stats);
  // One actor Adam step on rows `idx` ([m] int64): clipped surrogate + action-magnitude
  // regularizer, + weight × the label error on m random rows of `demos` if weight > 0 (then
  // REQUIRES demos non-empty). Adds the minibatch's terms to *stats. With a defined
  // `start_mean` ([n, act_dim], the iteration's starting means) the learning rate adapts.
  void ActorMinibatchStep(const UpdateBatch& b, const at::Tensor& idx, const DemoBuffer* demos,
                          double weight, const at::Tensor& start_mean, UpdateStats* stats);
  // Once per PPO iteration without desired_kl: the actor's rate decays towards its floor.
  void DecayLearningRate();
  // desired_kl: sets the learning rate from the KL between the iteration's starting means and
  // the current ones (minibatch rows), and applies it to both optimizers.
  void AdaptLearningRate(const at::Tensor& mean, const at::Tensor& start_mean);
  // The end of every update: the normalizer learns the batch's observations, version and
  // iteration advance.
  void FinishUpdate(const UnrollBatch& batch);
  std::unique_ptr<Impl> impl_;
  config::PpoConfig ppo_;
  int obs_dim_, act_dim_;
  int64_t version_ = 0;
  int64_t iteration_ = 0;
  double actor_lr_;
};

}  // namespace juggle

#endif  // JUGGLE_LEARNER_PPO_TRAINER_H_
