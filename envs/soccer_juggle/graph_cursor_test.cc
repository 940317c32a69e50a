// Graph cursor: phase speed, transition timing, apex choice, edge events, ball reference.
#include "envs/soccer_juggle/graph_cursor.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "gmock/gmock.h"
#include "google/protobuf/text_format.h"
#include "gtest/gtest.h"

namespace juggle::soccer_juggle {
namespace {

using ::testing::ElementsAre;

constexpr double kDt = 0.02;
constexpr double kG = 9.81;

// Ballistic half-cycle time from apex H down to contact height h (independent of the code).
double FallTime(double apex, double contact) { return std::sqrt(2.0 * (apex - contact) / kG); }

#define FOOT_FIELDS                                                                          \
  "contact_body: 'right_ankle' contact_height: 0.5 apex_height: 1.4 "                        \
  "ball_target { x: 0.6 y: -0.1 } pose { leg_swing {} }"
#define HEAD_FIELDS                                                                          \
  "contact_body: 'neck' contact_height: 1.6 apex_height: 2.0 "                               \
  "ball_target { x: 0 y: 0 } pose { head_dip {} }"

// right foot <-> right foot.
constexpr char kFoot[] =
    "node { name: 'foot_down' stage: DOWN initial: true " FOOT_FIELDS " }"
    "node { name: 'foot_up' stage: UP " FOOT_FIELDS " }"
    "edge { from: 'foot_down' to: 'foot_up' }"
    "edge { from: 'foot_up' to: 'foot_down' }";

// A fixed tour foot -> head -> foot (every node has one way out, so the walk is deterministic).
constexpr char kFootHeadTour[] =
    "node { name: 'foot_down' stage: DOWN initial: true " FOOT_FIELDS " }"
    "node { name: 'foot_up' stage: UP " FOOT_FIELDS " }"
    "node { name: 'head_down' stage: DOWN initial: true " HEAD_FIELDS " }"
    "node { name: 'head_up' stage: UP " HEAD_FIELDS " }"
    "edge { from: 'foot_down' to: 'foot_up' }"
    "edge { from: 'foot_up' to: 'head_down' }"
    "edge { from: 'head_down' to: 'head_up' }"
    "edge { from: 'head_up' to: 'foot_down' }";

// Foot juggles and headers with both transitions (the live page's skill choice).
constexpr char kFootAndHead[] =
    "node { name: 'foot_down' stage: DOWN initial: true " FOOT_FIELDS " }"
    "node { name: 'foot_up' stage: UP " FOOT_FIELDS " }"
    "node { name: 'head_down' stage: DOWN " HEAD_FIELDS " }"
    "node { name: 'head_up' stage: UP " HEAD_FIELDS " }"
    "edge { from: 'foot_down' to: 'foot_up' }"
    "edge { from: 'foot_up' to: 'foot_down' }"
    "edge { from: 'foot_up' to: 'head_down' }"
    "edge { from: 'head_down' to: 'head_up' }"
    "edge { from: 'head_up' to: 'head_down' }"
    "edge { from: 'head_up' to: 'foot_down' }";

// Head juggle only.
constexpr char kHead[] =
    "node { name: 'head_down' stage: DOWN initial: true " HEAD_FIELDS " }"
    "node { name: 'head_up' stage: UP " HEAD_FIELDS " }"
    "edge { from: 'head_down' to: 'head_up' }"
    "edge { from: 'head_up' to: 'head_down' }";

// Around-the-world: fixed 0.3 s halves.
constexpr char kAtw[] =
    "node { name: 'atw_down' stage: DOWN initial: true contact_body: 'right_ankle' "
    "  contact_height: 0.45 half_cycle_s: 0.3 ball_target { x: 0.6 y: -0.06 } "
    "  pose { keyframes { frame { phase: 0 } } } }"
    "node { name: 'atw_up' stage: UP contact_body: 'right_ankle' "
    "  contact_height: 0.45 half_cycle_s: 0.3 ball_target { x: 0.6 y: -0.06 } "
    "  pose { keyframes { frame { phase: 0.5 } } } }"
    "edge { from: 'atw_down' to: 'atw_up' }"
    "edge { from: 'atw_up' to: 'atw_down' }";

// Foot stall (paper App. C.2): down -> stall (self-loop 30) -> up -> down.
constexpr char kStall[] =
    "node { name: 'foot_down' stage: DOWN initial: true " FOOT_FIELDS " }"
    "node { name: 'foot_stall' stage: STALL contact_body: 'right_ankle' contact_height: 0.5 "
    "  ball_target { x: 0.55 y: -0.1 } stall { body: 'right_ankle' ball_height: 0.62 } "
    "  pose { leg_swing { hold_peak: true } } }"
    "node { name: 'foot_up' stage: UP " FOOT_FIELDS " }"
    "edge { from: 'foot_down' to: 'foot_stall' }"
    "edge { from: 'foot_stall' to: 'foot_stall' weight: 30 }"
    "edge { from: 'foot_stall' to: 'foot_up' }"
    "edge { from: 'foot_up' to: 'foot_down' }";

// Variable-height foot juggle: the UP node draws its apex in [1, 2].
constexpr char kVariable[] =
    "node { name: 'foot_down' stage: DOWN initial: true contact_body: 'right_ankle' "
    "  contact_height: 0.5 apex_height: 1.0 pose { leg_swing {} } }"
    "node { name: 'foot_up' stage: UP contact_body: 'right_ankle' contact_height: 0.5 "
    "  apex_height_range { min: 1.0 max: 2.0 } pose { leg_swing {} } }"
    "edge { from: 'foot_down' to: 'foot_up' }"
    "edge { from: 'foot_up' to: 'foot_down' }";

// A graph with its adaptive walk and a cursor at dt 0.02, g 9.81.
struct Harness {
  explicit Harness(const char* text, bool carry_phase = false) {
    config::ControlGraph proto;
    EXPECT_TRUE(google::protobuf::TextFormat::ParseFromString(text, &proto));
    absl::StatusOr<ControlGraph> built = ControlGraph::Build(proto, SourceLocator("test"));
    EXPECT_TRUE(built.ok()) << built.status();
    graph = std::make_unique<ControlGraph>(*std::move(built));
    walk = std::make_unique<AdaptiveWalk>(graph.get());
    cursor = std::make_unique<GraphCursor>(graph.get(), kDt, kG, carry_phase);
  }
  int Node(const std::string& name) const { return *graph->FindNode(name); }
  int EdgeBetween(const std::string& from, const std::string& to) const {
    return *graph->FindEdge(Node(from), Node(to));
  }
  void ResetAt(const std::string& name) { cursor->ResetAt(Node(name), *walk, &rng, &s); }
  // Advances until a transition; returns the number of Advance calls (0 if none in 10000).
  int StepsToTransition(std::vector<EdgeEvent>* events = nullptr) {
    std::vector<EdgeEvent> scratch;
    for (int steps = 1; steps <= 10000; ++steps) {
      if (cursor->Advance(*walk, &rng, &s, events != nullptr ? events : &scratch)) return steps;
    }
    return 0;
  }
  const std::string& Current() const { return graph->node(s.current).name; }

