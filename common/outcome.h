// Why an episode ended. Values 0..2 mean the same in every env family; each family numbers its
// own outcomes from kFirstFamilyOutcome on (envs/<family>/outcomes.h) and names them all through
// EnvSpec::outcome_names(). Workers end episodes; the learner counts them by name on /metrics;
// the values travel on the wire as indices below kMaxOutcomes.
#ifndef JUGGLE_COMMON_OUTCOME_H_
#define JUGGLE_COMMON_OUTCOME_H_

#include <cstdint>
#include <string>
#include <vector>

namespace juggle {

enum class Outcome : uint8_t {
  kRunning = 0,    // the episode has not ended
  kTimeLimit = 1,  // truncated at the family's step limit (not a failure: bootstrapped)
  kDiverged = 2,   // simulator warning or non-finite state
  kFirstFamilyOutcome = 3,
};

// Outcome values on the wire are below this.
constexpr int kMaxOutcomes = 64;

// The family outcome number `i` (0-based).
constexpr Outcome FamilyOutcome(int i) { return static_cast<Outcome>(3 + i); }

// Names of the values shared by every family: {"running", "time_limit", "diverged"}. A family's
// outcome_names() starts with these.
std::vector<std::string> CommonOutcomeNames();

// names[o] if `o` is in range, else "outcome_<o>".
std::string OutcomeName(const std::vector<std::string>& names, Outcome o);

}  // namespace juggle

#endif  // JUGGLE_COMMON_OUTCOME_H_
