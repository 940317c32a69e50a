// Test helper: the description of a small run — two nodes a (initial) and b, edges a->b and
// b->a — for the dashboard and run-log tests.
#ifndef JUGGLE_LEARNER_TESTING_TWO_NODE_RUN_H_
#define JUGGLE_LEARNER_TESTING_TWO_NODE_RUN_H_

#include "learner/dashboard_state.h"

namespace juggle {

inline DashboardRunInfo TwoNodeRun() {
  DashboardRunInfo info;
  info.config_name = "test_run";
  info.family = "soccer_juggle";
  info.seed = 7;
  info.min_workers = 2;
  info.queue_capacity = 64;
  info.outcome_names = {"running", "time_limit", "diverged", "ball_lost"};
  info.nodes = {{"a", "DOWN", true}, {"b", "UP", false}};
  info.edges = {{0, 1, 1.0}, {1, 0, 2.0}};
  return info;
}

}  // namespace juggle

#endif  // JUGGLE_LEARNER_TESTING_TWO_NODE_RUN_H_
