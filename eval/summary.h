// What an evaluation reports: the distribution of juggles per episode (median, 10th and 90th
// percentiles, the fraction reaching 10 and 20), mean return, completions and episode length,
// and how episodes ended, printed as the `key=value` line commands end with. Pure functions.
#ifndef JUGGLE_EVAL_SUMMARY_H_
#define JUGGLE_EVAL_SUMMARY_H_

#include <map>
#include <string>
#include <vector>

#include "nlohmann/json.hpp"

#include "eval/episode_runner.h"

namespace juggle {

struct EvalSummary {
  int episodes = 0;
  double median_juggles = 0;
  double p10_juggles = 0;
  double p90_juggles = 0;
  double mean_juggles = 0;
  double frac_juggles_ge_10 = 0;
  double frac_juggles_ge_20 = 0;
  double mean_return = 0;
  double mean_completions = 0;
  double mean_episode_s = 0;
  std::map<std::string, int> outcomes;             // by name, episodes that ended so
  // Episodes whose env named what ended them (Env::EndingDetail), by "outcome.detail", e.g.
  // "bad_contact.floor".
  std::map<std::string, int> ending_details;
  std::map<std::string, double> mean_metrics;       // Env::AppendEpisodeMetrics, averaged
};

// Percentile of `values` by linear interpolation between order statistics (numpy's default):
// q in [0, 1]. 0 for no values.
double Percentile(std::vector<double> values, double q);

EvalSummary Summarize(const std::vector<EpisodeResult>& episodes, double control_dt,
                      const std::vector<std::string>& outcome_names);

// The summary as JSON members: every field by name, `outcomes` as an object, each mean
// metric as "mean_<name>" (the evaluation tables' JSON lines; the run log's eval record is
// proto/run_log.proto's EvaluationRecord, filled by learner/in_run_eval.h's SetSummary).
nlohmann::ordered_json SummaryToJson(const EvalSummary& summary);

// "episodes=50 median_juggles=12 p10_juggles=4 ... mean_episode_s=9.870 ball_lost=31 ..."; with
// `juggles` false (EnvSpec::counts_juggles) the juggle fields are left out:
// "episodes=50 mean_return=... mean_completions=... mean_episode_s=... ...".
std::string SummaryLine(const EvalSummary& summary, bool juggles = true);

}  // namespace juggle

#endif  // JUGGLE_EVAL_SUMMARY_H_
