// `--planner-trace`: one line per re-plan, for any planning task — its cost before and after
// the search, rollouts, rescue, predicted end, the task's description of the decision and its
// outcome (PlanningTask::DescribeDecision), and the chosen plan's cost terms by name.
#ifndef JUGGLE_PLANNER_REPLAN_TRACE_H_
#define JUGGLE_PLANNER_REPLAN_TRACE_H_

#include <string>

#include "envs/env.h"
#include "planner/planning_task.h"
#include "planner/receding_horizon.h"

namespace juggle::planner {

// "  re-plan slot S step N node K: cost A -> B (R rollouts)[ rescue][ light][ ends ...]<decision>
// terms: name=value ..." without a newline.
std::string FormatReplanTrace(const PlanningTask& task, const EnvSpec& spec, int slot,
                              const ReplanReport& r);

}  // namespace juggle::planner

#endif  // JUGGLE_PLANNER_REPLAN_TRACE_H_
