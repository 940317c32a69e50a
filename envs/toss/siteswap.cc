#include "envs/toss/siteswap.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "absl/strings/escaping.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"

namespace juggle::toss {
namespace {

constexpr int kMaxEnumeratePeriod = 16;
constexpr size_t kMaxTransitionStates = size_t{1} << 20;

bool HasBit(JugglingState s, int k) { return (s >> k) & 1; }

// The state machine step without the error message; false when the throw is impossible.
bool TryThrow(JugglingState s, int t, JugglingState* next) {
  const JugglingState shifted = s >> 1;
  if (!HasBit(s, 0)) {
    if (t != 0) return false;
    *next = shifted;
    return true;
  }
  if (t <= 0 || HasBit(shifted, t - 1)) return false;
  *next = shifted | (JugglingState{1} << (t - 1));
  return true;
}

// Smallest r >= 0 with (s >> r) a subset of `to`: after r beats the balls of s still in the
// air sit where `to` has balls. A lower bound on the transition length from s to `to`: those
// balls cannot move before they land. Consistent: bound(s) <= 1 + bound(successor of s).
int TransitionLowerBound(JugglingState s, JugglingState to) {
  int r = 0;
  while (((s >> r) & ~to) != 0) ++r;
  return r;
}

// "positions 0 ('5'), 1 ('4') and 2 ('3')".
std::string DescribePositions(const std::vector<int>& throws, const std::vector<int>& positions) {
  std::vector<std::string> items;
  for (int p : positions) {
    items.push_back(absl::StrFormat("%d ('%c')", p, SiteswapThrowChar(throws[p])));
  }
  if (items.size() == 1) return items[0];
  const std::string last = items.back();
  items.pop_back();
  return absl::StrCat(absl::StrJoin(items, ", "), " and ", last);
}

}  // namespace

char SiteswapThrowChar(int value) {
  return value < 10 ? static_cast<char>('0' + value) : static_cast<char>('a' + value - 10);
}

std::string FormatSiteswap(const std::vector<int>& throws) {
  std::string out;
  out.reserve(throws.size());
  for (int t : throws) out.push_back(SiteswapThrowChar(t));
  return out;
}

absl::StatusOr<std::vector<int>> ParseSiteswapThrows(std::string_view text) {
  if (text.empty()) {
    return absl::InvalidArgumentError(
        "empty siteswap: expected throw values such as \"531\" (0-9, a-z for 10-35)");
  }
  if (text.size() > static_cast<size_t>(kMaxSiteswapLength)) {
    return absl::InvalidArgumentError(absl::StrCat("siteswap of ", text.size(),
                                                   " characters is longer than the limit of ",
                                                   kMaxSiteswapLength));
  }
  std::vector<int> throws;
  throws.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c >= '0' && c <= '9') {
      throws.push_back(c - '0');
    } else if (c >= 'a' && c <= 'z') {
      throws.push_back(c - 'a' + 10);
    } else if (c >= 'A' && c <= 'Z') {
      throws.push_back(c - 'A' + 10);
    } else {
      return absl::InvalidArgumentError(absl::StrCat(
          "siteswap \"", absl::CHexEscape(absl::string_view(text.data(), text.size())), "\": invalid character '",
          absl::CHexEscape(std::string(1, c)), "' at position ", i,
          " (expected 0-9, or a-z for throws 10-35; only vanilla asynchronous siteswaps are "
          "supported)"));
    }
  }
  return throws;
}

SiteswapCheck CheckSiteswap(const std::vector<int>& throws) {
  SiteswapCheck check;
  const int p = static_cast<int>(throws.size());
  check.period = p;
  std::map<int, std::vector<int>> by_beat;  // landing beat mod p -> positions
  for (int i = 0; i < p; ++i) {
    check.sum += throws[i];
    by_beat[(i + throws[i]) % p].push_back(i);
  }
  check.integer_average = p > 0 && check.sum % p == 0;
  std::vector<std::string> reasons;
  for (const auto& [beat, positions] : by_beat) {
    if (positions.size() < 2) continue;
    check.collisions.push_back({beat, positions});
    reasons.push_back(absl::StrFormat("throws at positions %s %s land on beat %d (mod %d)",
                                      DescribePositions(throws, positions),
                                      positions.size() == 2 ? "both" : "all", beat, p));
  }
  if (!check.integer_average && p > 0) {
    reasons.push_back(absl::StrFormat(
        "the throw sum %d is not a multiple of the period %d (average %.4g is not a whole number "
        "of balls)",
        check.sum, p, static_cast<double>(check.sum) / p));
  }
  check.valid = p > 0 && reasons.empty();
  check.reason = absl::StrJoin(reasons, "; ");
  return check;
}

