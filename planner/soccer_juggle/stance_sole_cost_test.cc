// The planner's standing-sole terms (PlannerCost.stance_tilt, stance_turn; docs/planner.md,
// "The standing foot's turn, traced"): on hand-made states whose foot tilt and turn rate are
// known by construction (the leg's joints at zero, so the foot turns with the root), the terms
// equal their formulas, count the standing foot only while a leg swings and both feet
// otherwise, and are part of the body cost.
#include <cmath>
#include <memory>
#include <string>

#include "common/adaptive_walk.h"
#include "envs/humanoid/humanoid.h"
#include "envs/registry.h"
#include "envs/soccer_juggle/env.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"
#include "planner/soccer_juggle/cost.h"

namespace juggle::planner {
namespace {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;

class StanceSoleCostTest : public ::testing::Test {
 protected:
  void SetUp() override {
    absl::StatusOr<LoadedConfig> config = ::juggle::testing::LoadRightFootPlannerWithGraph(
        ::juggle::testing::ReadRepoFile("configs/graphs/foot_and_head.textproto"),
        "soccer_juggle { cost { stance_tilt: 3 stance_tilt_scale: 0.04 stance_turn: 2 "
        "stance_turn_scale: 0.5 } }");
    ASSERT_TRUE(config.ok()) << config.status();
    absl::StatusOr<std::shared_ptr<const EnvSpec>> base = CreateEnvSpec(*config);
    ASSERT_TRUE(base.ok()) << base.status();
    spec_ = std::dynamic_pointer_cast<const JuggleSpec>(*base);
    cost_ = config->run.planner().soccer_juggle().cost();
    walk_ = std::make_unique<AdaptiveWalk>(&spec_->graph());
  }

  // An episode in node `name` with the root turned by `tilt` (rad) about the world's forward
  // axis and spinning at `spin` (rad/s) about its own vertical, the named legs straight (every
  // angle 0) so that their feet are oriented and turn as the root is and does.
  std::unique_ptr<JuggleEnv> Posed(const std::string& name, double tilt, double spin, bool left_leg,
                                   bool right_leg) const {
    auto env = std::make_unique<JuggleEnv>(spec_, Rng(3));
    env->ResetAt(*spec_->graph().FindNode(name), *walk_);
    mjData* d = env->data();
    mju_zero(d->qvel, spec_->model()->nv);
    const double about_x[4] = {std::cos(tilt / 2), std::sin(tilt / 2), 0, 0};
    mju_mulQuat(d->qpos + 3, about_x, humanoid::kUprightRoot);
    // The free joint's angular velocity is local: y is the root's vertical, so the world's
    // vertical component is spin · cos(tilt).
    d->qvel[4] = spin;
    using humanoid::JointId;
    auto straighten = [&](JointId hip, JointId knee, JointId ankle) {
      for (JointId ball : {hip, ankle}) {
        double* q = d->qpos + spec_->joint(ball).qpos_adr;
        q[0] = 1, q[1] = q[2] = q[3] = 0;
      }
      d->qpos[spec_->joint(knee).qpos_adr] = 0;
    };
    if (left_leg) straighten(humanoid::kLeftHip, humanoid::kLeftKnee, humanoid::kLeftAnkle);
    if (right_leg) straighten(humanoid::kRightHip, humanoid::kRightKnee, humanoid::kRightAnkle);
    mj_forward(spec_->model(), d);
    return env;
  }

  double Tilt(double angle) const {
    return cost_.stance_tilt() * std::pow(angle / cost_.stance_tilt_scale(), 2);
  }
  double Turn(double rate) const {
    return cost_.stance_turn() * std::pow(rate / cost_.stance_turn_scale(), 2);
  }

  std::shared_ptr<const JuggleSpec> spec_;
  config::PlannerCost cost_;
  std::unique_ptr<AdaptiveWalk> walk_;
};

TEST_F(StanceSoleCostTest, AStandingFootTiltedByAKnownAngleCostsItsFormula) {
  // right_foot_down swings the right leg: the left foot stands.
  std::unique_ptr<JuggleEnv> env = Posed("right_foot_down", 0.07, 0, true, false);
  EXPECT_NEAR(StanceSoleCost(*env, cost_), Tilt(0.07), 1e-9);
  env = Posed("right_foot_down", -0.12, 0, true, false);
  EXPECT_NEAR(StanceSoleCost(*env, cost_), Tilt(0.12), 1e-9);
}

TEST_F(StanceSoleCostTest, AFlatStandingFootTurningAtAKnownRateCostsItsFormula) {
  std::unique_ptr<JuggleEnv> env = Posed("right_foot_down", 0, 0.8, true, false);
  EXPECT_NEAR(StanceSoleCost(*env, cost_), Turn(0.8), 1e-9);
  env = Posed("right_foot_down", 0, 0, true, false);
  EXPECT_NEAR(StanceSoleCost(*env, cost_), 0, 1e-12);
}

TEST_F(StanceSoleCostTest, TheSwingingFootIsNotCounted) {
  // The right leg keeps its swing pose, tilted: the same cost as with the right leg straight.
  std::unique_ptr<JuggleEnv> swung = Posed("right_foot_down", 0.05, 0.3, true, false);
  std::unique_ptr<JuggleEnv> straight = Posed("right_foot_down", 0.05, 0.3, true, true);
  EXPECT_NEAR(StanceSoleCost(*swung, cost_), Tilt(0.05) + Turn(0.3 * std::cos(0.05)), 1e-9);
  EXPECT_NEAR(StanceSoleCost(*straight, cost_), StanceSoleCost(*swung, cost_), 1e-9);
}

TEST_F(StanceSoleCostTest, BothFeetCountWhenNoLegSwings) {
  // head_down swings no leg: both feet stand.
  std::unique_ptr<JuggleEnv> env = Posed("head_down", 0.06, 0.4, true, true);
  EXPECT_NEAR(StanceSoleCost(*env, cost_), 2 * (Tilt(0.06) + Turn(0.4 * std::cos(0.06))), 1e-9);
}

TEST_F(StanceSoleCostTest, TheTermsArePartOfTheBodyCostAndOffByDefault) {
  std::unique_ptr<JuggleEnv> env = Posed("right_foot_down", 0.09, 0.6, true, false);
  config::PlannerCost off = cost_;
  off.clear_stance_tilt();
  off.clear_stance_turn();
  EXPECT_EQ(StanceSoleCost(*env, off), 0);
  EXPECT_NEAR(BodyCost(*env, cost_) - BodyCost(*env, off), Tilt(0.09) + Turn(0.6 * std::cos(0.09)),
              1e-9);
}

}  // namespace
}  // namespace juggle::planner
