#include "planner/label_spread.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "common/adaptive_walk.h"
#include "common/rng.h"
#include "common/status_macros.h"
#include "planner/planner_config.h"
#include "planner/planning_pools.h"
#include "planner/receding_horizon.h"
#include "planner/rollout_pool.h"
#include "planner/tasks.h"

namespace juggle::planner {

namespace {
// Salts the DART noise's streams apart from the episode starts' and the planners' (which use
// the same seed and small stream numbers).
constexpr uint64_t kNoiseSalt = 0x6e6f697365ULL;  // "noise"
}  // namespace

absl::StatusOr<LabelSpreadReport> MeasureLabelSpread(
    std::shared_ptr<const EnvSpec> spec, const LoadedConfig& config,
    const LabelSpreadOptions& o, const std::function<void(const std::string&)>& progress) {
  if (absl::Status s = ValidatePlannerConfig(config); !s.ok()) return s;
  if (o.forks == 1 || o.forks < 0) {
    return absl::InvalidArgumentError("label spread needs 0 forks (none) or at least 2");
  }
  if (!(o.student_mix >= 0 && o.student_mix <= 1)) {
    return absl::InvalidArgumentError(
        absl::StrCat("student mix must be in [0, 1], not ", o.student_mix));
  }
  if (o.student_mix > 0 && o.student == nullptr) {
    return absl::InvalidArgumentError("a student mix needs a student policy");
  }
  if (!(o.expert_noise >= 0) || o.noise_hold_steps < 1) {
    return absl::InvalidArgumentError(absl::StrCat("expert noise must be >= 0 and its hold >= 1 "
                                                   "step, not ", o.expert_noise, " and ",
                                                   o.noise_hold_steps));
  }
  const config::PlannerConfig& pc = config.run.planner();
  ASSIGN_OR_RETURN(std::shared_ptr<const PlanningTask> task, MakePlanningTask(spec, pc));
  ASSIGN_OR_RETURN(PlanningPools pools, MakePlanningPools(spec, pc, pc.threads()));
  const int act = spec->act_dim();
  std::vector<double> sum(act, 0), sum_sq(act, 0);          // every visited state's label
  std::vector<double> student_sq(act, 0);                    // (student − label)²
  std::vector<float> obs(spec->obs_dim());
  std::vector<std::vector<double>> fork_var;                 // per re-plan state, per action
  LabelSpreadReport report;
  report.decision_size = task->decision_size();
  const AdaptiveWalk walk(&spec->graph());
  for (int e = 0; e < o.episodes; ++e) {
    std::unique_ptr<Env> env = spec->NewEnv(Rng::ForStream(o.seed, 0, e));
    env->Reset(walk);
    RecedingHorizonPlanner driver(task, pc, pools.search.get(), uint64_t(e) << 8, nullptr,
                                  pools.exact.get());
    const int steps = static_cast<int>(std::lround(o.seconds / spec->control_dt()));
    std::vector<float> a(act), fa(act), executed(act);
    Rng noise_rng = Rng::ForStream(o.seed ^ kNoiseSalt, 0, e);
    std::vector<double> noise(act, 0.0);
    int juggles = 0;
    const int steps_before = report.steps;
    for (int k = 0; k < steps; ++k) {
      std::vector<RecedingHorizonPlanner> forks;
      for (int f = 0; f < o.forks; ++f) forks.push_back(driver.Fork((uint64_t(e) << 8) + 1 + f));
      if (o.keep_rows || o.student != nullptr) env->WriteObservation(obs.data());
      if (o.keep_rows) report.row_obs.insert(report.row_obs.end(), obs.begin(), obs.end());
      RETURN_IF_ERROR(driver.Act(*env, a.data()));
      if (o.keep_rows) {
        report.row_labels.insert(report.row_labels.end(), a.begin(), a.end());
        const std::vector<double>& decision = driver.last_replan().decision;
        for (int v = 0; v < report.decision_size; ++v) {
          report.row_kicks.push_back(v < static_cast<int>(decision.size()) ? float(decision[v])
                                                                           : 0.0f);
        }
      }
      if (o.forks > 0 && driver.last_replan().env_step == env->steps()) {  // re-planned here
        std::vector<double> mean(act, 0), sq(act, 0);
        for (RecedingHorizonPlanner& fork : forks) {
          RETURN_IF_ERROR(fork.Act(*env, fa.data()));
          for (int i = 0; i < act; ++i) {
            mean[i] += fa[i];
            sq[i] += double(fa[i]) * fa[i];
          }
        }
        std::vector<double> var(act);
        for (int i = 0; i < act; ++i) {
          const double m = mean[i] / o.forks;
          var[i] = std::max(0.0, (sq[i] - o.forks * m * m) / (o.forks - 1));
        }
        fork_var.push_back(std::move(var));
      }
      for (int i = 0; i < act; ++i) {
        sum[i] += a[i];
        sum_sq[i] += double(a[i]) * a[i];
      }
      executed = a;
      if (o.student != nullptr) {
        const RowMatrix s = o.student->MeanActions(obs.data(), 1);
        for (int i = 0; i < act; ++i) {
          student_sq[i] += (s(0, i) - a[i]) * double(s(0, i) - a[i]);
          executed[i] = static_cast<float>(a[i] + o.student_mix * (double(s(0, i)) - a[i]));
        }
      }
      if (o.expert_noise > 0) {
        if (k % o.noise_hold_steps == 0) {
          for (double& n : noise) n = o.expert_noise * noise_rng.Normal();
        }
        for (int i = 0; i < act; ++i) {
          executed[i] = std::clamp(float(executed[i] + noise[i]), -1.0f, 1.0f);
        }
      }
      ++report.steps;
      const StepResult r = env->Step(executed.data(), walk);
      juggles = env->juggles();
      if (r.outcome != Outcome::kRunning) break;
    }
    report.juggles += juggles;
    if (o.keep_rows) report.episode_steps.push_back(report.steps - steps_before);
    report.episode_juggles.push_back(juggles);
    if (progress) {
      progress(absl::StrFormat("episode %d/%d: %d juggles, %zu re-plan states so far", e + 1,
                               o.episodes, juggles, fork_var.size()));
    }
  }
  report.states = static_cast<int>(fork_var.size());
  report.label_std.resize(act);
  report.fork_std.assign(act, 0);
  double weighted = 0, student_weighted = 0;
  if (o.student != nullptr) report.student_rmse.resize(act);
  for (int i = 0; i < act; ++i) {
    const double m = sum[i] / std::max(report.steps, 1);
    report.label_std[i] = std::sqrt(std::max(0.0, sum_sq[i] / std::max(report.steps, 1) - m * m));
    const double w = 1.0 / std::max(report.label_std[i] * report.label_std[i],
                                    o.min_label_std * o.min_label_std);
    double v = 0;
    for (const std::vector<double>& s : fork_var) v += s[i];
    v /= std::max(report.states, 1);
    report.fork_std[i] = std::sqrt(v);
    weighted += w * v;
    if (o.student != nullptr) {
      const double mse = student_sq[i] / std::max(report.steps, 1);
      report.student_rmse[i] = std::sqrt(mse);
      student_weighted += w * mse;
    }
  }
  report.weighted_spread = weighted / act;
  report.student_weighted_error = student_weighted / act;
  return report;
}

}  // namespace juggle::planner
