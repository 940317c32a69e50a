#include "learner/in_run_eval.h"

#include <chrono>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "nlohmann/json.hpp"
#include "common/status_macros.h"
#include "envs/registry.h"
#include "eval/controller.h"
#include "eval/episode_runner.h"

namespace juggle {

std::string InRunEvaluation::ToJson() const {
  nlohmann::ordered_json j = {
      {"event", "eval"},
      {"iteration", iteration},
      {"samples", samples},
      {"train_s", train_seconds},
      {"eval_s", eval_seconds},
      {"episodes", summary.episodes},
      {"median_juggles", summary.median_juggles},
      {"p10_juggles", summary.p10_juggles},
      {"p90_juggles", summary.p90_juggles},
      {"mean_juggles", summary.mean_juggles},
      {"frac_juggles_ge_10", summary.frac_juggles_ge_10},
      {"frac_juggles_ge_20", summary.frac_juggles_ge_20},
      {"mean_return", summary.mean_return},
      {"mean_episode_s", summary.mean_episode_s},
  };
  nlohmann::ordered_json outcomes = nlohmann::ordered_json::object();
  for (const auto& [name, count] : summary.outcomes) outcomes[name] = count;
  j["outcomes"] = std::move(outcomes);
  j["juggles"] = juggles;
  return j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

std::string InRunEvaluation::ToShort() const {
  return absl::StrFormat("eval @%.1f min: median %g juggles (p90 %g, >=10: %.0f%%)",
                         train_seconds / 60, summary.median_juggles, summary.p90_juggles,
                         100 * summary.frac_juggles_ge_10);
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

InRunEvaluation InRunEvaluator::Run(const EigenPolicy& policy, int64_t iteration,
                                    int64_t samples, double train_seconds) {
  const auto start = std::chrono::steady_clock::now();
  PolicyController controller(std::shared_ptr<const EigenPolicy>(&policy, [](const EigenPolicy*) {}));
  EpisodeOptions options;
  options.episodes = config_.episodes();
  options.seed = config_.seed();
  InRunEvaluation result;
  result.iteration = iteration;
  result.samples = samples;
  result.train_seconds = train_seconds;
  absl::StatusOr<EpisodeReport> report = RunEpisodes(spec_, &controller, options);
  if (report.ok()) {
    result.summary = Summarize(report->episodes, spec_->control_dt(), spec_->outcome_names());
    for (const EpisodeResult& episode : report->episodes) result.juggles.push_back(episode.juggles);
  }
  result.eval_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  last_iteration_ = iteration;
  last_seconds_ = train_seconds;
  return result;
}

}  // namespace juggle
