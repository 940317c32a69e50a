// Keyframes.smooth (envs/soccer_juggle/reference_pose.cc SmoothKeyframePose): the cubic passes
// through every authored frame, and its velocity, which jumps at a frame when the frames are
// joined by straight lines, is continuous there. graphs/around_the_world.textproto's frames.
#include <cmath>
#include <memory>
#include <string>

#include "absl/strings/str_replace.h"
#include "envs/soccer_juggle/reference_pose.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle::soccer_juggle {
namespace {

std::shared_ptr<const JuggleSpec> SmoothAtwSpec(bool smooth) {
  std::string graph = testing::ReadRepoFile("configs/graphs/around_the_world.textproto");
  if (smooth) {
    graph = absl::StrReplaceAll(graph, {{"swing_side: RIGHT\n", "swing_side: RIGHT smooth: true\n"}});
  }
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = testing::SoccerSpecWithGraph(graph);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return spec.ok() ? *spec : nullptr;
}

// Every coordinate of the pose's qpos (root, quaternions, hinges) at `phase` of `node`.
CharacterPose PoseAt(const JuggleSpec& spec, int node, double phase) {
  CharacterPose pose;
  ComputeReferencePose(spec, node, phase, &pose);
  return pose;
}

TEST(SmoothKeyframesTest, TheCubicPassesThroughEveryFrame) {
  const std::shared_ptr<const JuggleSpec> linear = SmoothAtwSpec(false);
  const std::shared_ptr<const JuggleSpec> smooth = SmoothAtwSpec(true);
  ASSERT_NE(linear, nullptr);
  ASSERT_NE(smooth, nullptr);
  for (const char* name : {"right_atw_down", "right_atw_up"}) {
    const int node = *smooth->graph().FindNode(name);
    const NodeRuntime& rt = smooth->node_runtime(node);
    ASSERT_GE(rt.keyframe_phase.size(), 5u);
    for (size_t k = 0; k < rt.keyframe_phase.size(); ++k) {
      const CharacterPose at = PoseAt(*smooth, node, rt.keyframe_phase[k]);
      for (size_t i = 0; i < at.size(); ++i) {
        EXPECT_NEAR(at[i], rt.keyframe_pose[k][i], 1e-9)
            << name << " frame " << k << " qpos " << i;
      }
    }
    // Between frames the two interpolations differ: the option is not a no-op.
    const double mid = 0.5 * (rt.keyframe_phase[1] + rt.keyframe_phase[2]);
    const CharacterPose a = PoseAt(*linear, node, mid), b = PoseAt(*smooth, node, mid);
    double differ = 0;
    for (size_t i = 0; i < a.size(); ++i) differ = std::max(differ, std::abs(a[i] - b[i]));
    EXPECT_GT(differ, 1e-3) << name;
  }
}

TEST(SmoothKeyframesTest, TheVelocityIsContinuousAtAFrameWhereTheLinearOneJumps) {
  const std::shared_ptr<const JuggleSpec> linear = SmoothAtwSpec(false);
  const std::shared_ptr<const JuggleSpec> smooth = SmoothAtwSpec(true);
  ASSERT_NE(linear, nullptr);
  ASSERT_NE(smooth, nullptr);
  const int node = *smooth->graph().FindNode("right_atw_up");
  const NodeRuntime& rt = smooth->node_runtime(node);
  const int knee = smooth->joint(humanoid::kRightKnee).qpos_adr;
  const double h = 1e-5;
  int frames = 0;
  for (size_t k = 1; k + 1 < rt.keyframe_phase.size(); ++k) {
    const double phase = rt.keyframe_phase[k];
    // One-sided rates of the knee just before and just after the frame.
    auto jump = [&](const JuggleSpec& spec) {
      const double before = (PoseAt(spec, node, phase)[knee] -
                             PoseAt(spec, node, phase - h)[knee]) / h;
      const double after = (PoseAt(spec, node, phase + h)[knee] -
                            PoseAt(spec, node, phase)[knee]) / h;
      return std::abs(after - before);
    };
    const double linear_jump = jump(*linear);
    if (linear_jump < 0.3) continue;  // a frame the straight lines pass without a kink
    EXPECT_LT(jump(*smooth), 1e-3 * linear_jump) << "frame " << k << " at phase " << phase;
    ++frames;
  }
  EXPECT_GE(frames, 3) << "the authored frames bend the knee's path at several frames";
}

}  // namespace
}  // namespace juggle::soccer_juggle
