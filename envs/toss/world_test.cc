// TossWorld's catch test (envs/toss/world.h): a ball is caught when its path over the last step
// passes within catch_radius of the palm, not only when one sampled position does.
#include <memory>

#include "gtest/gtest.h"
#include "envs/testing/test_configs.h"
#include "envs/toss/world.h"

namespace juggle::toss {
namespace {

std::shared_ptr<const TossSpec> Spec() { return testing::LoadTossSpec("toss_catch"); }

TEST(TossWorldCatchTest, AFastBallPassingThePalmBetweenTwoStepsIsCaught) {
  auto spec = Spec();
  TossWorld world(spec);
  const Vec2 palm = world.palm_position(Hand::kRight);
  // 16 m/s downwards, 16 cm per step: sampled 7.5 cm above the palm, then 8.6 cm below it;
  // neither sample is within the 7 cm radius.
  world.SetFree(0, {palm.x, palm.z + 0.075}, {0, -16.0});
  world.Step();
  const Vec2 after = world.ball_position(0);
  ASSERT_LT(after.z, palm.z - spec->toss().catch_radius());  // jumped past the palm
  EXPECT_TRUE(world.CanCatch(0, Hand::kRight));
}

TEST(TossWorldCatchTest, ABallPassingBesideThePalmIsNotCaught) {
  auto spec = Spec();
  TossWorld world(spec);
  const Vec2 palm = world.palm_position(Hand::kRight);
  world.SetFree(0, {palm.x + 0.08, palm.z + 0.075}, {0, -16.0});
  world.Step();
  EXPECT_FALSE(world.CanCatch(0, Hand::kRight));
}

TEST(TossWorldCatchTest, AGoodThrowLandsWithinTheCatchRadiusNotTwice) {
  auto spec = Spec();
  const ThrowTiming t = ComputeThrowTiming(3, 0, spec->timing());
  const Vec2 home{spec->home_x(Hand::kRight), spec->home_z()};
  EXPECT_TRUE(IsGoodThrow(*spec, Hand::kRight, 3, home, {t.v_x, t.v_z}));
  // 10 cm long over the 0.4 s flight: outside the 7 cm radius.
  EXPECT_FALSE(IsGoodThrow(*spec, Hand::kRight, 3, home, {t.v_x + 0.1 / 0.4, t.v_z}));
  EXPECT_TRUE(IsGoodThrow(*spec, Hand::kRight, 3, home, {t.v_x + 0.05 / 0.4, t.v_z}));
}

}  // namespace
}  // namespace juggle::toss
