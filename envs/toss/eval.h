// The toss evaluation protocol (docs/toss.md): for each pattern, the median over seeds of the
// throws before the first drop (capped); the longest chain of basic patterns 3, 4, 5, ... that
// reach 100 throws; and a wind sweep — the largest constant horizontal force on balls in flight
// under which 3 still reaches 100 throws. Also the arm states where the policies took over
// (`juggle toss --record-states`). Thread-compatible.
#ifndef JUGGLE_ENVS_TOSS_EVAL_H_
#define JUGGLE_ENVS_TOSS_EVAL_H_

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "envs/toss/juggler.h"
#include "envs/toss/siteswap.h"
#include "envs/toss/spec.h"

namespace juggle::toss {

// Arm states where the policies took over, gathered over runs.
struct StartStates {
  std::vector<TossArmState> catch_starts, throw_starts;
  void Add(const JuggleRunResult& r);
};

// One juggling run of `pattern` from seed `seed`; appended to `recording` if given.
absl::StatusOr<JuggleRunResult> RunOnce(std::shared_ptr<const TossSpec> spec,
                                        const JuggleSchedule& schedule, TossPolicies policies,
                                        int max_throws, uint64_t seed,
                                        TrajectoryBuilder* recording = nullptr);

// `base`'s spec with a constant horizontal force `wind` (N) on balls in flight.
absl::StatusOr<std::shared_ptr<const TossSpec>> SpecWithWind(const LoadedConfig& base,
                                                             double wind);

struct TossEvalOptions {
  std::vector<std::string> patterns = {"3", "4", "5", "53", "441", "531", "6", "7"};
  int first_seed = 1;
  int seeds = 10;
  int max_throws = 200;
  double wind_step = 0.02;  // N
  double wind_max = 1.0;    // N
  bool keep_start_states = false;
  // The transition run: these patterns in turn, each for throws_each throws, then 20 throws of
  // the last; empty: none.
  std::vector<std::string> transitions = {"3", "531", "5", "7", "3"};
  int throws_each = 20;
};

// The transition run over the seeds: throws made of the `needed` (the whole schedule).
struct TransitionResult {
  std::string name;  // "3>531>5>7>3"
  int needed = 0;
  int median_throws = 0;
  std::vector<int> throws;  // per seed
};

// Release and catch accuracy over runs: |v − v̄| at releases (m/s; v̄ the schedule's in still
// air), |hand_z − z_ball| at catches (m).
struct ThrowAccuracy {
  int releases = 0, catches = 0;
  double velocity_error_sum = 0, max_velocity_error = 0, catch_height_error_sum = 0;
  void Add(const JuggleRunResult& r);
  double mean_velocity_error() const { return releases ? velocity_error_sum / releases : 0; }
  double mean_catch_height_error() const { return catches ? catch_height_error_sum / catches : 0; }
};

struct PatternResult {
  std::string pattern;
  int balls = 0;
  int median_throws = 0;
  std::vector<int> throws;  // per seed, in seed order
  ThrowAccuracy accuracy;   // over its runs
};

// Release-velocity error per throw value over the pattern runs of an evaluation.
struct ValueAccuracy {
  int value = 0, releases = 0;
  double mean_velocity_error = 0;
};

struct TossEvalReport {
  std::vector<PatternResult> patterns;
  int max_basic_pattern = 0;
  double max_wind_n = 0;       // 0 when 3 fails even without wind
  std::vector<std::pair<double, int>> wind_sweep;  // (force, median throws of 3)
  std::vector<ValueAccuracy> by_value;  // ascending value
  std::optional<TransitionResult> transition;
  StartStates start_states;    // of the pattern runs, when kept
};

// Runs the protocol; `progress` (may be empty) receives a line per pattern and wind step.
// Errors: unparsable patterns, patterns the model cannot juggle.
absl::StatusOr<TossEvalReport> EvaluateToss(const LoadedConfig& base, TossPolicies policies,
                                            const TossEvalOptions& options,
                                            const std::function<void(const std::string&)>& progress);

// The report as JSON lines (`juggle toss --eval --json=FILE`): one object per pattern
// {"table":"toss_pattern","pattern":"531","balls":3,"median_throws":..,"throws":[per seed],
// "mean_velocity_error":..,"max_velocity_error":..,"mean_catch_height_error":..}, one per throw
// value {"table":"toss_throw_value","value":5,"releases":..,"mean_velocity_error":..},
// one per wind step {"table":"toss_wind","wind_n":..,"pattern":"3","median_throws":..}, and a
// summary {"table":"toss_summary","seeds":..,"max_throws":..,"max_basic_pattern":..,
// "max_wind_n":..}; and the transition run {"table":"toss_transition","name":"3>531>5>7>3",
// "needed":..,"median_throws":..,"throws":[per seed]}.
std::vector<std::string> TossEvalJsonLines(const TossEvalReport& report,
                                           const TossEvalOptions& options);

// Writes PREFIX_catch.textproto (states at releases: where the catch policy starts) and
// PREFIX_throw.textproto (states at catches: where the throw policy starts) as text-format
// TossArmStates (TossConfig.start_states_file).
absl::Status WriteStartStates(const StartStates& states, const std::string& prefix);

}  // namespace juggle::toss

#endif  // JUGGLE_ENVS_TOSS_EVAL_H_