JugglingState GroundState(int balls) {
  return balls <= 0 ? 0 : (balls >= 64 ? ~JugglingState{0} : (JugglingState{1} << balls) - 1);
}

std::string FormatJugglingState(JugglingState state, int width) {
  if (width <= 0) return "-";
  std::string out;
  for (int k = 0; k < width; ++k) out.push_back(HasBit(state, k) ? 'x' : '-');
  return out;
}

int BallsInState(JugglingState state) {
  int n = 0;
  for (; state != 0; state &= state - 1) ++n;
  return n;
}

absl::StatusOr<JugglingState> ApplyThrow(JugglingState state, int value) {
  if (value < 0 || value > kMaxSiteswapThrow) {
    return absl::InvalidArgumentError(
        absl::StrCat("throw ", value, " is outside 0..", kMaxSiteswapThrow));
  }
  JugglingState next = 0;
  if (TryThrow(state, value, &next)) return next;
  const std::string s = FormatJugglingState(state, std::max(value, 1) + 1);
  if (!HasBit(state, 0)) {
    return absl::InvalidArgumentError(absl::StrCat("from state ", s, " no ball lands now: only a 0 "
                                                   "can be thrown, not ", value));
  }
  if (value == 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("from state ", s, " a ball lands now: a 0 would drop it"));
  }
  return absl::InvalidArgumentError(absl::StrCat("from state ", s, " a throw of ", value,
                                                 " lands on a beat that already has a ball"));
}

absl::StatusOr<Siteswap> Siteswap::Parse(std::string_view text) {
  absl::StatusOr<std::vector<int>> throws = ParseSiteswapThrows(text);
  if (!throws.ok()) return throws.status();
  return FromThrows(*std::move(throws));
}

absl::StatusOr<Siteswap> Siteswap::FromThrows(std::vector<int> throws) {
  if (throws.empty()) return absl::InvalidArgumentError("empty siteswap");
  if (throws.size() > static_cast<size_t>(kMaxSiteswapLength)) {
    return absl::InvalidArgumentError(
        absl::StrCat("siteswap of ", throws.size(), " throws is longer than the limit of ",
                     kMaxSiteswapLength));
  }
  for (size_t i = 0; i < throws.size(); ++i) {
    if (throws[i] < 0 || throws[i] > kMaxSiteswapThrow) {
      return absl::InvalidArgumentError(absl::StrCat("throw ", throws[i], " at position ", i,
                                                     " is outside 0..", kMaxSiteswapThrow));
    }
  }
  const SiteswapCheck check = CheckSiteswap(throws);
  if (!check.valid) {
    return absl::InvalidArgumentError(
        absl::StrCat("siteswap \"", FormatSiteswap(throws), "\" is invalid: ", check.reason));
  }
  Siteswap s;
  s.throws_ = std::move(throws);
  const int p = s.period();
  s.balls_ = check.sum / p;
  s.max_throw_ = *std::max_element(s.throws_.begin(), s.throws_.end());
  // The state before throw 0: bit k is set when a throw made at a beat j < 0 of the infinite
  // repetition lands on beat k >= 0; such a j is at least k - max_throw.
  JugglingState state = 0;
  for (int k = 0; k < s.max_throw_; ++k) {
    for (int j = k - s.max_throw_; j < 0; ++j) {
      const int t = s.throws_[((j % p) + p) % p];
      if (j + t == k) state |= JugglingState{1} << k;
    }
  }
  // The following states by the state machine; a valid pattern returns to where it started.
  s.states_.resize(p);
  for (int i = 0; i < p; ++i) {
    s.states_[i] = state;
    JugglingState next = 0;
    if (!TryThrow(state, s.throws_[i], &next)) {
      return absl::InternalError(absl::StrCat("state machine rejects valid siteswap ",
                                              s.ToString(), " at position ", i));
    }
    state = next;
  }
  if (state != s.states_[0] || BallsInState(state) != s.balls_) {
    return absl::InternalError(
        absl::StrCat("state machine does not close the cycle of ", s.ToString()));
  }
  return s;
}

