#include "envs/toss/eval.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "common/file_io.h"
#include "common/status_macros.h"
#include "envs/toss/dims.h"
#include "google/protobuf/text_format.h"
#include "nlohmann/json.hpp"

namespace juggle::toss {
namespace {

// The median of throw counts (the lower-rounded mean of the middle two for an even count).
int Median(std::vector<int> throws) {
  std::sort(throws.begin(), throws.end());
  const size_t n = throws.size();
  return n % 2 ? throws[n / 2] : (throws[n / 2 - 1] + throws[n / 2]) / 2;
}

// Median of the throws over seeds first_seed..first_seed + seeds − 1.
absl::StatusOr<int> MedianThrows(std::shared_ptr<const TossSpec> spec, const Siteswap& pattern,
                                 TossPolicies policies, int max_throws, int first_seed, int seeds,
                                 std::vector<int>* all, StartStates* start_states,
                                 ThrowAccuracy* accuracy = nullptr,
                                 std::map<int, std::pair<double, int>>* by_value = nullptr) {
  std::vector<int> throws;
  for (int s = first_seed; s < first_seed + seeds; ++s) {
    ASSIGN_OR_RETURN(JuggleRunResult r,
                     RunOnce(spec, JuggleSchedule(pattern), policies, max_throws, s));
    throws.push_back(r.throws);
    if (start_states) start_states->Add(r);
    if (accuracy) accuracy->Add(r);
    if (by_value) {
      for (const auto& [value, sum_count] : r.velocity_error_by_value) {
        (*by_value)[value].first += sum_count.first;
        (*by_value)[value].second += sum_count.second;
      }
    }
  }
  if (all) *all = throws;
  return Median(std::move(throws));
}

// Writes `states` as a text-format TossArmStates file.
absl::Status WriteArmStates(const std::vector<TossArmState>& states, const std::string& path,
                            const std::string& what) {
  config::TossArmStates message;
  for (const TossArmState& s : states) {
    config::TossArmState* m = message.add_state();
    for (int j = 0; j < kTossJoints; ++j) {
      m->add_angle(s.angle[j]);
      m->add_speed(s.speed[j]);
    }
  }
  std::string text;
  if (!google::protobuf::TextFormat::PrintToString(message, &text)) {
    return absl::InternalError("cannot print the arm states");
  }
  return WriteFile(path, absl::StrCat(
      "# proto-file: proto/envs/toss.proto\n# proto-message: juggle.config.TossArmStates\n# ",
      states.size(), " arm states (right arm's frame: neck, shoulder, elbow, wrist; rad, rad/s) ",
      what, ", written by `juggle toss --record-states`.\n", text));
}

}  // namespace

void ThrowAccuracy::Add(const JuggleRunResult& r) {
  releases += r.releases;
  catches += r.catches;
  velocity_error_sum += r.mean_velocity_error * r.releases;
  max_velocity_error = std::max(max_velocity_error, r.max_velocity_error);
  catch_height_error_sum += r.mean_catch_height_error * r.catches;
}

void StartStates::Add(const JuggleRunResult& r) {
  catch_starts.insert(catch_starts.end(), r.catch_starts.begin(), r.catch_starts.end());
  throw_starts.insert(throw_starts.end(), r.throw_starts.begin(), r.throw_starts.end());
}

absl::StatusOr<JuggleRunResult> RunOnce(std::shared_ptr<const TossSpec> spec,
                                        const JuggleSchedule& schedule, TossPolicies policies,
                                        int max_throws, uint64_t seed,
                                        TrajectoryBuilder* recording) {
  JugglerOptions options;
  options.max_throws = max_throws;
  options.seed = seed;
  ASSIGN_OR_RETURN(std::unique_ptr<TossJuggler> juggler,
                   TossJuggler::Create(std::move(spec), schedule, policies, options));
  return juggler->Run(recording);
}

absl::StatusOr<std::shared_ptr<const TossSpec>> SpecWithWind(const LoadedConfig& base,
                                                             double wind) {
  LoadedConfig config = base;
  config.run.mutable_toss()->set_wind_force(wind);
  return TossSpec::Create(config);
}

absl::StatusOr<TossEvalReport> EvaluateToss(const LoadedConfig& base, TossPolicies policies,
                                            const TossEvalOptions& o,
                                            const std::function<void(const std::string&)>& progress) {
  auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };
  ASSIGN_OR_RETURN(std::shared_ptr<const TossSpec> spec,
                   SpecWithWind(base, base.run.toss().wind_force()));
  TossEvalReport report;
  std::map<int, std::pair<double, int>> by_value;
  bool basic_chain = true;
  for (const std::string& text : o.patterns) {
    ASSIGN_OR_RETURN(Siteswap pattern, Siteswap::Parse(text));
    PatternResult r;
    r.pattern = text;
    r.balls = pattern.balls();
    ASSIGN_OR_RETURN(r.median_throws,
                     MedianThrows(spec, pattern, policies, o.max_throws, o.first_seed, o.seeds,
                                  &r.throws, o.keep_start_states ? &report.start_states : nullptr,
                                  &r.accuracy, &by_value));
    std::string per_seed;
    for (int t : r.throws) absl::StrAppend(&per_seed, " ", t);
    say(absl::StrFormat("%-8s %5d %8d  %8.1e %8.1e %6.2f  %s", text, r.balls, r.median_throws,
                        r.accuracy.mean_velocity_error(), r.accuracy.max_velocity_error,
                        100 * r.accuracy.mean_catch_height_error(), per_seed));
    if (pattern.period() == 1 && pattern.balls() >= 3) {
      // Basic patterns count upwards from 3 without a gap.
      if (basic_chain && r.median_throws >= 100 &&
          pattern.balls() == std::max(3, report.max_basic_pattern + 1)) {
        report.max_basic_pattern = pattern.balls();
      } else if (r.median_throws < 100) {
        basic_chain = false;
      }
    }
    report.patterns.push_back(std::move(r));
  }
  for (const auto& [value, sum_count] : by_value) {
    report.by_value.push_back({value, sum_count.second, sum_count.first / sum_count.second});
    say(absl::StrFormat("throw %d: %d releases, mean release-velocity error %.2e m/s", value,
                        sum_count.second, sum_count.first / sum_count.second));
  }
  if (!o.transitions.empty()) {
    std::vector<Siteswap> patterns;
    for (const std::string& text : o.transitions) {
      ASSIGN_OR_RETURN(Siteswap p, Siteswap::Parse(text));
      patterns.push_back(p);
    }
    ASSIGN_OR_RETURN(JuggleSchedule schedule, JuggleSchedule::Transitions(patterns, o.throws_each));
    TransitionResult t;
    t.name = schedule.Name();
    t.needed = schedule.sequence_length() + 20;  // every planned beat throws, or nearly
    for (int s = o.first_seed; s < o.first_seed + o.seeds; ++s) {
      ASSIGN_OR_RETURN(JuggleRunResult r, RunOnce(spec, schedule, policies, t.needed, s));
      t.throws.push_back(r.throws);
    }
    t.median_throws = Median(t.throws);
    std::string per_seed;
    for (int x : t.throws) absl::StrAppend(&per_seed, " ", x);
    say(absl::StrFormat("transitions %s: median %d of %d throws; per seed%s", t.name,
                        t.median_throws, t.needed, per_seed));
    report.transition = std::move(t);
  }
  // Wind sweep: the largest force at which the median over the seeds still reaches 100 throws
  // of "3".
  const Siteswap three = *Siteswap::Parse("3");
  double max_wind = -1;
  for (double wind = 0; wind <= o.wind_max + 1e-9; wind += o.wind_step) {
    ASSIGN_OR_RETURN(std::shared_ptr<const TossSpec> windy, SpecWithWind(base, wind));
    ASSIGN_OR_RETURN(int median,
                     MedianThrows(windy, three, policies, 100, o.first_seed, o.seeds, nullptr,
                                  nullptr));
    report.wind_sweep.push_back({wind, median});
    say(absl::StrFormat("wind %.3f N: median %d throws of 3", wind, median));
    if (median < 100) break;
    max_wind = wind;
  }
  report.max_wind_n = std::max(0.0, max_wind);
  return report;
}