  std::unique_ptr<ControlGraph> graph;
  std::unique_ptr<AdaptiveWalk> walk;
  std::unique_ptr<GraphCursor> cursor;
  Rng rng{7};
  CursorState s;
};

// 50 foot cycles: the release's snapping runs each in 42 steps (0.84 s), 17 ms short of the
// ballistic 2·0.4284 s; carrying the phase keeps the clock within a step of the ball.
TEST(GraphCursorTest, CarriedPhaseKeepsTimeWithTheBallOverManyCycles) {
  const double cycle_s = 2 * FallTime(1.4, 0.5);
  for (bool carry : {false, true}) {
    Harness t(kFoot, carry);
    t.ResetAt("foot_down");
    int steps = 0;
    for (int transitions = 0; transitions < 100; ++transitions) steps += t.StepsToTransition();
    const double clock_s = steps * kDt;
    if (carry) {
      EXPECT_NEAR(clock_s, 50 * cycle_s, kDt) << "carried";
    } else {
      EXPECT_EQ(steps, 50 * 42) << "snapped";
      EXPECT_NEAR(50 * cycle_s - clock_s, 50 * 0.0169, 0.02);
    }
  }
}

TEST(GraphCursorTest, FootHalfCycleIsTheBallisticFallFromApexToContact) {
  Harness t(kFoot);
  t.ResetAt("foot_down");
  EXPECT_EQ(t.s.apex_height, 1.4);
  EXPECT_NEAR(t.cursor->HalfCycleSeconds(t.Node("foot_down"), 1.4), 0.4284, 1e-4);
  EXPECT_NEAR(t.s.phase_speed, kDt / (2 * FallTime(1.4, 0.5)), 1e-12);
  EXPECT_EQ(t.s.phase, 0.0);
}

TEST(GraphCursorTest, FootContactComesAfterTheNearestWholeNumberOfControlSteps) {
  Harness t(kFoot);
  t.ResetAt("foot_down");
  // 0.4284 s / 0.02 s = 21.4 steps: the transition is on step 21.
  const int steps = t.StepsToTransition();
  EXPECT_EQ(steps, std::lround(FallTime(1.4, 0.5) / kDt));
  EXPECT_EQ(steps, 21);
  EXPECT_EQ(t.Current(), "foot_up");
  EXPECT_EQ(t.s.phase, 0.5);  // snapped exactly
}

TEST(GraphCursorTest, HeadHalfCycleUsesApexTwoAndContactOnePointSix) {
  Harness t(kHead);
  t.ResetAt("head_down");
  EXPECT_EQ(t.s.apex_height, 2.0);
  EXPECT_NEAR(t.cursor->HalfCycleSeconds(t.Node("head_down"), 2.0), 0.28557, 1e-5);
  EXPECT_NEAR(t.s.phase_speed, kDt / (2 * FallTime(2.0, 1.6)), 1e-12);
  EXPECT_EQ(t.StepsToTransition(), 14);  // 0.2856 s = 14.3 steps
  EXPECT_EQ(t.StepsToTransition(), 14);  // the rise back to 2.0 m
  EXPECT_EQ(t.Current(), "head_down");
}

TEST(GraphCursorTest, DownNodeEndsOnTheStepNearestHalfAndUpNodeOnTheStepNearestOne) {
  Harness t(kFoot);
  // Phase speeds for half cycles from 0.2 s to 0.6 s, including ones that land between steps.
  for (double half = 0.2; half < 0.6; half += 0.0137) {
    const double ps = kDt / (2 * half);
    t.ResetAt("foot_down");
    t.s.phase_speed = ps;
    const int k = t.StepsToTransition();
    EXPECT_LE(std::abs(k * ps - 0.5), std::abs((k - 1) * ps - 0.5)) << half;
    EXPECT_LE(std::abs(k * ps - 0.5), std::abs((k + 1) * ps - 0.5)) << half;
    EXPECT_EQ(t.s.phase, 0.5);
    ASSERT_EQ(t.Current(), "foot_up");

    t.s.phase_speed = ps;
    const int m = t.StepsToTransition();
    EXPECT_LE(std::abs(0.5 + m * ps - 1.0), std::abs(0.5 + (m - 1) * ps - 1.0)) << half;
    EXPECT_LE(std::abs(0.5 + m * ps - 1.0), std::abs(0.5 + (m + 1) * ps - 1.0)) << half;
    EXPECT_EQ(t.s.phase, 0.0);  // wrapped
    ASSERT_EQ(t.Current(), "foot_down");
  }
}

TEST(GraphCursorTest, PhaseGrowsByThePhaseSpeedEveryStepBetweenTransitions) {
  Harness t(kFoot);
  t.ResetAt("foot_down");
  std::vector<EdgeEvent> events;
  for (int i = 1; i <= 10; ++i) {
    ASSERT_FALSE(t.cursor->Advance(*t.walk, &t.rng, &t.s, &events));
    EXPECT_NEAR(t.s.phase, i * t.s.phase_speed, 1e-12);
  }
  EXPECT_TRUE(events.empty());
}

TEST(GraphCursorTest, DesiredBallVelocityIsTheTimeDerivativeOfTheDesiredBall) {
  Harness t(kFoot);
  for (const char* node : {"foot_down", "foot_up"}) {
    t.ResetAt(node);
    const double dphi = 1e-6;
    const double dt = dphi / t.s.phase_speed * kDt;  // seconds per dphi
    for (double phase : {0.05, 0.2, 0.45, 0.55, 0.8, 0.95}) {
      const double z0 = t.cursor->DesiredBall(t.s, phase - dphi).z;
      const double z1 = t.cursor->DesiredBall(t.s, phase + dphi).z;
      const BallReference v = t.cursor->DesiredBallVelocity(t.s, phase);
      if ((std::string(node) == "foot_down") == (phase < 0.5)) {
        EXPECT_NEAR(v.z, (z1 - z0) / (2 * dt), 1e-5) << node << " " << phase;
      }
      EXPECT_EQ(v.x, 0.0);
      EXPECT_EQ(v.y, 0.0);
    }
  }
}

TEST(GraphCursorTest, FootToFootCycleTakesTwiceTheRoundedHalfCycle) {
  Harness t(kFoot);
  t.ResetAt("foot_down");
  const int down = t.StepsToTransition();
  EXPECT_EQ(t.s.apex_height, 1.4);  // max(1.4, 1.4)
  const int up = t.StepsToTransition();
  EXPECT_EQ(t.Current(), "foot_down");
  EXPECT_NEAR(down + up, 2 * std::lround(0.4284 / kDt), 1);
}

TEST(GraphCursorTest, FootToHeadFlightUsesTheHigherApexForAscentAndDescent) {
  Harness t(kFootHeadTour);
  t.ResetAt("foot_down");
  ASSERT_EQ(t.StepsToTransition(), 21);  // foot_down from its own 1.4 m
  ASSERT_EQ(t.Current(), "foot_up");
  EXPECT_EQ(t.s.apex_height, 2.0);  // max(foot 1.4, head 2.0)
  EXPECT_NEAR(t.s.phase_speed, kDt / (2 * FallTime(2.0, 0.5)), 1e-12);  // rises 0.553 s
  EXPECT_EQ(t.StepsToTransition(), 28);                                 // 27.65 steps

  ASSERT_EQ(t.Current(), "head_down");
  EXPECT_EQ(t.s.apex_height, 2.0);  // the same flight comes down onto the head
  EXPECT_NEAR(t.s.phase_speed, kDt / (2 * FallTime(2.0, 1.6)), 1e-12);  // falls 0.286 s
  EXPECT_EQ(t.StepsToTransition(), 14);
}

TEST(GraphCursorTest, HeadToFootFlightUsesTheHigherApexForAscentAndDescent) {
  Harness t(kFootHeadTour);
  t.ResetAt("head_down");
  ASSERT_EQ(t.StepsToTransition(), 14);
  ASSERT_EQ(t.Current(), "head_up");
  EXPECT_EQ(t.s.apex_height, 2.0);  // max(head 2.0, foot 1.4)
  EXPECT_NEAR(t.s.phase_speed, kDt / (2 * FallTime(2.0, 1.6)), 1e-12);
  ASSERT_EQ(t.StepsToTransition(), 14);
  ASSERT_EQ(t.Current(), "foot_down");
  EXPECT_EQ(t.s.apex_height, 2.0);
  EXPECT_NEAR(t.s.phase_speed, kDt / (2 * FallTime(2.0, 0.5)), 1e-12);
  EXPECT_EQ(t.StepsToTransition(), 28);
}

TEST(GraphCursorTest, HalfCycleOverrideGivesFifteenStepsPerAroundTheWorldHalf) {
  Harness t(kAtw);
  t.ResetAt("atw_down");
  for (double apex : {0.5, 0.9, 3.0}) {
    EXPECT_EQ(t.cursor->HalfCycleSeconds(t.Node("atw_down"), apex), 0.3);
  }
  EXPECT_NEAR(t.s.phase_speed, kDt / 0.6, 1e-15);
  // The apex implied by the fixed half cycle: 0.45 + ½·9.81·0.3².
  EXPECT_NEAR(t.s.apex_height, 0.45 + 0.5 * kG * 0.09, 1e-12);
  EXPECT_EQ(t.StepsToTransition(), 15);
  EXPECT_EQ(t.Current(), "atw_up");
  EXPECT_EQ(t.StepsToTransition(), 15);
  EXPECT_EQ(t.Current(), "atw_down");
}

TEST(GraphCursorTest, StallHoldsPhaseHalfAndTransitionsEveryStep) {
  Harness t(kStall);
  t.ResetAt("foot_down");
  ASSERT_EQ(t.StepsToTransition(), 21);
  ASSERT_EQ(t.Current(), "foot_stall");
  int stall_steps = 0;
  while (t.Current() == "foot_stall" && stall_steps < 10000) {
    EXPECT_EQ(t.s.phase, 0.5);
    EXPECT_EQ(t.s.phase_speed, 0.0);
    EXPECT_EQ(t.cursor->SecondsFromContact(t.s, t.s.phase), 0.0);
    EXPECT_EQ(t.cursor->DesiredBall(t.s, 0.5).z, 0.62);  // stall.ball_height
    EXPECT_EQ(t.cursor->DesiredBall(t.s, 0.5).x, 0.55);
    std::vector<EdgeEvent> events;
    EXPECT_TRUE(t.cursor->Advance(*t.walk, &t.rng, &t.s, &events));  // every step
    ++stall_steps;
  }
  ASSERT_EQ(t.Current(), "foot_up");
  EXPECT_EQ(t.s.phase, 0.5);  // the rise starts at the contact phase
  EXPECT_NEAR(t.s.phase_speed, kDt / (2 * FallTime(1.4, 0.5)), 1e-12);
}

TEST(GraphCursorTest, StallDwellAveragesThirtyOneStepsWithSelfLoopWeightThirty) {
  // P(leave) = 1/31 per step: the dwell is geometric with mean 31 steps (≈ 0.62 s).
  Harness t(kStall);
  const int visits = 400;
  long total = 0;
  for (int v = 0; v < visits; ++v) {
    t.ResetAt("foot_down");
    ASSERT_GT(t.StepsToTransition(), 0);
    ASSERT_EQ(t.Current(), "foot_stall");
    int dwell = 0;
    while (t.Current() == "foot_stall") {
      dwell += t.StepsToTransition();
      ASSERT_LT(dwell, 5000);
    }
    total += dwell;
  }
  EXPECT_NEAR(static_cast<double>(total) / visits, 31.0, 5.0);
}

TEST(GraphCursorTest, FirstTransitionEmitsOnlyChosen) {
  Harness t(kFoot);
  t.ResetAt("foot_down");
  EXPECT_EQ(t.s.entered_by, -1);
  const int down_up = t.EdgeBetween("foot_down", "foot_up");
  EXPECT_EQ(t.s.edge_to_next, down_up);
  std::vector<EdgeEvent> events;
  t.StepsToTransition(&events);
  EXPECT_THAT(events, ElementsAre(EdgeEvent{down_up, EdgeEventType::kChosen}));
  EXPECT_EQ(t.s.entered_by, down_up);
  EXPECT_EQ(t.s.completions, 1);
}

TEST(GraphCursorTest, LaterTransitionsEmitCompletedForTheEnteringEdgeThenChosen) {
  Harness t(kFoot);
  t.ResetAt("foot_down");
  const int down_up = t.EdgeBetween("foot_down", "foot_up");
  const int up_down = t.EdgeBetween("foot_up", "foot_down");
  t.StepsToTransition();
  std::vector<EdgeEvent> events;
  t.StepsToTransition(&events);
  EXPECT_THAT(events, ElementsAre(EdgeEvent{down_up, EdgeEventType::kCompleted},
                                  EdgeEvent{up_down, EdgeEventType::kChosen}));
  events.clear();
  t.StepsToTransition(&events);
  EXPECT_THAT(events, ElementsAre(EdgeEvent{up_down, EdgeEventType::kCompleted},
                                  EdgeEvent{down_up, EdgeEventType::kChosen}));
  EXPECT_EQ(t.s.completions, 3);
}

TEST(GraphCursorTest, FailEmitsFailedForTheEnteringEdge) {
  Harness t(kFoot);
  t.ResetAt("foot_down");
  t.StepsToTransition();
  std::vector<EdgeEvent> events;
  t.cursor->Fail(t.s, &events);
  EXPECT_THAT(events, ElementsAre(EdgeEvent{t.EdgeBetween("foot_down", "foot_up"),
                                            EdgeEventType::kFailed}));
}

TEST(GraphCursorTest, FailInTheFirstNodeEmitsNothing) {
  Harness t(kFoot);
  t.ResetAt("foot_down");
  std::vector<EdgeEvent> events;
  t.cursor->Fail(t.s, &events);
  EXPECT_TRUE(events.empty());
}

TEST(GraphCursorTest, DesiredBallFallsFromTheApexToTheContactHeightOnADownNode) {
  Harness t(kFoot);
  t.ResetAt("foot_down");
  const double T = FallTime(1.4, 0.5);
  EXPECT_NEAR(t.cursor->DesiredBall(t.s, 0.0).z, 1.4, 1e-12);
  EXPECT_NEAR(t.cursor->DesiredBall(t.s, 0.5).z, 0.5, 1e-12);
  for (double phase : {0.1, 0.25, 0.4}) {
    const double time = phase / 0.5 * T;  // seconds since the apex
    EXPECT_NEAR(t.cursor->DesiredBall(t.s, phase).z, 1.4 - 0.5 * kG * time * time, 1e-9) << phase;
  }
  const BallReference ref = t.cursor->DesiredBall(t.s, 0.3);
  EXPECT_EQ(ref.x, 0.6);
  EXPECT_EQ(ref.y, -0.1);
}

TEST(GraphCursorTest, DesiredBallRisesBallisticallyOnAnUpNode) {
  Harness t(kFoot);
  t.ResetAt("foot_down");
  t.StepsToTransition();
  ASSERT_EQ(t.Current(), "foot_up");
  const double h = 0.5, H = 1.4;
  const double T = FallTime(H, h);
  const double v0 = std::sqrt(2 * kG * (H - h));  // leaves the foot at this speed
  for (double phase : {0.5, 0.6, 0.75, 0.9, 1.0}) {
    const double time = (phase - 0.5) / 0.5 * T;  // seconds since the contact
    EXPECT_NEAR(t.cursor->DesiredBall(t.s, phase).z, h + v0 * time - 0.5 * kG * time * time, 1e-9)
        << phase;
  }
  EXPECT_NEAR(t.cursor->DesiredBall(t.s, 1.0).z, H, 1e-9);
}

TEST(GraphCursorTest, UpNodeSteersTheBallToTheNextNodesTarget) {
  Harness t(kFootHeadTour);
  t.ResetAt("foot_down");
  EXPECT_EQ(t.cursor->DesiredBall(t.s, 0.2).x, 0.6);
  EXPECT_EQ(t.cursor->DesiredBall(t.s, 0.2).y, -0.1);
  t.StepsToTransition();
  ASSERT_EQ(t.Current(), "foot_up");
  ASSERT_EQ(t.graph->node(t.s.next).name, "head_down");
  // foot_up's own target is (0.6, -0.1); the next node (head) wants the ball above the root.
  EXPECT_EQ(t.cursor->DesiredBall(t.s, 0.7).x, 0.0);
  EXPECT_EQ(t.cursor->DesiredBall(t.s, 0.7).y, 0.0);
  // And the ascent peaks at the flight's apex, 2.0 m.
  EXPECT_NEAR(t.cursor->DesiredBall(t.s, 1.0).z, 2.0, 1e-9);
}

TEST(GraphCursorTest, SecondsFromContactIsNegativeBeforeTheContact) {
  Harness t(kFoot);
  t.ResetAt("foot_down");
  const double T = FallTime(1.4, 0.5);
  EXPECT_NEAR(t.cursor->SecondsFromContact(t.s, 0.4), -0.2 * T, 1e-12);
  EXPECT_NEAR(t.cursor->SecondsFromContact(t.s, 0.5), 0.0, 1e-12);
  EXPECT_NEAR(t.cursor->SecondsFromContact(t.s, 0.55), 0.1 * T, 1e-12);
}

TEST(GraphCursorTest, VariableApexIsDrawnInItsRangeEveryCycle) {
  Harness t(kVariable);
  t.ResetAt("foot_down");
  EXPECT_EQ(t.s.apex_height, 1.0);  // the DOWN node's own apex starts the episode
  std::vector<double> apexes;
  for (int cycle = 0; cycle < 300; ++cycle) {
    ASSERT_GT(t.StepsToTransition(), 0);
    ASSERT_EQ(t.Current(), "foot_up");
    const double H = t.s.apex_height;
    apexes.push_back(H);
    EXPECT_GE(H, 1.0);
    EXPECT_LE(H, 2.0);
    EXPECT_NEAR(t.s.phase_speed, kDt / (2 * FallTime(H, 0.5)), 1e-12);
    ASSERT_GT(t.StepsToTransition(), 0);
    ASSERT_EQ(t.Current(), "foot_down");
    // The descent that follows comes from the same apex.
    EXPECT_EQ(t.s.apex_height, H);
    EXPECT_NEAR(t.s.phase_speed, kDt / (2 * FallTime(H, 0.5)), 1e-12);
  }
  double mean = 0, lo = 2, hi = 1;
  for (double H : apexes) {
    mean += H / apexes.size();
    lo = std::min(lo, H);
    hi = std::max(hi, H);
  }
  EXPECT_NEAR(mean, 1.5, 0.06);  // uniform in [1, 2]
  EXPECT_LT(lo, 1.1);
  EXPECT_GT(hi, 1.9);
}

TEST(GraphCursorTest, VariableApexDiffersAcrossSeeds) {
  std::vector<double> first_apex;
  for (uint64_t seed : {1, 2, 3}) {
    Harness t(kVariable);
    t.rng = Rng(seed);
    t.ResetAt("foot_down");
    t.StepsToTransition();
    first_apex.push_back(t.s.apex_height);
  }
  EXPECT_NE(first_apex[0], first_apex[1]);
  EXPECT_NE(first_apex[1], first_apex[2]);
  EXPECT_NE(first_apex[0], first_apex[2]);
}

TEST(GraphCursorTest, ResetStartsAtAnInitialNodeDrawnUniformly) {
  Harness t(kFootHeadTour);  // initial: foot_down and head_down
  int foot = 0;
  const int resets = 4000;
  for (int i = 0; i < resets; ++i) {
    t.cursor->Reset(*t.walk, &t.rng, &t.s);
    ASSERT_TRUE(t.Current() == "foot_down" || t.Current() == "head_down") << t.Current();
    foot += t.Current() == "foot_down";
    EXPECT_EQ(t.s.phase, 0.0);
    EXPECT_EQ(t.s.entered_by, -1);
    EXPECT_EQ(t.s.completions, 0);
    // The lookahead follows the sampled edges.
    EXPECT_EQ(t.graph->edge(t.s.edge_to_next).from, t.s.current);
    EXPECT_EQ(t.graph->edge(t.s.edge_to_next).to, t.s.next);
    EXPECT_EQ(t.graph->edge(t.s.edge_to_next_next).from, t.s.next);
    EXPECT_EQ(t.graph->edge(t.s.edge_to_next_next).to, t.s.next_next);
  }
  EXPECT_NEAR(static_cast<double>(foot) / resets, 0.5, 0.03);
}

// The live page's skill choice: a steering toward the head takes effect for the node after the
// coming one at once (the DOWN node's kick aims there), and every later choice of the walk
// follows it; the current and the coming node stay.
TEST(GraphCursorTest, ResteerTakesTheSteeredEdgeForTheNodeAfterTheComingOne) {
  Harness h(kFootAndHead);
  h.ResetAt("foot_down");
  std::vector<int> steering(h.graph->num_nodes(), -1);
  steering[h.Node("foot_up")] = h.EdgeBetween("foot_up", "head_down");
  steering[h.Node("head_up")] = h.EdgeBetween("head_up", "head_down");
  ASSERT_TRUE(h.walk->SetSteering(steering).ok());
  const bool sampled_head = h.graph->node(h.s.next_next).name == "head_down";
  EXPECT_EQ(h.cursor->Resteer(*h.walk, &h.s), !sampled_head);
  EXPECT_EQ(h.Current(), "foot_down");
  EXPECT_EQ(h.graph->node(h.s.next).name, "foot_up");
  EXPECT_EQ(h.graph->node(h.s.next_next).name, "head_down");
  EXPECT_EQ(h.s.edge_to_next_next, h.EdgeBetween("foot_up", "head_down"));
  EXPECT_FALSE(h.cursor->Resteer(*h.walk, &h.s));  // nothing left to change
  std::vector<std::string> visited;
  for (int i = 0; i < 7; ++i) {
    ASSERT_GT(h.StepsToTransition(), 0);
    visited.push_back(h.Current());
  }
  EXPECT_EQ(visited, std::vector<std::string>({"foot_up", "head_down", "head_up", "head_down",
                                               "head_up", "head_down", "head_up"}));
}

}  // namespace
}  // namespace juggle::soccer_juggle