int Siteswap::GroundRotation() const {
  const JugglingState ground = GroundState(balls_);
  for (int i = 0; i < period(); ++i) {
    if (states_[i] == ground) return i;
  }
  return -1;
}

Siteswap Siteswap::Rotated(int k) const {
  Siteswap r = *this;
  std::rotate(r.throws_.begin(), r.throws_.begin() + k, r.throws_.end());
  std::rotate(r.states_.begin(), r.states_.begin() + k, r.states_.end());
  return r;
}

bool Siteswap::IsRepetition() const {
  const int p = period();
  for (int d = 1; d < p; ++d) {
    if (p % d != 0) continue;
    bool repeats = true;
    for (int i = d; i < p && repeats; ++i) repeats = throws_[i] == throws_[i - d];
    if (repeats) return true;
  }
  return false;
}

Siteswap Siteswap::CanonicalRotation() const {
  int best = 0;
  for (int k = 1; k < period(); ++k) {
    for (int i = 0; i < period(); ++i) {
      const int a = throws_[(k + i) % period()];
      const int b = throws_[(best + i) % period()];
      if (a != b) {
        if (a > b) best = k;
        break;
      }
    }
  }
  return Rotated(best);
}

absl::StatusOr<SiteswapTransition> FindTransition(JugglingState from, JugglingState to,
                                                  int width) {
  if (width < 1 || width > kMaxSiteswapThrow) {
    return absl::InvalidArgumentError(
        absl::StrCat("state width ", width, " is outside 1..", kMaxSiteswapThrow));
  }
  const JugglingState outside = ~GroundState(width);
  if ((from & outside) != 0 || (to & outside) != 0) {
    return absl::InvalidArgumentError(absl::StrCat("states wider than ", width, " beats"));
  }
  const int balls = BallsInState(from);
  if (balls != BallsInState(to)) {
    return absl::InvalidArgumentError(absl::StrCat(
        "no transition between ", balls, " and ", BallsInState(to),
        " balls: both patterns must juggle the same number of balls"));
  }
  // Layered breadth-first search, keeping at depth d only the states s with
  // d + TransitionLowerBound(s) <= limit. The bound is admissible, so the first limit at which
  // `to` is reached is the shortest length; raise it until then (in practice the first limit
  // always succeeds: see the width-8 test). Any state of `width` with the same ball count is
  // reachable well within max_limit throws.
  const int max_limit = 4 * width + 8;
  for (int limit = TransitionLowerBound(from, to); limit <= max_limit; ++limit) {
    std::vector<std::vector<JugglingState>> layers = {{from}};
    size_t visited = 1;
    for (int d = 0; d < limit; ++d) {
      std::set<JugglingState> next;
      for (JugglingState s : layers[d]) {
        for (int t = 0; t <= width; ++t) {
          JugglingState n = 0;
          if (!TryThrow(s, t, &n) || (n & outside) != 0) continue;
          if (d + 1 + TransitionLowerBound(n, to) <= limit) next.insert(n);
        }
      }
      visited += next.size();
      if (visited > kMaxTransitionStates) {
        return absl::ResourceExhaustedError(absl::StrCat(
            "transition search between ", FormatJugglingState(from, width), " and ",
            FormatJugglingState(to, width), " visited more than ", kMaxTransitionStates,
            " states"));
      }
      layers.emplace_back(next.begin(), next.end());
    }
    if (!std::binary_search(layers[limit].begin(), layers[limit].end(), to)) continue;
    // good[d]: states of layer d from which `to` is reached in limit - d throws.
    std::vector<std::set<JugglingState>> good(limit + 1);
    good[limit] = {to};
    for (int d = limit - 1; d >= 0; --d) {
      for (JugglingState s : layers[d]) {
        for (int t = 0; t <= width; ++t) {
          JugglingState n = 0;
          if (TryThrow(s, t, &n) && good[d + 1].count(n)) {
            good[d].insert(s);
            break;
          }
        }
      }
    }
    // Forward, always the smallest throw that stays on a shortest path.
    SiteswapTransition result;
    result.width = width;
    result.balls = balls;
    result.path.push_back(from);
    JugglingState s = from;
    for (int d = 0; d < limit; ++d) {
      for (int t = 0; t <= width; ++t) {
        JugglingState n = 0;
        if (TryThrow(s, t, &n) && good[d + 1].count(n)) {
          result.throws.push_back(t);
          result.path.push_back(n);
          s = n;
          break;
        }
      }
    }
    return result;
  }
  return absl::InternalError(absl::StrCat("no transition from ", FormatJugglingState(from, width),
                                          " to ", FormatJugglingState(to, width), " within ",
                                          max_limit, " throws"));
}

