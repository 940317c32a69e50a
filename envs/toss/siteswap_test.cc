// Vanilla siteswaps: parsing, validity with the exact collision, ball count, states and
// ground/excited, transitions (checked by an independent state machine and an exhaustive
// search), enumeration (checked by brute force and by the Buhler-Eisenbud-Graham-Wright count),
// and the physical schedule of Chemin & Lee's Eq. 1-3 (docs/siteswap.md) against hand-computed numbers.
#include "envs/toss/siteswap.h"

#include <cmath>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle::toss {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;

// ---------------------------------------------------------------------------------------------
// Independent reference implementations (no code shared with siteswap.cc).

// A state as a vector of booleans, lowest beat first.
using RefState = std::vector<bool>;

// Throws `t` from `s`; false when impossible. Width grows as needed.
bool RefThrow(RefState* s, int t) {
  const bool ball_now = !s->empty() && (*s)[0];
  if (!s->empty()) s->erase(s->begin());
  if (!ball_now) return t == 0;
  if (t == 0) return false;
  if (static_cast<int>(s->size()) < t) s->resize(t, false);
  if ((*s)[t - 1]) return false;
  (*s)[t - 1] = true;
  return true;
}

RefState RefFromString(const std::string& x) {
  RefState s;
  for (char c : x) s.push_back(c == 'x');
  return s;
}

bool RefEqual(RefState a, RefState b) {
  const size_t n = std::max(a.size(), b.size());
  a.resize(n, false);
  b.resize(n, false);
  return a == b;
}

// The state before throw 0 of a periodic pattern, by juggling it from the ground state for
// many periods first: after enough periods any valid pattern has settled into its cycle only if
// it started there, so instead mark directly which beats k >= 0 receive a ball thrown before 0.
RefState RefPatternState(const std::vector<int>& throws) {
  const int p = static_cast<int>(throws.size());
  int h = 0;
  for (int t : throws) h = std::max(h, t);
  RefState s(h, false);
  for (int j = -1; j >= -10 * (h + p); --j) {
    const int land = j + throws[((j % p) + p) % p];
    if (land >= 0 && land < h) s[land] = true;
  }
  return s;
}

// Validity by the permutation test, written out again.
bool RefValid(const std::vector<int>& throws) {
  const int p = static_cast<int>(throws.size());
  std::vector<int> hits(p, 0);
  for (int i = 0; i < p; ++i) ++hits[(i + throws[i]) % p];
  for (int h : hits) {
    if (h != 1) return false;
  }
  return true;
}

std::vector<int> Throws(const std::string& text) {
  absl::StatusOr<std::vector<int>> t = ParseSiteswapThrows(text);
  EXPECT_TRUE(t.ok()) << t.status();
  return t.ok() ? *t : std::vector<int>{};
}

Siteswap Must(const std::string& text) {
  absl::StatusOr<Siteswap> s = Siteswap::Parse(text);
  if (!s.ok()) {
    ADD_FAILURE() << text << ": " << s.status();
    return *Siteswap::Parse("0");
  }
  return *std::move(s);
}

EnumerateOptions Options(int balls, int max_throw, int period) {
  EnumerateOptions o;
  o.balls = balls;
  o.max_throw = max_throw;
  o.period = period;
  return o;
}

// ---------------------------------------------------------------------------------------------
// Parsing.

TEST(SiteswapParseTest, ReadsDigitsAndLettersCaseInsensitively) {
  EXPECT_THAT(Throws("531"), ElementsAre(5, 3, 1));
  EXPECT_THAT(Throws("b97531"), ElementsAre(11, 9, 7, 5, 3, 1));
  EXPECT_THAT(Throws("B97531"), ElementsAre(11, 9, 7, 5, 3, 1));
  EXPECT_THAT(Throws("azAZ0"), ElementsAre(10, 35, 10, 35, 0));
  EXPECT_EQ(FormatSiteswap({11, 9, 7, 5, 3, 1}), "b97531");
  EXPECT_EQ(FormatSiteswap({10, 35, 0, 9}), "az09");
  EXPECT_EQ(Must("B97531").ToString(), "b97531");
}