absl::Status WriteStartStates(const StartStates& states, const std::string& prefix) {
  RETURN_IF_ERROR(WriteArmStates(states.catch_starts, prefix + "_catch.textproto",
                                 "of throwing hands at their releases"));
  return WriteArmStates(states.throw_starts, prefix + "_throw.textproto",
                        "of catching hands at their catches");
}

std::vector<std::string> TossEvalJsonLines(const TossEvalReport& report,
                                           const TossEvalOptions& options) {
  using Json = nlohmann::ordered_json;
  auto line = [](const Json& j) { return j.dump(-1, ' ', false, Json::error_handler_t::replace); };
  std::vector<std::string> lines;
  for (const PatternResult& p : report.patterns) {
    lines.push_back(line({{"table", "toss_pattern"},
                          {"pattern", p.pattern},
                          {"balls", p.balls},
                          {"median_throws", p.median_throws},
                          {"throws", p.throws},
                          {"mean_velocity_error", p.accuracy.mean_velocity_error()},
                          {"max_velocity_error", p.accuracy.max_velocity_error},
                          {"mean_catch_height_error", p.accuracy.mean_catch_height_error()}}));
  }
  for (const ValueAccuracy& v : report.by_value) {
    lines.push_back(line({{"table", "toss_throw_value"},
                          {"value", v.value},
                          {"releases", v.releases},
                          {"mean_velocity_error", v.mean_velocity_error}}));
  }
  for (const auto& [wind, median] : report.wind_sweep) {
    lines.push_back(line(
        {{"table", "toss_wind"}, {"wind_n", wind}, {"pattern", "3"}, {"median_throws", median}}));
  }
  if (report.transition) {
    lines.push_back(line({{"table", "toss_transition"},
                          {"name", report.transition->name},
                          {"needed", report.transition->needed},
                          {"median_throws", report.transition->median_throws},
                          {"throws", report.transition->throws}}));
  }
  lines.push_back(line({{"table", "toss_summary"},
                        {"seeds", options.seeds},
                        {"max_throws", options.max_throws},
                        {"max_basic_pattern", report.max_basic_pattern},
                        {"max_wind_n", report.max_wind_n}}));
  return lines;
}

}  // namespace juggle::toss