absl::StatusOr<SiteswapTransition> FindTransition(const Siteswap& from, const Siteswap& to) {
  if (from.balls() != to.balls()) {
    return absl::InvalidArgumentError(absl::StrCat(
        "no transition from ", from.ToString(), " (", from.balls(), " balls) to ",
        to.ToString(), " (", to.balls(), " balls): both must juggle the same number of balls"));
  }
  return FindTransition(from.state(), to.state(), std::max(from.state_width(), to.state_width()));
}

namespace {

// Whether `throws` is its own largest rotation and no repetition of a shorter sequence.
bool IsCanonicalPrimitive(const std::vector<int>& throws) {
  const int p = static_cast<int>(throws.size());
  for (int k = 1; k < p; ++k) {
    int i = 0;
    while (i < p && throws[(k + i) % p] == throws[i]) ++i;
    if (i == p) return false;  // equals a rotation: a repetition
    if (throws[(k + i) % p] > throws[i]) return false;  // a larger rotation exists
  }
  return true;
}

// Depth-first search over throw sequences: position i takes a throw t <= throws[0] (the
// canonical rotation starts with its highest throw) whose landing beat (i + t) mod p is free,
// while the remaining positions can still reach the required sum. Keeps the canonical,
// primitive ones; stops after max_patterns + 1 of them.
void EnumerateRecursive(const EnumerateOptions& o, int i, int remaining_sum,
                        std::vector<int>* throws, std::vector<bool>* taken,
                        std::vector<std::vector<int>>* out) {
  const int p = o.period;
  if (static_cast<int>(out->size()) > o.max_patterns) return;
  if (i == p) {
    if (remaining_sum == 0 && IsCanonicalPrimitive(*throws)) out->push_back(*throws);
    return;
  }
  const int cap = i == 0 ? o.max_throw : (*throws)[0];
  const int positions_after = p - i - 1;
  for (int t = std::min(cap, remaining_sum); t >= 0; --t) {
    // Later throws are at most throws[0] (= t at position 0). Smaller t only makes it worse.
    if (remaining_sum - t > positions_after * (i == 0 ? t : cap)) break;
    const int beat = (i + t) % p;
    if ((*taken)[beat]) continue;
    (*taken)[beat] = true;
    (*throws)[i] = t;
    EnumerateRecursive(o, i + 1, remaining_sum - t, throws, taken, out);
    (*taken)[beat] = false;
  }
}

}  // namespace

absl::StatusOr<std::vector<Siteswap>> EnumerateSiteswaps(const EnumerateOptions& options) {
  if (options.balls < 0 || options.balls > kMaxSiteswapThrow) {
    return absl::InvalidArgumentError(
        absl::StrCat("balls ", options.balls, " is outside 0..", kMaxSiteswapThrow));
  }
  if (options.max_throw < 0 || options.max_throw > kMaxSiteswapThrow) {
    return absl::InvalidArgumentError(
        absl::StrCat("max_throw ", options.max_throw, " is outside 0..", kMaxSiteswapThrow));
  }
  if (options.period < 1 || options.period > kMaxEnumeratePeriod) {
    return absl::InvalidArgumentError(
        absl::StrCat("period ", options.period, " is outside 1..", kMaxEnumeratePeriod));
  }
  if (options.max_patterns < 1) {
    return absl::InvalidArgumentError("max_patterns must be positive");
  }
  std::vector<int> throws(options.period, 0);
  std::vector<bool> taken(options.period, false);
  std::vector<std::vector<int>> candidates;
  EnumerateRecursive(options, 0, options.balls * options.period, &throws, &taken, &candidates);
  std::vector<Siteswap> out;
  for (std::vector<int>& c : candidates) {
    absl::StatusOr<Siteswap> s = Siteswap::FromThrows(std::move(c));
    if (!s.ok()) return s.status();  // the search only builds valid sequences
    out.push_back(*std::move(s));
  }
  if (static_cast<int>(out.size()) > options.max_patterns) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "more than ", options.max_patterns, " patterns with ", options.balls,
        " balls, max throw ", options.max_throw, " and period ", options.period));
  }
  std::sort(out.begin(), out.end(),
            [](const Siteswap& a, const Siteswap& b) { return a.throws() > b.throws(); });
  return out;
}