TEST(SiteswapParseTest, RejectsEmptyInput) {
  const absl::Status s = ParseSiteswapThrows("").status();
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message(),
            "empty siteswap: expected throw values such as \"531\" (0-9, a-z for 10-35)");
  EXPECT_EQ(Siteswap::Parse("").status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(Siteswap::FromThrows({}).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(SiteswapParseTest, RejectsBadCharacterNamingItAndItsPosition) {
  const absl::Status s = ParseSiteswapThrows("53!1").status();
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message(),
            "siteswap \"53!1\": invalid character '!' at position 2 (expected 0-9, or a-z for "
            "throws 10-35; only vanilla asynchronous siteswaps are supported)");
  EXPECT_THAT(ParseSiteswapThrows("(4,2x)").status().message(),
              HasSubstr("invalid character '(' at position 0"));
  EXPECT_THAT(ParseSiteswapThrows("[33]").status().message(),
              HasSubstr("invalid character '[' at position 0"));
  EXPECT_THAT(ParseSiteswapThrows("5 1").status().message(),
              HasSubstr("invalid character ' ' at position 1"));
  EXPECT_THAT(ParseSiteswapThrows(std::string("3\n", 2)).status().message(),
              HasSubstr("invalid character '\\n' at position 1"));
  EXPECT_THAT(ParseSiteswapThrows(std::string("3\xff", 2)).status().message(),
              HasSubstr("invalid character '\\xff' at position 1"));
}

TEST(SiteswapParseTest, RejectsOverlongInputAndOutOfRangeThrows) {
  EXPECT_THAT(ParseSiteswapThrows(std::string(kMaxSiteswapLength + 1, '3')).status().message(),
              HasSubstr("longer than the limit of 1024"));
  EXPECT_TRUE(Siteswap::Parse(std::string(kMaxSiteswapLength, '3')).ok());
  EXPECT_EQ(Siteswap::FromThrows({3, 36}).status().message(),
            "throw 36 at position 1 is outside 0..35");
  EXPECT_EQ(Siteswap::FromThrows({-1}).status().message(), "throw -1 at position 0 is outside 0..35");
}

// ---------------------------------------------------------------------------------------------
// Validity and ball count.

struct ValidCase {
  const char* text;
  int balls;
  int period;
  int max_throw;
};

TEST(SiteswapValidityTest, AcceptsValidPatternsWithTheirBallCount) {
  const ValidCase cases[] = {
      {"3", 3, 1, 3},       {"441", 3, 3, 4},    {"531", 3, 3, 5},    {"51", 3, 2, 5},
      {"423", 3, 3, 4},     {"55500", 3, 5, 5},  {"7441", 4, 4, 7},   {"b97531", 6, 6, 11},
      {"633", 4, 3, 6},     {"5", 5, 1, 5},      {"6", 6, 1, 6},      {"31", 2, 2, 3},
      {"615", 4, 3, 6},     {"91", 5, 2, 9},     {"0", 0, 1, 0},      {"a", 10, 1, 10},
      {"z1", 18, 2, 35},    {"552", 4, 3, 5},    {"534", 4, 3, 5},    {"144", 3, 3, 4},
  };
  for (const ValidCase& c : cases) {
    SCOPED_TRACE(c.text);
    const SiteswapCheck check = CheckSiteswap(Throws(c.text));
    EXPECT_TRUE(check.valid);
    EXPECT_TRUE(check.integer_average);
    EXPECT_THAT(check.collisions, IsEmpty());
    EXPECT_EQ(check.reason, "");
    absl::StatusOr<Siteswap> s = Siteswap::Parse(c.text);
    ASSERT_TRUE(s.ok()) << s.status();
    EXPECT_EQ(s->balls(), c.balls);
    EXPECT_EQ(s->period(), c.period);
    EXPECT_EQ(s->max_throw(), c.max_throw);
    EXPECT_TRUE(RefValid(s->throws()));
  }
}

struct InvalidCase {
  const char* text;
  std::vector<LandingCollision> collisions;
  bool integer_average;
  const char* reason;
};

TEST(SiteswapValidityTest, RejectsInvalidPatternsNamingTheCollision) {
  const InvalidCase cases[] = {
      {"432", {{1, {0, 1, 2}}}, true,
       "throws at positions 0 ('4'), 1 ('3') and 2 ('2') all land on beat 1 (mod 3)"},
      {"543", {{2, {0, 1, 2}}}, true,
       "throws at positions 0 ('5'), 1 ('4') and 2 ('3') all land on beat 2 (mod 3)"},
      {"321", {{0, {0, 1, 2}}}, true,
       "throws at positions 0 ('3'), 1 ('2') and 2 ('1') all land on beat 0 (mod 3)"},
      {"54", {{1, {0, 1}}}, false,
       "throws at positions 0 ('5') and 1 ('4') both land on beat 1 (mod 2); the throw sum 9 "
       "is not a multiple of the period 2 (average 4.5 is not a whole number of balls)"},
      {"5331", {{0, {1, 3}}, {1, {0, 2}}}, true,
       "throws at positions 1 ('3') and 3 ('1') both land on beat 0 (mod 4); throws at "
       "positions 0 ('5') and 2 ('3') both land on beat 1 (mod 4)"},
      {"ab", {{0, {0, 1}}}, false,
       "throws at positions 0 ('a') and 1 ('b') both land on beat 0 (mod 2); the throw sum 21 "
       "is not a multiple of the period 2 (average 10.5 is not a whole number of balls)"},
      {"631", {{0, {0, 2}}}, false,
       "throws at positions 0 ('6') and 2 ('1') both land on beat 0 (mod 3); the throw sum 10 "
       "is not a multiple of the period 3 (average 3.333 is not a whole number of balls)"},
  };
  for (const InvalidCase& c : cases) {
    SCOPED_TRACE(c.text);
    const SiteswapCheck check = CheckSiteswap(Throws(c.text));
    EXPECT_FALSE(check.valid);
    EXPECT_FALSE(RefValid(Throws(c.text)));
    EXPECT_EQ(check.integer_average, c.integer_average);
    ASSERT_EQ(check.collisions.size(), c.collisions.size());
    for (size_t i = 0; i < c.collisions.size(); ++i) {
      EXPECT_EQ(check.collisions[i].beat, c.collisions[i].beat);
      EXPECT_EQ(check.collisions[i].positions, c.collisions[i].positions);
    }
    EXPECT_EQ(check.reason, c.reason);
    const absl::Status s = Siteswap::Parse(c.text).status();
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
    EXPECT_EQ(s.message(), std::string("siteswap \"") + c.text + "\" is invalid: " + c.reason);
  }
}

TEST(SiteswapValidityTest, PermutationTestAgreesWithTheReferenceOnAllShortSequences) {
  // Every sequence of length 1..4 over 0..6: validity matches, and valid ones have an integer
  // average equal to the ball count.
  int valid = 0;
  for (int p = 1; p <= 4; ++p) {
    std::vector<int> t(p, 0);
    std::function<void(int)> rec = [&](int i) {
      if (i == p) {
        const SiteswapCheck check = CheckSiteswap(t);
        ASSERT_EQ(check.valid, RefValid(t)) << FormatSiteswap(t);
        if (check.valid) {
          ++valid;
          int sum = 0;
          for (int x : t) sum += x;
          ASSERT_EQ(sum % p, 0);
          ASSERT_EQ(Siteswap::FromThrows(t)->balls(), sum / p);
        }
        return;
      }
      for (int v = 0; v <= 6; ++v) {
        t[i] = v;
        rec(i + 1);
      }
    };
    rec(0);
  }
  EXPECT_GT(valid, 100);
}

// ---------------------------------------------------------------------------------------------
// States, ground and excited.

TEST(SiteswapStateTest, StateStringsOfKnownPatterns) {
  // Worked by hand in docs/siteswap.md: bit k is set when a ball thrown before beat 0 lands on
  // beat k.
  EXPECT_EQ(Must("3").StateString(), "xxx");
  EXPECT_EQ(Must("441").StateString(), "xxx-");
  EXPECT_EQ(Must("531").StateString(), "xxx--");
  EXPECT_EQ(Must("423").StateString(), "xxx-");
  EXPECT_EQ(Must("55500").StateString(), "xxx--");
  EXPECT_EQ(Must("7441").StateString(), "xxxx---");
  EXPECT_EQ(Must("b97531").StateString(), "xxxxxx-----");
  EXPECT_EQ(Must("633").StateString(), "xxxx--");
  EXPECT_EQ(Must("51").StateString(), "xx-x-");
  EXPECT_EQ(Must("15").StateString(), "x-x-x");
  EXPECT_EQ(Must("144").StateString(), "x-xx");
  EXPECT_EQ(Must("615").StateString(), "xx-xx-");
  EXPECT_EQ(Must("0").StateString(), "-");
  for (const char* text : {"3", "441", "531", "51", "15", "144", "615", "7441", "b97531", "91",
                           "55500", "552", "a"}) {
    SCOPED_TRACE(text);
    const Siteswap s = Must(text);
    EXPECT_TRUE(RefEqual(RefFromString(s.StateString()), RefPatternState(s.throws())));
    EXPECT_EQ(BallsInState(s.state()), s.balls());
  }
}

TEST(SiteswapStateTest, GroundAndExcitedPatterns) {
  for (const char* text : {"3", "441", "531", "423", "55500", "7441", "b97531", "633", "5", "31"}) {
    SCOPED_TRACE(text);
    const Siteswap s = Must(text);
    EXPECT_TRUE(s.StartsInGroundState());
    EXPECT_EQ(s.GroundRotation(), 0);
    EXPECT_TRUE(s.IsGroundStatePattern());
  }
  // 144 does not start in the ground state but passes through it: rotation 1 is 441.
  const Siteswap r = Must("144");
  EXPECT_FALSE(r.StartsInGroundState());
  EXPECT_EQ(r.GroundRotation(), 1);
  EXPECT_EQ(r.Rotated(1).ToString(), "441");
  EXPECT_TRUE(r.IsGroundStatePattern());
  // Excited: 51 (3 balls; its states are xx-x- and x-x-x, never xxx), 615, 91.
  for (const char* text : {"51", "15", "615", "91"}) {
    SCOPED_TRACE(text);
    const Siteswap s = Must(text);
    EXPECT_FALSE(s.StartsInGroundState());
    EXPECT_EQ(s.GroundRotation(), -1);
    EXPECT_FALSE(s.IsGroundStatePattern());
  }
}

TEST(SiteswapStateTest, StatesFollowTheStateMachineAroundTheCycle) {
  const Siteswap s = Must("51");
  ASSERT_EQ(s.states().size(), 2u);
  EXPECT_EQ(FormatJugglingState(s.states()[0], 5), "xx-x-");
  EXPECT_EQ(FormatJugglingState(s.states()[1], 5), "x-x-x");
  const Siteswap b = Must("b97531");
  for (int i = 0; i < b.period(); ++i) {
    RefState ref = RefFromString(FormatJugglingState(b.states()[i], b.state_width()));
    ASSERT_TRUE(RefThrow(&ref, b.throws()[i]));
    EXPECT_TRUE(RefEqual(ref, RefFromString(FormatJugglingState(
                                  b.states()[(i + 1) % b.period()], b.state_width()))));
  }
}

TEST(SiteswapStateTest, ApplyThrowNamesTheReason) {
  const JugglingState ground3 = GroundState(3);
  EXPECT_EQ(FormatJugglingState(ground3, 5), "xxx--");
  EXPECT_EQ(FormatJugglingState(*ApplyThrow(ground3, 4), 5), "xx-x-");
  EXPECT_EQ(FormatJugglingState(*ApplyThrow(ground3, 3), 5), "xxx--");
  EXPECT_EQ(ApplyThrow(ground3, 2).status().message(),
            "from state xxx a throw of 2 lands on a beat that already has a ball");
  EXPECT_EQ(ApplyThrow(ground3, 0).status().message(),
            "from state xx a ball lands now: a 0 would drop it");
  EXPECT_EQ(ApplyThrow(0b110, 3).status().message(),
            "from state -xx- no ball lands now: only a 0 can be thrown, not 3");
  EXPECT_EQ(*ApplyThrow(0b110, 0), JugglingState{0b11});
  EXPECT_EQ(ApplyThrow(ground3, 36).status().message(), "throw 36 is outside 0..35");
}

TEST(SiteswapStateTest, CanonicalRotationAndRepetition) {
  EXPECT_EQ(Must("153").CanonicalRotation().ToString(), "531");
  EXPECT_EQ(Must("315").CanonicalRotation().ToString(), "531");
  EXPECT_EQ(Must("144").CanonicalRotation().ToString(), "441");
  EXPECT_EQ(Must("05550").CanonicalRotation().ToString(), "55500");
  EXPECT_TRUE(Must("333").IsRepetition());
  EXPECT_TRUE(Must("5151").IsRepetition());
  EXPECT_FALSE(Must("5511").IsRepetition());
  EXPECT_FALSE(Must("3").IsRepetition());
}

// ---------------------------------------------------------------------------------------------
// Transitions.

// Juggles `throws` from `from` with the reference machine; the end state, or nullopt-like
// empty vector with ok=false.
bool RefJuggle(RefState s, const std::vector<int>& throws, RefState* end) {
  for (int t : throws) {
    if (!RefThrow(&s, t)) return false;
  }
  *end = s;
  return true;
}

// The shortest transition length by exhaustive search over all throw sequences (values
// 0..max_value), independent of the library's pruned search.
int RefShortestLength(const RefState& from, const RefState& to, int max_value, int max_len) {
  for (int len = 0; len <= max_len; ++len) {
    std::vector<int> t(len, 0);
    bool found = false;
    std::function<void(int, RefState)> rec = [&](int i, RefState s) {
      if (found) return;
      if (i == len) {
        found = RefEqual(s, to);
        return;
      }
      for (int v = 0; v <= max_value && !found; ++v) {
        RefState n = s;
        if (RefThrow(&n, v)) rec(i + 1, n);
      }
    };
    rec(0, from);
    if (found) return len;
  }
  return -1;
}

TEST(SiteswapTransitionTest, GroundStatePatternsNeedNoTransition) {
  absl::StatusOr<SiteswapTransition> t = FindTransition(Must("3"), Must("441"));
  ASSERT_TRUE(t.ok()) << t.status();
  EXPECT_THAT(t->throws, IsEmpty());
  EXPECT_EQ(t->path.size(), 1u);
  EXPECT_THAT(FindTransition(Must("531"), Must("3"))->throws, IsEmpty());
  EXPECT_THAT(FindTransition(Must("3"), Must("55500"))->throws, IsEmpty());
}

TEST(SiteswapTransitionTest, IntoAndOutOfTheExcitedPattern51) {
  // From the cascade a single 4 enters 51: xxx-- -4-> xx-x-; a 2 leaves it: xx-x- -2-> xxx--.
  absl::StatusOr<SiteswapTransition> in = FindTransition(Must("3"), Must("51"));
  ASSERT_TRUE(in.ok()) << in.status();
  EXPECT_THAT(in->throws, ElementsAre(4));
  EXPECT_EQ(in->width, 5);
  EXPECT_EQ(in->balls, 3);
  ASSERT_EQ(in->path.size(), 2u);
  EXPECT_EQ(FormatJugglingState(in->path[0], 5), "xxx--");
  EXPECT_EQ(FormatJugglingState(in->path[1], 5), "xx-x-");
  EXPECT_THAT(FindTransition(Must("51"), Must("3"))->throws, ElementsAre(2));
  // The transition example of the SiteswapSuite library's documentation: 5 -> 91 is 678.
  EXPECT_THAT(FindTransition(Must("5"), Must("91"))->throws, ElementsAre(6, 7, 8));
  // Entering at the other rotation takes longer.
  EXPECT_THAT(FindTransition(Must("3"), Must("15"))->throws, ElementsAre(4, 5));
}

TEST(SiteswapTransitionTest, TransitionLeadsIntoTheExcitedPatternsState) {
  struct Case {
    const char* from;
    const char* to;
  };
  for (const Case& c : {Case{"4", "615"}, Case{"615", "4"}, Case{"5", "91"}, Case{"91", "5"},
                        Case{"3", "51"}, Case{"441", "15"}, Case{"4", "552"}, Case{"7441", "615"},
                        Case{"b97531", "6"}, Case{"6", "b97531"}, Case{"55500", "51"}}) {
    SCOPED_TRACE(std::string(c.from) + " -> " + c.to);
    const Siteswap a = Must(c.from), b = Must(c.to);
    absl::StatusOr<SiteswapTransition> t = FindTransition(a, b);
    ASSERT_TRUE(t.ok()) << t.status();
    // Juggle a few periods of A, the transition, then a few periods of B: every throw is legal
    // and the transition ends in B's own state.
    RefState s = RefPatternState(a.throws());
    std::vector<int> all;
    for (int k = 0; k < 3; ++k) all.insert(all.end(), a.throws().begin(), a.throws().end());
    RefState after_a;
    ASSERT_TRUE(RefJuggle(s, all, &after_a));
    ASSERT_TRUE(RefEqual(after_a, s));
    RefState after_t;
    ASSERT_TRUE(RefJuggle(after_a, t->throws, &after_t));
    EXPECT_TRUE(RefEqual(after_t, RefPatternState(b.throws())));
    std::vector<int> bs;
    for (int k = 0; k < 3; ++k) bs.insert(bs.end(), b.throws().begin(), b.throws().end());
    RefState after_b;
    ASSERT_TRUE(RefJuggle(after_t, bs, &after_b));
    EXPECT_TRUE(RefEqual(after_b, after_t));
    // Shortest: no shorter sequence exists, even with throws above the state width.
    const int width = std::max(a.state_width(), b.state_width());
    EXPECT_EQ(RefShortestLength(RefPatternState(a.throws()), RefPatternState(b.throws()),
                                std::min(width + 4, 14), static_cast<int>(t->throws.size())),
              static_cast<int>(t->throws.size()));
    for (int v : t->throws) EXPECT_LE(v, width);
  }
}

TEST(SiteswapTransitionTest, ShortestBetweenEveryPairOfSmallStates) {
  // All 3-ball states of width 5 (10 of them) and all 2-ball states of width 4: the library's
  // length equals the exhaustive minimum over throws up to 8, and the path is legal.
  for (int balls : {2, 3}) {
    const int width = balls == 3 ? 5 : 4;
    std::vector<JugglingState> states;
    for (JugglingState s = 0; s < (JugglingState{1} << width); ++s) {
      if (BallsInState(s) == balls) states.push_back(s);
    }
    for (JugglingState from : states) {
      for (JugglingState to : states) {
        absl::StatusOr<SiteswapTransition> t = FindTransition(from, to, width);
        ASSERT_TRUE(t.ok()) << t.status();
        const RefState rf = RefFromString(FormatJugglingState(from, width));
        const RefState rt = RefFromString(FormatJugglingState(to, width));
        RefState end;
        ASSERT_TRUE(RefJuggle(rf, t->throws, &end));
        EXPECT_TRUE(RefEqual(end, rt));
        EXPECT_EQ(static_cast<int>(t->throws.size()),
                  RefShortestLength(rf, rt, 8, static_cast<int>(t->throws.size())))
            << FormatJugglingState(from, width) << " -> " << FormatJugglingState(to, width);
      }
    }
  }
}

TEST(SiteswapTransitionTest, LengthMeetsTheShiftLowerBoundForAllStatesOfWidthEight) {
  // Balls in the air cannot move before they land, so any transition from A to B (with throws
  // of any height) takes at least the smallest r with (A >> r) a subset of B. The search, whose
  // throws never exceed the width, meets that bound for every pair of states of width 8 with
  // the same ball count: its transitions are shortest even among unrestricted ones.
  constexpr int kWidth = 8;
  int pairs = 0;
  for (JugglingState from = 0; from < (1u << kWidth); ++from) {
    for (JugglingState to = 0; to < (1u << kWidth); ++to) {
      if (BallsInState(from) != BallsInState(to)) continue;
      int bound = 0;
      while (((from >> bound) & ~to) != 0) ++bound;
      absl::StatusOr<SiteswapTransition> t = FindTransition(from, to, kWidth);
      ASSERT_TRUE(t.ok()) << t.status();
      ASSERT_EQ(static_cast<int>(t->throws.size()), bound)
          << FormatJugglingState(from, kWidth) << " -> " << FormatJugglingState(to, kWidth);
      ASSERT_EQ(t->path.back(), to);
      ++pairs;
    }
  }
  EXPECT_EQ(pairs, 12870);  // sum over b of C(8, b)^2 = C(16, 8)
}

TEST(SiteswapTransitionTest, RejectsDifferentBallCounts) {
  const absl::Status s = FindTransition(Must("3"), Must("5")).status();
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message(),
            "no transition from 3 (3 balls) to 5 (5 balls): both must juggle the same number of "
            "balls");
  EXPECT_EQ(FindTransition(0b111, 0b1111, 5).status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(FindTransition(0b111, 0b111000, 5).status().message(), "states wider than 5 beats");
  EXPECT_EQ(FindTransition(0b1, 0b1, 0).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST(SiteswapTransitionTest, IsDeterministic) {
  const SiteswapTransition a = *FindTransition(Must("b97531"), Must("6"));
  for (int i = 0; i < 3; ++i) EXPECT_EQ(FindTransition(Must("b97531"), Must("6"))->throws, a.throws);
}

// ---------------------------------------------------------------------------------------------
// Enumeration.

// Canonical, primitive valid sequences by brute force over [0, max_throw]^period.
std::set<std::string> BruteForcePatterns(int balls, int max_throw, int period) {
  std::set<std::string> out;
  std::vector<int> t(period, 0);
  std::function<void(int)> rec = [&](int i) {
    if (i == period) {
      int sum = 0;
      for (int x : t) sum += x;
      if (sum != balls * period || !RefValid(t)) return;
      std::set<std::vector<int>> rotations;
      std::vector<int> best = t;
      for (int k = 0; k < period; ++k) {
        std::vector<int> r(t.begin() + k, t.end());
        r.insert(r.end(), t.begin(), t.begin() + k);
        rotations.insert(r);
        best = std::max(best, r);
      }
      if (static_cast<int>(rotations.size()) == period && best == t) out.insert(FormatSiteswap(t));
      return;
    }
    for (int v = 0; v <= max_throw; ++v) {
      t[i] = v;
      rec(i + 1);
    }
  };
  rec(0);
  return out;
}

std::vector<std::string> Enumerate(int balls, int max_throw, int period) {
  absl::StatusOr<std::vector<Siteswap>> r = EnumerateSiteswaps(Options(balls, max_throw, period));
  EXPECT_TRUE(r.ok()) << r.status();
  std::vector<std::string> out;
  if (r.ok()) {
    for (const Siteswap& s : *r) out.push_back(s.ToString());
  }
  return out;
}

TEST(SiteswapEnumerateTest, ThreeBallPatternsUpToPeriodThreeWithMaxThrowFive) {
  EXPECT_THAT(Enumerate(3, 5, 1), ElementsAre("3"));
  EXPECT_THAT(Enumerate(3, 5, 2), ElementsAre("51", "42"));
  EXPECT_THAT(Enumerate(3, 5, 3), ElementsAre("531", "522", "504", "441", "423"));
  // 8 patterns of period <= 3.
  int total = 0;
  for (int p = 1; p <= 3; ++p) total += static_cast<int>(Enumerate(3, 5, p).size());
  EXPECT_EQ(total, 8);
}

TEST(SiteswapEnumerateTest, MatchesBruteForce) {
  for (int balls = 0; balls <= 4; ++balls) {
    for (int max_throw = 0; max_throw <= 7; ++max_throw) {
      for (int period = 1; period <= 5; ++period) {
        if (period == 5 && max_throw > 6) continue;  // keep the brute force small
        const std::vector<std::string> got = Enumerate(balls, max_throw, period);
        const std::set<std::string> want = BruteForcePatterns(balls, max_throw, period);
        EXPECT_EQ(std::set<std::string>(got.begin(), got.end()), want)
            << balls << " balls, max " << max_throw << ", period " << period;
        EXPECT_EQ(got.size(), want.size());  // no duplicates
        EXPECT_TRUE(std::is_sorted(got.rbegin(), got.rend()));
      }
    }
  }
}

TEST(SiteswapEnumerateTest, CountsMatchTheBuhlerEisenbudGrahamWrightFormula) {
  // The number of juggling sequences of length n with exactly b balls (all rotations and
  // repetitions counted) is (b+1)^n - b^n. Each canonical primitive pattern of period d | n
  // accounts for d of them.
  for (int b = 1; b <= 3; ++b) {
    for (int n = 1; n <= 4; ++n) {
      int64_t count = 0;
      for (int d = 1; d <= n; ++d) {
        if (n % d == 0) count += int64_t{d} * static_cast<int64_t>(Enumerate(b, b * n, d).size());
      }
      EXPECT_EQ(count, static_cast<int64_t>(std::pow(b + 1, n) - std::pow(b, n)))
          << b << " balls, period " << n;
    }
  }
}

TEST(SiteswapEnumerateTest, RejectsOptionsOutOfRangeAndCapsTheOutput) {
  EXPECT_EQ(EnumerateSiteswaps(Options(3, 5, 0)).status().message(), "period 0 is outside 1..16");
  EXPECT_EQ(EnumerateSiteswaps(Options(3, 5, 17)).status().message(), "period 17 is outside 1..16");
  EXPECT_EQ(EnumerateSiteswaps(Options(-1, 5, 3)).status().message(), "balls -1 is outside 0..35");
  EXPECT_EQ(EnumerateSiteswaps(Options(3, 36, 3)).status().message(), "max_throw 36 is outside 0..35");
  EnumerateOptions o = Options(3, 9, 5);
  o.max_patterns = 10;
  EXPECT_EQ(EnumerateSiteswaps(o).status().code(), absl::StatusCode::kResourceExhausted);
  // More balls than the max throw allows: nothing, not an error.
  EXPECT_THAT(Enumerate(6, 5, 3), IsEmpty());
}

// ---------------------------------------------------------------------------------------------
// Physical schedule (Eq. 1-3).

TEST(SiteswapPhysicsTest, FlightTimesAndVelocitiesAtThePapersDefaults) {
  // P_hand = 0.5 s, D_ratio = 0.7, g = 9.81, separation 0.4 m. By hand:
  //   T_air = 0.5 * (t/2 - 0.7): t=2 0.15, 3 0.40, 4 0.65, 5 0.90, 7 1.40 s
  //   v_z = 9.81 * T / 2: 0.73575, 1.962, 3.18825, 4.4145, 6.867 m/s
  //   apex = 9.81 * T^2 / 8: 0.0275906, 0.1962, 0.5180906, 0.9932625, 2.40345 m
  //   v_x (odd) = 0.4 / T: t=3 1.0, t=5 0.444444, t=7 0.285714 m/s
  const ThrowPhysicsParams p;
  struct Row {
    int t;
    double flight, vz, vx, apex;
  };
  for (const Row& r : {Row{2, 0.15, 0.73575, 0, 0.0275906}, Row{3, 0.40, 1.962, 1.0, 0.1962},
                       Row{4, 0.65, 3.18825, 0, 0.5180906}, Row{5, 0.90, 4.4145, 0.4444444, 0.9932625},
                       Row{7, 1.40, 6.867, 0.2857143, 2.40345}}) {
    SCOPED_TRACE(r.t);
    const ThrowTiming right = ComputeThrowTiming(r.t, 0, p);
    EXPECT_EQ(right.kind, ThrowKind::kToss);
    EXPECT_NEAR(FlightTimeEq1(r.t, p), r.flight, 1e-12);
    EXPECT_NEAR(right.flight_time_s, r.flight, 1e-12);
    EXPECT_NEAR(right.v_z, r.vz, 1e-9);
    EXPECT_NEAR(right.v_x, r.vx, 1e-6);
    EXPECT_NEAR(right.apex_height_m, r.apex, 1e-6);
    // From the left hand a crossing throw flies the other way.
    const ThrowTiming left = ComputeThrowTiming(r.t, 1, p);
    EXPECT_EQ(left.hand, Hand::kLeft);
    EXPECT_NEAR(left.v_x, -r.vx, 1e-6);
    EXPECT_NEAR(left.v_z, r.vz, 1e-12);
    // The catching hand holds the ball for the dwell time D_ratio * P_hand before rethrowing.
    EXPECT_NEAR(right.next_throw_time_s - right.catch_time_s, 0.35, 1e-12);
    // Ballistics: the ball is back at release height after T_air.
    EXPECT_NEAR(right.v_z * right.flight_time_s - 0.5 * 9.81 * std::pow(right.flight_time_s, 2),
                0, 1e-12);
  }
}

TEST(SiteswapPhysicsTest, ScheduleOf531AlternatesHands) {
  const Siteswap s = Must("531");
  absl::StatusOr<std::vector<ThrowTiming>> sched = ComputeSchedule(s, ThrowPhysicsParams());
  ASSERT_TRUE(sched.ok()) << sched.status();
  ASSERT_EQ(sched->size(), 6u);  // odd period: both hands throw each value once
  const int values[] = {5, 3, 1, 5, 3, 1};
  for (int i = 0; i < 6; ++i) {
    SCOPED_TRACE(i);
    const ThrowTiming& t = (*sched)[i];
    EXPECT_EQ(t.beat, i);
    EXPECT_EQ(t.position, i % 3);
    EXPECT_EQ(t.value, values[i]);
    EXPECT_EQ(t.hand, i % 2 == 0 ? Hand::kRight : Hand::kLeft);
    EXPECT_NE(t.catch_hand, t.hand);  // all odd: every throw crosses
    EXPECT_NEAR(t.throw_time_s, 0.25 * i, 1e-12);
  }
  // Beat 0: right hand throws the 5, caught by the left at 0.9 s, rethrown at beat 5 (1.25 s).
  EXPECT_NEAR((*sched)[0].catch_time_s, 0.9, 1e-12);
  EXPECT_NEAR((*sched)[0].next_throw_time_s, 1.25, 1e-12);
  EXPECT_NEAR((*sched)[0].v_x, 0.4 / 0.9, 1e-12);
  // Beat 1: left hand's 3 to the right: v_x = -0.4 / 0.4.
  EXPECT_NEAR((*sched)[1].v_x, -1.0, 1e-12);
  // Beat 2: a 1 at D_ratio 0.7 has no flight time (0.5 * (0.5 - 0.7) < 0): a handoff.
  EXPECT_EQ((*sched)[2].kind, ThrowKind::kHandoff);
  EXPECT_EQ((*sched)[2].flight_time_s, 0);
  EXPECT_EQ((*sched)[2].v_z, 0);
  EXPECT_EQ((*sched)[2].catch_hand, Hand::kLeft);
  EXPECT_NEAR(FlightTimeEq1(1, ThrowPhysicsParams()), -0.1, 1e-12);
  // Even period: one period is a full cycle of both hands; 4s return to the same hand.
  absl::StatusOr<std::vector<ThrowTiming>> s441 = ComputeSchedule(Must("441"), {});
  ASSERT_EQ(s441->size(), 6u);
  EXPECT_EQ((*s441)[0].catch_hand, Hand::kRight);
  EXPECT_EQ((*s441)[0].v_x, 0);
  EXPECT_EQ(ComputeSchedule(Must("51"), {})->size(), 2u);
  EXPECT_EQ(ComputeSchedule(Must("51"), {}, 7)->size(), 7u);
}

TEST(SiteswapPhysicsTest, CustomParametersAndEmptyHands) {
  ThrowPhysicsParams p;
  p.hand_period_s = 0.4;
  p.dwell_ratio = 0.4;
  p.hand_separation_m = 0.3;
  // t=3: 0.4 * (1.5 - 0.4) = 0.44 s; v_z = 9.81 * 0.22 = 2.1582; v_x = 0.3 / 0.44.
  const ThrowTiming t3 = ComputeThrowTiming(3, 2, p);
  EXPECT_NEAR(t3.flight_time_s, 0.44, 1e-12);
  EXPECT_NEAR(t3.v_z, 2.1582, 1e-12);
  EXPECT_NEAR(t3.v_x, 0.3 / 0.44, 1e-12);
  EXPECT_NEAR(t3.throw_time_s, 0.4, 1e-12);
  // With a dwell ratio below 0.5 a 1 is a short toss: 0.4 * (0.5 - 0.4) = 0.04 s.
  const ThrowTiming t1 = ComputeThrowTiming(1, 0, p);
  EXPECT_EQ(t1.kind, ThrowKind::kToss);
  EXPECT_NEAR(t1.flight_time_s, 0.04, 1e-12);
  EXPECT_NEAR(t1.v_x, 0.3 / 0.04, 1e-9);
  // A 0 is an empty hand.
  const ThrowTiming t0 = ComputeThrowTiming(0, 3, p);
  EXPECT_EQ(t0.kind, ThrowKind::kEmpty);
  EXPECT_EQ(t0.flight_time_s, 0);
  EXPECT_EQ(t0.v_z, 0);
  EXPECT_EQ(t0.catch_hand, Hand::kLeft);
}

TEST(SiteswapPhysicsTest, RejectsBadParameters) {
  const Siteswap s = Must("3");
  ThrowPhysicsParams p;
  p.hand_period_s = 0;
  EXPECT_EQ(ComputeSchedule(s, p).status().message(),
            "hand period must be a positive number of seconds, got 0");
  p = ThrowPhysicsParams();
  p.dwell_ratio = 1.0;
  EXPECT_EQ(ComputeSchedule(s, p).status().message(), "dwell ratio must be in (0, 1), got 1");
  p = ThrowPhysicsParams();
  p.hand_separation_m = -0.1;
  EXPECT_EQ(p.Validate().code(), absl::StatusCode::kInvalidArgument);
  p = ThrowPhysicsParams();
  p.gravity = std::nan("");
  EXPECT_EQ(p.Validate().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(ComputeSchedule(s, {}, -1).status().code(), absl::StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace juggle::toss
