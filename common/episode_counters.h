// Counters over finished episodes: what an env pool accumulates, a worker reports with each
// contribution, and the learner sums per iteration.
#ifndef JUGGLE_COMMON_EPISODE_COUNTERS_H_
#define JUGGLE_COMMON_EPISODE_COUNTERS_H_

#include <cstdint>
#include <vector>

namespace juggle {

struct EpisodeCounters {
  int64_t episodes = 0;
  int64_t steps = 0;             // env steps, finished episodes or not
  double return_sum = 0;
  int64_t length_sum = 0;        // control steps of the finished episodes
  int64_t completions_sum = 0;   // node completions of the finished episodes
  int64_t juggles_sum = 0;       // juggles of the finished episodes (Env::juggles())
  std::vector<int64_t> outcomes; // finished episodes by outcome value (common/outcome.h)

  void CountOutcome(int outcome) {
    if (static_cast<int>(outcomes.size()) <= outcome) outcomes.resize(outcome + 1, 0);
    ++outcomes[outcome];
  }
  int64_t outcome(int o) const { return o < static_cast<int>(outcomes.size()) ? outcomes[o] : 0; }
  void Add(const EpisodeCounters& o) {
    episodes += o.episodes;
    steps += o.steps;
    return_sum += o.return_sum;
    length_sum += o.length_sum;
    completions_sum += o.completions_sum;
    juggles_sum += o.juggles_sum;
    if (outcomes.size() < o.outcomes.size()) outcomes.resize(o.outcomes.size(), 0);
    for (size_t i = 0; i < o.outcomes.size(); ++i) outcomes[i] += o.outcomes[i];
  }
  double mean_return() const { return episodes ? return_sum / episodes : 0; }
  double mean_length() const { return episodes ? double(length_sum) / episodes : 0; }
  double mean_completions() const { return episodes ? double(completions_sum) / episodes : 0; }
  double mean_juggles() const { return episodes ? double(juggles_sum) / episodes : 0; }
};

}  // namespace juggle

#endif  // JUGGLE_COMMON_EPISODE_COUNTERS_H_