absl::Status ThrowPhysicsParams::Validate() const {
  if (!std::isfinite(hand_period_s) || hand_period_s <= 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("hand period must be a positive number of seconds, got ", hand_period_s));
  }
  if (!std::isfinite(dwell_ratio) || dwell_ratio <= 0 || dwell_ratio >= 1) {
    return absl::InvalidArgumentError(
        absl::StrCat("dwell ratio must be in (0, 1), got ", dwell_ratio));
  }
  if (!std::isfinite(hand_separation_m) || hand_separation_m < 0) {
    return absl::InvalidArgumentError(
        absl::StrCat("hand separation must be >= 0 m, got ", hand_separation_m));
  }
  if (!std::isfinite(gravity) || gravity <= 0) {
    return absl::InvalidArgumentError(absl::StrCat("gravity must be positive, got ", gravity));
  }
  return absl::OkStatus();
}

const char* HandName(Hand hand) { return hand == Hand::kRight ? "R" : "L"; }

const char* ThrowKindName(ThrowKind kind) {
  switch (kind) {
    case ThrowKind::kEmpty:
      return "empty";
    case ThrowKind::kHandoff:
      return "handoff";
    case ThrowKind::kToss:
      return "toss";
  }
  return "unknown";
}

double FlightTimeEq1(int value, const ThrowPhysicsParams& params) {
  return params.hand_period_s * (0.5 * value - params.dwell_ratio);
}

ThrowTiming ComputeThrowTiming(int value, int beat, const ThrowPhysicsParams& params) {
  ThrowTiming t;
  t.beat = beat;
  t.value = value;
  t.hand = beat % 2 == 0 ? Hand::kRight : Hand::kLeft;
  t.catch_hand = (beat + value) % 2 == 0 ? Hand::kRight : Hand::kLeft;
  const double beat_s = 0.5 * params.hand_period_s;
  t.throw_time_s = beat * beat_s;
  t.next_throw_time_s = (beat + value) * beat_s;
  const double flight = FlightTimeEq1(value, params);
  if (value == 0) {
    t.kind = ThrowKind::kEmpty;
  } else if (flight <= 0) {
    t.kind = ThrowKind::kHandoff;
  } else {
    t.kind = ThrowKind::kToss;
    t.flight_time_s = flight;
    t.v_z = params.gravity * flight / 2;  // Eq. 2
    if (value % 2 == 1) {                 // Eq. 3: odd throws cross
      const double v = params.hand_separation_m / flight;
      t.v_x = t.hand == Hand::kRight ? v : -v;
    }
    t.apex_height_m = params.gravity * flight * flight / 8;
  }
  t.catch_time_s = t.throw_time_s + t.flight_time_s;
  return t;
}

absl::StatusOr<std::vector<ThrowTiming>> ComputeSchedule(const Siteswap& pattern,
                                                         const ThrowPhysicsParams& params,
                                                         int num_beats) {
  if (absl::Status s = params.Validate(); !s.ok()) return s;
  if (num_beats < 0) {
    return absl::InvalidArgumentError(absl::StrCat("num_beats must be >= 0, got ", num_beats));
  }
  if (num_beats == 0) num_beats = pattern.period() % 2 == 0 ? pattern.period() : 2 * pattern.period();
  std::vector<ThrowTiming> out;
  out.reserve(num_beats);
  for (int beat = 0; beat < num_beats; ++beat) {
    const int position = beat % pattern.period();
    ThrowTiming t = ComputeThrowTiming(pattern.throws()[position], beat, params);
    t.position = position;
    out.push_back(t);
  }
  return out;
}

}  // namespace juggle::toss
