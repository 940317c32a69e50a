#include "learner/in_run_eval.h"

#include <chrono>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "common/status_macros.h"
#include "envs/registry.h"
#include "eval/controller.h"
#include "eval/episode_runner.h"

namespace juggle {

void SetSummary(const EvalSummary& s, runlog::EvaluationRecord* r) {
  r->set_episodes(s.episodes);
  r->set_median_juggles(s.median_juggles);
  r->set_p10_juggles(s.p10_juggles);
  r->set_p90_juggles(s.p90_juggles);
  r->set_mean_juggles(s.mean_juggles);
  r->set_frac_juggles_ge_10(s.frac_juggles_ge_10);
  r->set_frac_juggles_ge_20(s.frac_juggles_ge_20);
  r->set_mean_return(s.mean_return);
  r->set_mean_episode_s(s.mean_episode_s);
  r->set_mean_completions(s.mean_completions);
  r->mutable_outcomes()->clear();
  for (const auto& [name, count] : s.outcomes) (*r->mutable_outcomes())[name] = count;
  r->mutable_mean_metrics()->clear();
  for (const auto& [name, mean] : s.mean_metrics) (*r->mutable_mean_metrics())[name] = mean;
}

EvalSummary SummaryOf(const runlog::EvaluationRecord& r) {
  EvalSummary s;
  s.episodes = r.episodes();
  s.median_juggles = r.median_juggles();
  s.p10_juggles = r.p10_juggles();
  s.p90_juggles = r.p90_juggles();
  s.mean_juggles = r.mean_juggles();
  s.frac_juggles_ge_10 = r.frac_juggles_ge_10();
  s.frac_juggles_ge_20 = r.frac_juggles_ge_20();
  s.mean_return = r.mean_return();
  s.mean_episode_s = r.mean_episode_s();
  s.mean_completions = r.mean_completions();
  s.outcomes.insert(r.outcomes().begin(), r.outcomes().end());
  s.mean_metrics.insert(r.mean_metrics().begin(), r.mean_metrics().end());
  return s;
}

std::string EvaluationShort(const runlog::EvaluationRecord& r) {
  return absl::StrFormat("eval @%.1f min: median %g juggles (p90 %g, >=10: %.0f%%)",
                         r.train_s() / 60, r.median_juggles(), r.p90_juggles(),
                         100 * r.frac_juggles_ge_10());
}

absl::StatusOr<std::unique_ptr<InRunEvaluator>> InRunEvaluator::Create(const LoadedConfig& base) {
  std::unique_ptr<InRunEvaluator> e(new InRunEvaluator());
  e->config_ = base.run.evaluation();
  e->every_minutes_ = e->config_.every_minutes();
  e->every_iterations_ = e->config_.every_iterations();
  if (!e->enabled()) return e;
  LoadedConfig config = base;
  ASSIGN_OR_RETURN(const EnvFamily* family, FamilyOf(config.run));
  family->ConfigureForEvaluation(e->config_.max_seconds(), &config.run);
  ASSIGN_OR_RETURN(e->spec_, CreateEnvSpec(config));
  return e;
}

bool InRunEvaluator::Due(int64_t iteration, double train_seconds) const {
  if (every_iterations_ > 0 && iteration - last_iteration_ >= every_iterations_) return true;
  return every_minutes_ > 0 && train_seconds - last_seconds_ >= every_minutes_ * 60;
}

runlog::EvaluationRecord InRunEvaluator::Run(const EigenPolicy& policy, int64_t iteration,
                                             int64_t samples, double train_seconds) {
  const auto start = std::chrono::steady_clock::now();
  PolicyController controller(std::shared_ptr<const EigenPolicy>(&policy, [](const EigenPolicy*) {}));
  EpisodeOptions options;
  options.episodes = config_.episodes();
  options.seed = config_.seed();
  runlog::EvaluationRecord result;
  result.set_event("eval");
  result.set_iteration(static_cast<int32_t>(iteration));
  result.set_samples(static_cast<double>(samples));
  result.set_train_s(train_seconds);
  absl::StatusOr<EpisodeReport> report = RunEpisodes(spec_, &controller, options);
  if (report.ok()) {
    SetSummary(Summarize(report->episodes, spec_->control_dt(), spec_->outcome_names()), &result);
    for (const EpisodeResult& episode : report->episodes) result.add_juggles(episode.juggles);
  }
  result.set_eval_s(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  last_iteration_ = iteration;
  last_seconds_ = train_seconds;
  return result;
}

}  // namespace juggle
