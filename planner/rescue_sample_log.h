// A record of every rollout the rescue search simulates (`juggle eval --rescue-samples-out`):
// the data to study how a troubled plan's cost and outcome depend on its variables
// (scripts/analysis/kick_landscape.py) or to fit a proposal from. JSON lines:
//   {"rescue":K,"stream":S,"step":T,"troubled_cost":C,"observation":[...]}   once per rescue,
//   {"rescue":K,"theta":[...],"outcome":[...],"cost":C}                      once per rollout,
//   {"rescue":K,"best_cost":C,"rollouts":N}                                   when it ends.
// K counts rescues from 1 in the order they begin; S is the planner's random stream, T the
// env's step; the observation is the env's (Env::WriteObservation); theta the candidate's
// variables (PlanningTask order); outcome the rollout's first outcome (PlanningTask; empty when
// the rollout predicted none, e.g. pruned before it); cost the search's cost of it (with
// PlannerConfig.prune, a pruned candidate's cost so far: a lower bound). Thread-safe.
#ifndef JUGGLE_PLANNER_RESCUE_SAMPLE_LOG_H_
#define JUGGLE_PLANNER_RESCUE_SAMPLE_LOG_H_

#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "envs/env.h"

namespace juggle::planner {

class RescueSampleLog {
 public:
  // Opens `path` for writing (truncated) for envs of `obs_dim` observations.
  // Errors: the file cannot be opened.
  static absl::StatusOr<std::unique_ptr<RescueSampleLog>> Open(const std::string& path,
                                                               int obs_dim);
  ~RescueSampleLog();
  RescueSampleLog(const RescueSampleLog&) = delete;
  RescueSampleLog& operator=(const RescueSampleLog&) = delete;

  // Starts a rescue of `env`'s current state by the planner of random stream
  // `stream`, whose regular search left `troubled_cost`; returns its K.
  int Begin(uint64_t stream, const Env& env, double troubled_cost);
  // One rollout of rescue `rescue`: `theta` holds `dim` values.
  void Rollout(int rescue, const double* theta, int dim, const std::vector<double>& outcome,
               double cost);
  void End(int rescue, double best_cost, int rollouts);

  int rescues() const;
  int64_t rollouts() const;
  // Flushes the file; errors: a failed write since Open.
  absl::Status Close();

 private:
  RescueSampleLog(std::FILE* file, int obs_dim) : obs_dim_(obs_dim), file_(file) {}
  void WriteLine(const std::string& line);  // REQUIRES: mu_ held

  const int obs_dim_;
  mutable std::mutex mu_;  // guards the members below
  std::FILE* file_;
  bool failed_ = false;
  int rescues_ = 0;
  int64_t rollouts_ = 0;
};

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_RESCUE_SAMPLE_LOG_H_
