#include "eval/summary.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace juggle {

double Percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const double pos = std::clamp(q, 0.0, 1.0) * (values.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (pos - lo) * (values[hi] - values[lo]);
}

EvalSummary Summarize(const std::vector<EpisodeResult>& episodes, double control_dt,
                      const std::vector<std::string>& outcome_names) {
  EvalSummary s;
  s.episodes = static_cast<int>(episodes.size());
  if (episodes.empty()) return s;
  std::vector<double> juggles;
  std::map<std::string, int> metric_counts;
  int ge10 = 0, ge20 = 0;
  for (const EpisodeResult& e : episodes) {
    juggles.push_back(e.juggles);
    ge10 += e.juggles >= 10;
    ge20 += e.juggles >= 20;
    s.mean_return += e.return_sum;
    s.mean_completions += e.completions;
    s.mean_episode_s += e.steps * control_dt;
    ++s.outcomes[OutcomeName(outcome_names, e.outcome)];
    if (!e.ending_detail.empty()) {
      ++s.ending_details[OutcomeName(outcome_names, e.outcome) + "." + e.ending_detail];
    }
    for (const NamedValue& m : e.metrics) {
      s.mean_metrics[m.name] += m.value;
      ++metric_counts[m.name];
    }
  }
  const double n = static_cast<double>(episodes.size());
  s.median_juggles = Percentile(juggles, 0.5);
  s.p10_juggles = Percentile(juggles, 0.1);
  s.p90_juggles = Percentile(juggles, 0.9);
  for (double j : juggles) s.mean_juggles += j / n;
  s.frac_juggles_ge_10 = ge10 / n;
  s.frac_juggles_ge_20 = ge20 / n;
  s.mean_return /= n;
  s.mean_completions /= n;
  s.mean_episode_s /= n;
  for (auto& [name, sum] : s.mean_metrics) sum /= metric_counts[name];
  return s;
}

nlohmann::ordered_json SummaryToJson(const EvalSummary& s) {
  nlohmann::ordered_json j = {
      {"episodes", s.episodes},
      {"median_juggles", s.median_juggles},
      {"p10_juggles", s.p10_juggles},
      {"p90_juggles", s.p90_juggles},
      {"mean_juggles", s.mean_juggles},
      {"frac_juggles_ge_10", s.frac_juggles_ge_10},
      {"frac_juggles_ge_20", s.frac_juggles_ge_20},
      {"mean_return", s.mean_return},
      {"mean_completions", s.mean_completions},
      {"mean_episode_s", s.mean_episode_s},
      {"outcomes", s.outcomes},
  };
  if (!s.ending_details.empty()) j["ending_details"] = s.ending_details;
  for (const auto& [name, mean] : s.mean_metrics) j["mean_" + name] = mean;
  return j;
}

std::string SummaryLine(const EvalSummary& s, bool juggles) {
  std::string line = absl::StrFormat("episodes=%d", s.episodes);
  if (juggles) {
    absl::StrAppend(&line, absl::StrFormat(
        " median_juggles=%g p10_juggles=%g p90_juggles=%g mean_juggles=%.3f "
        "frac_juggles_ge_10=%.3f frac_juggles_ge_20=%.3f",
        s.median_juggles, s.p10_juggles, s.p90_juggles, s.mean_juggles, s.frac_juggles_ge_10,
        s.frac_juggles_ge_20));
  }
  absl::StrAppend(&line, absl::StrFormat(" mean_return=%.4f mean_completions=%.3f "
                                         "mean_episode_s=%.3f",
                                         s.mean_return, s.mean_completions, s.mean_episode_s));
  for (const auto& [name, count] : s.outcomes) absl::StrAppend(&line, " ", name, "=", count);
  for (const auto& [name, count] : s.ending_details) {
    absl::StrAppend(&line, " ", name, "=", count);
  }
  for (const auto& [name, mean] : s.mean_metrics) {
    absl::StrAppend(&line, absl::StrFormat(" mean_%s=%.4f", name, mean));
  }
  return line;
}

}  // namespace juggle
