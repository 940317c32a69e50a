#include "envs/toss/juggle_schedule.h"

#include <algorithm>
#include <map>
#include <queue>
#include <tuple>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"

namespace juggle::toss {

absl::StatusOr<std::vector<ScheduledThrow>> FindScheduleTransition(JugglingState from,
                                                                   JugglingState to, int width) {
  if (width < 1 || width > 16) {
    return absl::InvalidArgumentError(absl::StrCat("state width ", width, " is outside 1..16"));
  }
  const JugglingState all = GroundState(width);
  if ((from & ~all) != 0 || (to & ~all) != 0) {
    return absl::InvalidArgumentError(absl::StrCat("states wider than ", width, " beats"));
  }
  // Dijkstra over states with cost (beats, ball changes), lexicographic.
  using Cost = std::pair<int, int>;
  std::map<JugglingState, Cost> best;
  std::map<JugglingState, std::pair<JugglingState, ScheduledThrow>> parent;
  using Item = std::tuple<Cost, JugglingState>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  best[from] = {0, 0};
  open.push({{0, 0}, from});
  while (!open.empty()) {
    const Cost cost = std::get<0>(open.top());
    const JugglingState s = std::get<1>(open.top());
    open.pop();
    if (cost != best[s]) continue;
    if (s == to) break;
    const bool lands = (s & 1) != 0;
    const JugglingState rest = s >> 1;
    auto relax = [&](JugglingState n, ScheduledThrow t) {
      const Cost c{cost.first + 1, cost.second + (t.change != BallChange::kNone)};
      auto it = best.find(n);
      if (it == best.end() || c < it->second) {
        best[n] = c;
        parent[n] = {s, t};
        open.push({c, n});
      }
    };
    // Nothing thrown: an empty beat, or the landing ball taken out.
    relax(rest, {0, lands ? BallChange::kRemoveBall : BallChange::kNone});
    for (int t = 1; t <= width; ++t) {
      const JugglingState bit = JugglingState{1} << (t - 1);
      if ((rest & bit) != 0) continue;
      relax(rest | bit, {t, lands ? BallChange::kNone : BallChange::kAddBall});
    }
  }
  if (best.find(to) == best.end()) {
    return absl::InvalidArgumentError(absl::StrCat("no transition from ",
                                                   FormatJugglingState(from, width), " to ",
                                                   FormatJugglingState(to, width)));
  }
  std::vector<ScheduledThrow> throws;
  for (JugglingState s = to; s != from;) {
    const auto& [prev, t] = parent.at(s);
    throws.push_back(t);
    s = prev;
  }
  std::reverse(throws.begin(), throws.end());
  return throws;
}

JuggleSchedule::JuggleSchedule(const Siteswap& pattern)
    : patterns_{pattern}, max_throw_(pattern.max_throw()), max_balls_(pattern.balls()) {}

absl::StatusOr<JuggleSchedule> JuggleSchedule::Transitions(const std::vector<Siteswap>& patterns,
                                                           int throws_each) {
  if (patterns.empty()) return absl::InvalidArgumentError("a transition run needs a pattern");
  JuggleSchedule s;
  s.patterns_ = patterns;
  for (const Siteswap& p : patterns) {
    s.max_throw_ = std::max(s.max_throw_, p.max_throw());
    s.max_balls_ = std::max(s.max_balls_, p.balls());
  }
  const int width = std::max(s.max_throw_, 1);
  for (size_t i = 0; i + 1 < patterns.size(); ++i) {
    const Siteswap& a = patterns[i];
    const int cycles = std::max(1, (throws_each + a.period() - 1) / a.period());
    for (int c = 0; c < cycles; ++c) {
      for (int t : a.throws()) s.sequence_.push_back({t, BallChange::kNone});
    }
    absl::StatusOr<std::vector<ScheduledThrow>> pass =
        FindScheduleTransition(a.state(), patterns[i + 1].state(), width);
    if (!pass.ok()) {
      return absl::InvalidArgumentError(absl::StrCat("from ", a.ToString(), " to ",
                                                      patterns[i + 1].ToString(), ": ",
                                                      pass.status().message()));
    }
    s.sequence_.insert(s.sequence_.end(), pass->begin(), pass->end());
  }
  return s;
}

JugglingState JuggleSchedule::StateAt(int beat) const {
  JugglingState state = 0;
  for (int b = beat - std::max(max_throw_, 1); b < beat; ++b) {
    const int landing = b + At(b).value;
    if (At(b).value > 0 && landing >= beat && landing - beat < 64) {
      state |= JugglingState{1} << (landing - beat);
    }
  }
  return state;
}

absl::StatusOr<JuggleSchedule> JuggleSchedule::SwitchAt(int beat, const Siteswap& next) const {
  if (beat < 0) return absl::InvalidArgumentError("a switch needs a beat >= 0");
  const int width = std::max({max_throw_, next.max_throw(), 1});
  if (width > 16) {
    return absl::InvalidArgumentError(
        absl::StrCat("throws of ", width, " beats are beyond the passages searched (16)"));
  }
  absl::StatusOr<std::vector<ScheduledThrow>> pass =
      FindScheduleTransition(StateAt(beat), next.state(), width);
  if (!pass.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat("from ", Name(), " to ", next.ToString(), ": ", pass.status().message()));
  }
  JuggleSchedule s;
  s.patterns_ = patterns_;
  s.patterns_.push_back(next);
  for (int b = 0; b < beat; ++b) s.sequence_.push_back(At(b));
  s.sequence_.insert(s.sequence_.end(), pass->begin(), pass->end());
  s.max_throw_ = std::max(max_throw_, next.max_throw());
  s.max_balls_ = std::max(max_balls_, next.balls());
  for (const ScheduledThrow& t : *pass) s.max_throw_ = std::max(s.max_throw_, t.value);
  return s;
}

ScheduledThrow JuggleSchedule::At(int beat) const {
  auto periodic = [](const Siteswap& p, int k) {
    const int n = p.period();
    return ScheduledThrow{p.throws()[((k % n) + n) % n], BallChange::kNone};
  };
  if (beat < 0) return periodic(patterns_.front(), beat);
  if (beat < sequence_length()) return sequence_[beat];
  return periodic(patterns_.back(), beat - sequence_length());
}

std::string JuggleSchedule::Name() const {
  std::vector<std::string> names;
  for (const Siteswap& p : patterns_) names.push_back(p.ToString());
  return absl::StrJoin(names, ">");
}

}  // namespace juggle::toss
