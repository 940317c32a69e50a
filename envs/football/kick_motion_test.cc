// The scripted kick's reference pose (envs/football/kick_motion.h): without a knee lag the knee
// opens with the hip over the forward swing; with one it stays folded for that share of the
// swing, then opens to the same forward angle (the planner's knee change included) by its end,
// and the hip's path is the same either way.
#include "envs/football/kick_motion.h"

#include <memory>
#include <string>

#include "absl/strings/str_cat.h"
#include "envs/football/spec.h"
#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle::football {
namespace {

using ::juggle::testing::RepoPath;
using ::juggle::testing::WriteTemp;

// The shipped kick config with the given fields of `motion` set.
std::shared_ptr<const FootballSpec> SpecWithMotion(const std::string& name,
                                                   const std::string& motion) {
  const std::string text =
      absl::StrCat("base_config: \"", RepoPath("configs/football_kick.textproto"), "\"\nname: \"",
                   name, "\"\nfootball { motion { ", motion, " } }\n");
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(WriteTemp(name + ".textproto", text));
  EXPECT_TRUE(config.ok()) << config.status();
  if (!config.ok()) return nullptr;
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  if (!spec.ok()) return nullptr;
  return std::static_pointer_cast<const FootballSpec>(*spec);
}

constexpr char kMotion[] =
    "start_s: 0.2 backswing_s: 0.3 swing_s: 0.2 hip_forward: 1.7 knee_back: 1.5 knee_forward: 0";

struct LegAt {
  double knee;
  double hip_quat[4];
};

LegAt ReferenceAt(const FootballSpec& spec, double t, const KickAdjust& adjust) {
  CharacterPose pose;
  KickReferencePose(spec, t, adjust, &pose);
  const humanoid::Joints& joints = spec.joints();
  LegAt leg;
  leg.knee = pose[joints[humanoid::kRightKnee].qpos_adr];
  for (int k = 0; k < 4; ++k) leg.hip_quat[k] = pose[joints[humanoid::kRightHip].qpos_adr + k];
  return leg;
}

TEST(KickMotionTest, AKneeLagHoldsTheKneeFoldedThenOpensItByTheSwingsEndOnTheSameHipPath) {
  std::shared_ptr<const FootballSpec> together =
      SpecWithMotion("kick_together", absl::StrCat(kMotion, " knee_lag: 0"));
  std::shared_ptr<const FootballSpec> whip =
      SpecWithMotion("kick_whip", absl::StrCat(kMotion, " knee_lag: 0.5"));
  ASSERT_NE(together, nullptr);
  ASSERT_NE(whip, nullptr);
  KickAdjust adjust;
  adjust.knee = 0.1;
  const double swing = 0.2 + 0.3, recover = swing + 0.2;

  // Without a lag the knee has opened a quarter of the swing in; with one it is still folded.
  EXPECT_GT(ReferenceAt(*together, swing + 0.05, adjust).knee, -1.5 + 0.1);
  for (double u : {0.0, 0.1, 0.25, 0.45}) {
    EXPECT_DOUBLE_EQ(ReferenceAt(*whip, swing + u * 0.2, adjust).knee, -1.5) << "u " << u;
  }
  // After the lag it opens monotonically to the forward angle with the planner's change.
  double previous = -1.5;
  for (double u : {0.6, 0.7, 0.8, 0.9, 0.999}) {
    const double knee = ReferenceAt(*whip, swing + u * 0.2, adjust).knee;
    EXPECT_GT(knee, previous) << "u " << u;
    previous = knee;
  }
  EXPECT_NEAR(ReferenceAt(*whip, recover - 1e-9, adjust).knee, -(0 + 0.1), 1e-6);
  EXPECT_NEAR(ReferenceAt(*together, recover - 1e-9, adjust).knee, -(0 + 0.1), 1e-6);

  // The lag moves the knee only: the hip, the back-swing and the recovery are the same.
  for (double t = 0.15; t < 1.3; t += 0.01) {
    const LegAt a = ReferenceAt(*together, t, adjust);
    const LegAt b = ReferenceAt(*whip, t, adjust);
    for (int k = 0; k < 4; ++k) EXPECT_DOUBLE_EQ(a.hip_quat[k], b.hip_quat[k]) << "t " << t;
    if (t < swing || t >= recover) {
      EXPECT_DOUBLE_EQ(a.knee, b.knee) << "t " << t;
    }
  }
}

}  // namespace
}  // namespace juggle::football
