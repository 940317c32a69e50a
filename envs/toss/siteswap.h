// Vanilla siteswaps (asynchronous, one ball caught and thrown per beat, solo): parsing,
// validation, ball count, juggling states, transitions between patterns, enumeration, and the
// physical throw schedule of toss juggling (Chemin & Lee, MIG 2018, Eq. 1-3; docs/siteswap.md).
// docs/siteswap.md has the notation, worked examples and the CLI (`juggle siteswap`).
//
// Notation. A siteswap is a cyclic sequence of throw values t_0 .. t_{p-1} (period p), one
// throw per beat; the throw made at beat i is thrown again at beat i + t_i. Values 0-9 are
// digits, 10-35 the letters a-z (case-insensitive on input, lower case on output). Throw 0 is
// an empty hand. Beats alternate hands: beat i is thrown by hand i mod 2, the right hand on
// even beats (paper Fig. 2), so odd throws cross to the other hand and even throws come back
// to the same hand.
//
// Validity: the landing beats (i + t_i) mod p must be a permutation of 0..p-1 (no two balls
// land on one beat). Then sum t_i is a multiple of p and the number of balls is the mean throw.
//
// State: bit k (k = 0, 1, ...) is set when a ball lands k beats from now, i.e. when the throw
// at the current beat + k has a ball to throw. Written with 'x' for a ball and '-' for none,
// lowest beat first, over the pattern's maximum throw: 531 starts in "xxx--". The ground
// state of b balls is b x's ("xxx"); a pattern is a ground-state pattern when one of its
// rotations starts in the ground state (441 and 531 are; 51 is excited). A throw t from state
// s (bit 0 set) gives (s >> 1) | (1 << (t - 1)); with bit 0 clear only t = 0 is possible.
//
// Physical schedule (paper §2.1-2.2, Eq. 1-3; the paper's equations are garbled in the copy
// this project worked from, so these are re-derived here; docs/siteswap.md):
//   hand period P_hand: time between two throws of one hand (paper Table 1: 0.5 s), so one
//     beat lasts P_hand / 2 and the throw at beat i happens at time i * P_hand / 2;
//   dwell ratio D_ratio: fraction of P_hand a hand holds its ball (Table 1: 0.7), dwell time
//     D_ratio * P_hand;
//   Eq. 1  T_air(t) = P_hand * (t / 2 - D_ratio)   for t >= 2.
//     Derivation: a ball thrown at beat i is thrown again at beat i + t, t * P_hand / 2
//     later; it spends the dwell time D_ratio * P_hand of that interval in the catching hand,
//     the rest in the air.
//   Eq. 2  v_z = g * T_air / 2   (g = 9.81 m/s^2): release and catch at the same height, so the
//     ball rises for T_air / 2; its apex is g * T_air^2 / 8 above the release point.
//   Eq. 3  v_x = D_catch,throw / T_air, with D_catch,throw the horizontal distance between the
//     throw and the catch point. With one throw point per hand, D = the hand separation for
//     odd (crossing) throws and 0 for even throws. The paper gives no separation; the default
//     is 0.4 m (assumed, about shoulder width). Frame: x points from the right hand to the
//     left hand, so a crossing throw from the right hand has v_x > 0.
//   Throw 0 is no throw. For t = 1 (and any t with t / 2 <= D_ratio) Eq. 1 gives no positive
//     flight time: the paper restricts it to t >= 2. Such a throw is reported as a hand-to-hand
//     handoff with zero flight time and zero velocity (kind kHandoff).
//
// Thread-safety: everything here is a pure function or an immutable value; safe from any
// thread.
#ifndef JUGGLE_ENVS_TOSS_SITESWAP_H_
#define JUGGLE_ENVS_TOSS_SITESWAP_H_

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace juggle::toss {

// Highest throw value of the notation ('z').
inline constexpr int kMaxSiteswapThrow = 35;
// Longest siteswap accepted by the parser.
inline constexpr int kMaxSiteswapLength = 1024;

// '0'-'9' for 0-9, 'a'-'z' for 10-35. REQUIRES: 0 <= value <= kMaxSiteswapThrow.
char SiteswapThrowChar(int value);
// The throws as notation, e.g. {11, 9, 7} -> "b97". REQUIRES: every value in [0, 35].
std::string FormatSiteswap(const std::vector<int>& throws);

// Parses the characters of a vanilla siteswap into throw values without checking validity.
// INVALID_ARGUMENT for empty input, input longer than kMaxSiteswapLength, or a character other
// than 0-9, a-z, A-Z (the message names the character and its 0-based position).
absl::StatusOr<std::vector<int>> ParseSiteswapThrows(std::string_view text);

// Two or more throws that land on the same beat (mod period).
struct LandingCollision {
  int beat = 0;                // landing beat mod period
  std::vector<int> positions;  // positions of the colliding throws, ascending
};

// The outcome of the validity test of a throw sequence.
struct SiteswapCheck {
  bool valid = false;
  int period = 0;
  int sum = 0;
  bool integer_average = false;  // sum % period == 0
  std::vector<LandingCollision> collisions;  // by ascending beat; empty when valid
  // Why the sequence is not a siteswap, e.g. "throws at positions 0 ('5'), 1 ('4') and 2 ('3')
  // all land on beat 2 (mod 3)"; empty when valid.
  std::string reason;
};
// REQUIRES: throws non-empty, every value in [0, kMaxSiteswapThrow].
SiteswapCheck CheckSiteswap(const std::vector<int>& throws);

// Juggling states as bit masks (bit k: a ball lands k beats from now). Widths are at most
// kMaxSiteswapThrow + 1 bits.
using JugglingState = uint64_t;

// b balls landing on the next b beats: "xxx" for 3. REQUIRES: 0 <= balls < 64.
JugglingState GroundState(int balls);
// 'x'/'-' string of the lowest `width` bits, lowest first; "-" when width is 0.
std::string FormatJugglingState(JugglingState state, int width);
// Number of balls in the state.
int BallsInState(JugglingState state);
// One step of the state machine: throw `value` from `state`. INVALID_ARGUMENT when the throw
// is impossible: 0 while a ball lands now, > 0 with no ball, onto a beat already taken, or a
// value outside [0, kMaxSiteswapThrow].
absl::StatusOr<JugglingState> ApplyThrow(JugglingState state, int value);

// A valid vanilla siteswap. Immutable value type.
class Siteswap {
 public:
  // Parses and validates. INVALID_ARGUMENT with the parse error or, for an invalid sequence,
  // `siteswap "543" is invalid: <SiteswapCheck::reason>`.
  static absl::StatusOr<Siteswap> Parse(std::string_view text);
  // Validates a throw sequence (values in [0, 35], non-empty). INVALID_ARGUMENT as Parse.
  static absl::StatusOr<Siteswap> FromThrows(std::vector<int> throws);

  const std::vector<int>& throws() const { return throws_; }
  int period() const { return static_cast<int>(throws_.size()); }
  int balls() const { return balls_; }
  int max_throw() const { return max_throw_; }
  // Lower-case notation, e.g. "b97531".
  std::string ToString() const { return FormatSiteswap(throws_); }

  // Width of the state strings: max(max_throw(), 1).
  int state_width() const { return max_throw_ > 0 ? max_throw_ : 1; }
  // The state before throw 0 (after any number of whole periods).
  JugglingState state() const { return states_[0]; }
  // The state before each throw: states()[i] precedes throws()[i]; period() entries.
  const std::vector<JugglingState>& states() const { return states_; }
  std::string StateString() const { return FormatJugglingState(state(), state_width()); }
  // Whether the pattern as written starts in the ground state.
  bool StartsInGroundState() const { return state() == GroundState(balls_); }
  // The first rotation (0..period-1) that starts in the ground state, or -1 for an
  // excited-state pattern (one that never passes through the ground state).
  int GroundRotation() const;
  bool IsGroundStatePattern() const { return GroundRotation() >= 0; }
  // The pattern started at throw k: Rotated(1) of 531 is 315. REQUIRES: 0 <= k < period().
  Siteswap Rotated(int k) const;
  // Whether the pattern is a repetition of a shorter one (333, 5151).
  bool IsRepetition() const;
  // The rotation that is largest lexicographically by throw value (highest throw first):
  // 531 for 153 and 315. Enumeration lists patterns in this form.
  Siteswap CanonicalRotation() const;

  bool operator==(const Siteswap& o) const { return throws_ == o.throws_; }
  bool operator!=(const Siteswap& o) const { return throws_ != o.throws_; }

 private:
  Siteswap() = default;
  std::vector<int> throws_;
  int balls_ = 0;
  int max_throw_ = 0;
  std::vector<JugglingState> states_;
};

// A shortest throw sequence from one juggling state to another.
struct SiteswapTransition {
  std::vector<int> throws;          // empty when the states are equal
  std::vector<JugglingState> path;  // throws.size() + 1 states, from `from` to `to`
  int width = 0;                    // state width searched (the larger pattern's state width)
  int balls = 0;
};

// The shortest transition from `from` to `to` (same ball count), found by a search over the
// state graph of the given width: breadth-first in layers, pruned by the admissible bound
// "the balls of s still in the air after r beats must land where `to` has balls", and among
// the shortest, the lexicographically smallest throw sequence. Throws never exceed `width`.
// INVALID_ARGUMENT for different ball counts or states wider than `width` (1..35);
// RESOURCE_EXHAUSTED if the search visits more than 2^20 states (wide, many-ball states).
absl::StatusOr<SiteswapTransition> FindTransition(JugglingState from, JugglingState to,
                                                  int width);
// From the state `from` starts in (after whole periods of it) to the state `to` starts in, as
// written: rotate `to` to enter it elsewhere. INVALID_ARGUMENT for different ball counts.
absl::StatusOr<SiteswapTransition> FindTransition(const Siteswap& from, const Siteswap& to);

struct EnumerateOptions {
  int balls = 3;      // 0..35
  int max_throw = 5;  // 0..35
  int period = 3;     // exact period (patterns that repeat a shorter one are left out), 1..16
  int max_patterns = 100000;  // RESOURCE_EXHAUSTED beyond this
};
// Every valid siteswap with exactly `balls` balls, throws <= max_throw and period `period`,
// each once in its canonical rotation (Siteswap::CanonicalRotation), repetitions of shorter
// patterns left out; sorted descending (531 before 522). INVALID_ARGUMENT for options out of
// range.
absl::StatusOr<std::vector<Siteswap>> EnumerateSiteswaps(const EnumerateOptions& options);

// Timing parameters of the physical schedule (see the header comment for the formulas).
struct ThrowPhysicsParams {
  double hand_period_s = 0.5;      // P_hand, paper Table 1
  double dwell_ratio = 0.7;        // D_ratio, paper Table 1
  double hand_separation_m = 0.4;  // assumed: the paper gives none
  double gravity = 9.81;           // m/s^2, paper Table 1
  // INVALID_ARGUMENT unless hand_period_s > 0, 0 < dwell_ratio < 1, hand_separation_m >= 0 and
  // gravity > 0, all finite.
  absl::Status Validate() const;
};

enum class Hand { kRight = 0, kLeft = 1 };
// "R" or "L".
const char* HandName(Hand hand);

enum class ThrowKind {
  kEmpty,    // throw 0: the hand is empty on this beat
  kHandoff,  // Eq. 1 gives no positive flight time (t = 1 at D_ratio >= 0.5): passed over
  kToss,     // a ballistic throw
};
// "empty", "handoff" or "toss".
const char* ThrowKindName(ThrowKind kind);

// One throw of the schedule. Times in s from the first throw, velocities in m/s, lengths in m.
struct ThrowTiming {
  int beat = 0;      // beat index from 0
  int position = 0;  // index into the pattern: beat % period
  int value = 0;     // throw value t
  ThrowKind kind = ThrowKind::kEmpty;
  Hand hand = Hand::kRight;        // throwing hand: beat % 2 (right on even beats)
  Hand catch_hand = Hand::kRight;  // (beat + t) % 2
  double throw_time_s = 0;   // beat * P_hand / 2
  double flight_time_s = 0;  // Eq. 1 (0 for empty and handoff)
  double catch_time_s = 0;   // throw_time_s + flight_time_s
  double next_throw_time_s = 0;  // (beat + t) * P_hand / 2: when the ball is thrown again
  double v_z = 0;            // Eq. 2, upwards
  double v_x = 0;            // Eq. 3, signed: + from the right hand towards the left
  double apex_height_m = 0;  // above the release point: g * T_air^2 / 8
};

// Eq. 1 as written: P_hand * (t / 2 - D_ratio); may be <= 0 for small t.
double FlightTimeEq1(int value, const ThrowPhysicsParams& params);
// The timing of throw `value` made at `beat` (position is left 0).
// REQUIRES: params.Validate() ok, beat >= 0, 0 <= value <= kMaxSiteswapThrow.
ThrowTiming ComputeThrowTiming(int value, int beat, const ThrowPhysicsParams& params);
// The schedule of the first `num_beats` beats of the pattern; num_beats = 0 means one full
// cycle of both hands: period() beats for even periods, 2 * period() for odd ones (so each
// throw is shown from both hands). INVALID_ARGUMENT for bad params or num_beats < 0.
absl::StatusOr<std::vector<ThrowTiming>> ComputeSchedule(const Siteswap& pattern,
                                                         const ThrowPhysicsParams& params,
                                                         int num_beats = 0);

}  // namespace juggle::toss

#endif  // JUGGLE_ENVS_TOSS_SITESWAP_H_
