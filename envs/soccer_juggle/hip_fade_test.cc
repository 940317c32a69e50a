// env.stance_balance.hip_contact_window: in a leg swing the balance's hip terms fade linearly
// to nothing at the contact (φ = 0.5), seen in the stance hip's feed-forward torque of the base
// controller against the same config without the hip terms and with them whole; nodes where
// both feet stand keep them whole.
#include <cmath>
#include <memory>
#include <vector>

#include "envs/mujoco_model.h"
#include "envs/soccer_juggle/base_controller.h"
#include "envs/soccer_juggle/env.h"
#include "envs/soccer_juggle/reference_pose.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"

namespace juggle::soccer_juggle {
namespace {

constexpr double kWindow = 0.2;

// The base controller's feed-forward torque on `joint` ([3], N·m) at `node`'s `phase` (the
// next node `next`), from a copy of `state`.
std::vector<double> HipTorque(const JuggleSpec& spec, const mjData& state, const char* node,
                              const char* next, double phase, JointId joint) {
  BaseController base(spec);
  MjDataPtr data(mj_makeData(spec.model()));
  mj_copyData(data.get(), spec.model(), &state);
  CursorState cursor;
  cursor.current = *spec.graph().FindNode(node);
  cursor.next = *spec.graph().FindNode(next);
  cursor.phase = phase;
  cursor.phase_speed = 0.02;
  CharacterPose reference;
  ComputeReferencePose(spec, cursor.current, phase, &reference);
  std::vector<double> feedforward(kCharacterNv, 0.0);
  base.AddFeedforward(cursor, reference, SwingAdjust(), data.get(), feedforward.data());
  const int adr = spec.joint(joint).dof_adr;
  return {feedforward[adr], feedforward[adr + 1], feedforward[adr + 2]};
}

TEST(StanceHipFadeTest, TheHipTermsFadeLinearlyToNothingAtALegSwingsContactOnly) {
  // foot_and_head_planner ships the hip terms (hip_roll 1, hip_pitch 3) without a fade.
  std::shared_ptr<const JuggleSpec> whole = testing::LoadSpec("foot_and_head_planner");
  ASSERT_NE(whole, nullptr);
  ASSERT_GT(whole->env().stance_balance().hip_pitch(), 0);
  ASSERT_EQ(whole->env().stance_balance().hip_contact_window(), 0);
  std::shared_ptr<const JuggleSpec> faded = testing::EditedEnv(
      whole, [](config::EnvConfig* env) {
        env->mutable_stance_balance()->set_hip_contact_window(kWindow);
      });
  std::shared_ptr<const JuggleSpec> none = testing::EditedEnv(whole, [](config::EnvConfig* env) {
    env->mutable_stance_balance()->set_hip_roll(0);
    env->mutable_stance_balance()->set_hip_pitch(0);
  });
  ASSERT_NE(faded, nullptr);
  ASSERT_NE(none, nullptr);

  // The character at the kick's start, its centre of mass moved off the standing foot, moving.
  AdaptiveWalk walk(&whole->graph());
  JuggleEnv env(whole, Rng(5));
  ASSERT_TRUE(env.ResetAt(*whole->graph().FindNode("right_foot_down"), walk));
  mjData* d = env.data();
  d->qpos[0] += 0.03;
  d->qpos[1] -= 0.02;
  d->qvel[0] = 0.1;
  d->qvel[1] = -0.1;
  mj_forward(whole->model(), d);

  struct Case {
    const char* node;
    const char* next;
    double phase;
    double scale;  // of the hip terms
  };
  const Case cases[] = {
      {"right_foot_down", "right_foot_up", 0.1, 1.0},  // a window or more from the contact
      {"right_foot_down", "right_foot_up", 0.35, 0.75},
      {"right_foot_down", "right_foot_up", 0.5, 0.0},  // the contact
      {"right_foot_up", "head_down", 0.6, 0.5},
      {"right_foot_up", "head_down", 0.9, 1.0},
      {"head_down", "head_up", 0.5, 1.0},  // both feet stand: not a leg swing
  };
  for (const Case& c : cases) {
    // The right foot kicks, so the left hip stands; under a header both hips take half.
    const JointId hip = kLeftHip;
    const std::vector<double> w = HipTorque(*whole, *d, c.node, c.next, c.phase, hip);
    const std::vector<double> f = HipTorque(*faded, *d, c.node, c.next, c.phase, hip);
    const std::vector<double> n = HipTorque(*none, *d, c.node, c.next, c.phase, hip);
    // The hip terms matter here (else the comparison says nothing) and are not clamped: the
    // torque is affine in the gains, so the faded one lies `scale` of the way from none.
    EXPECT_GT(std::hypot(w[0] - n[0], w[1] - n[1], w[2] - n[2]), 1.0) << c.node << c.phase;
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(f[k], n[k] + c.scale * (w[k] - n[k]), 1e-9) << c.node << " " << c.phase;
    }
    // The ankles' torques do not depend on the hip terms.
    for (const JointId ankle : {kLeftAnkle, kRightAnkle}) {
      const std::vector<double> a = HipTorque(*whole, *d, c.node, c.next, c.phase, ankle);
      const std::vector<double> b = HipTorque(*faded, *d, c.node, c.next, c.phase, ankle);
      for (int k = 0; k < 3; ++k) EXPECT_EQ(a[k], b[k]) << c.node << c.phase;
    }
  }
}

}  // namespace
}  // namespace juggle::soccer_juggle
