// Physics of the model itself: restitution of the ball on the foot and free fall, in the
// 400-Hz world of every other config and in the coarser ones of issue 48
// (configs/right_foot_planner_{300,250,200}hz.textproto).
#include <cmath>
#include <ostream>
#include <string>

#include <mujoco/mujoco.h>

#include "gtest/gtest.h"
#include "envs/soccer_juggle/reference_pose.h"
#include "envs/testing/test_configs.h"

namespace juggle::soccer_juggle {
namespace {

// A shipped config and the physics step its world has.
struct World {
  const char* config;
  double timestep;
};
void PrintTo(const World& world, std::ostream* os) {
  *os << world.config << " (" << world.timestep << " s)";
}

class PhysicsTest : public ::testing::TestWithParam<World> {
 protected:
  void SetUp() override {
    spec_ = testing::LoadSpec(GetParam().config);
    ASSERT_NE(spec_, nullptr);
    m_ = spec_->model();
    d_ = mj_makeData(m_);
    standing_ = StandingPose(*spec_);
    FreezeCharacter();
  }
  void TearDown() override { mj_deleteData(d_); }

  // Holds the character at the standing pose (a static obstacle for the ball).
  void FreezeCharacter() {
    mju_copy(d_->qpos, standing_.data(), kCharacterNq);
    mju_zero(d_->qvel, kCharacterNv);
  }
  double* ball_pos() { return d_->qpos + spec_->ball_qpos(); }
  double* ball_vel() { return d_->qvel + spec_->ball_dof(); }
  void PlaceBall(double x, double y, double z) {
    double* b = ball_pos();
    b[0] = x; b[1] = y; b[2] = z; b[3] = 1; b[4] = b[5] = b[6] = 0;
    mju_zero(ball_vel(), 6);
    mj_forward(m_, d_);
  }

  std::shared_ptr<const JuggleSpec> spec_;
  const mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  CharacterPose standing_{};
};

TEST_P(PhysicsTest, BallDroppedOnFootBouncesWithRestitutionPointEight) {
  // A ball falling straight onto a standing foot would graze the shin first (the foot reaches
  // only 0.13 m ahead of the leg axis), so this copy of the model leaves only the foot solid.
  mjModel* copy = mj_copyModel(nullptr, m_);
  for (const char* geom : {"right_shin", "right_thigh", "left_shin", "left_thigh"}) {
    const int g = mj_name2id(copy, mjOBJ_GEOM, geom);
    copy->geom_contype[g] = copy->geom_conaffinity[g] = 0;
  }
  mj_deleteData(d_);
  m_ = copy;
  d_ = mj_makeData(m_);
  FreezeCharacter();
  mj_forward(m_, d_);
  const int foot = mj_name2id(m_, mjOBJ_BODY, "right_ankle");
  const int foot_geom = mj_name2id(m_, mjOBJ_GEOM, "right_foot");
  ASSERT_GE(foot, 0);
  // Top of the foot box: its centre height plus its half height (box axes: y is up).
  const double top = d_->geom_xpos[3 * foot_geom + 2] + m_->geom_size[3 * foot_geom + 1];
  const double x = d_->geom_xpos[3 * foot_geom], y = d_->geom_xpos[3 * foot_geom + 1];
  double restitution_sum = 0;
  const int kDrops = 5;
  for (int drop = 0; drop < kDrops; ++drop) {
    // Drop heights 1.9 mm apart sample where in a 2.5-ms step the impact falls (and in a 5-ms
    // one: the ball falls ~18 mm per step there).
    FreezeCharacter();
    PlaceBall(x, y, top + 0.11 + 0.6 + 0.0019 * drop);
    double v_in = 0, v_out = 0;
    bool touched = false;
    for (int i = 0; i < 2000; ++i) {
      const double vz_before = ball_vel()[2];
      mj_step(m_, d_);
      FreezeCharacter();
      bool contact = false;
      for (int c = 0; c < d_->ncon; ++c) {
        const int g1 = d_->contact[c].geom1, g2 = d_->contact[c].geom2;
        if ((g1 == spec_->ball_geom() && m_->geom_bodyid[g2] == foot) ||
            (g2 == spec_->ball_geom() && m_->geom_bodyid[g1] == foot)) {
          contact = true;
        }
      }
      if (contact && !touched) {
        touched = true;
        v_in = vz_before;
      }
      if (touched && !contact) {
        v_out = ball_vel()[2];
        break;
      }
    }
    ASSERT_TRUE(touched) << "ball never reached the foot";
    ASSERT_LT(v_in, -2.0);
    restitution_sum += -v_out / v_in;
  }
  EXPECT_NEAR(restitution_sum / kDrops, 0.8, 0.05);
  mj_deleteData(d_);
  d_ = mj_makeData(spec_->model());
  m_ = spec_->model();
  mj_deleteModel(copy);
}

TEST_P(PhysicsTest, FreeFallTimeMatchesBallisticFormulaWithinOneControlStep) {
  // Far from the character and high enough to touch nothing.
  const double h = 1.0, z0 = 3.0;
  PlaceBall(3.0, 3.0, z0);
  int steps = 0;
  while (ball_pos()[2] > z0 - h && steps < 10000) {
    mj_step(m_, d_);
    ++steps;
  }
  const double t = steps * m_->opt.timestep;
  const double expected = std::sqrt(2 * h / 9.81);
  EXPECT_NEAR(t, expected, spec_->control_dt());
  EXPECT_NEAR(t, expected, 2 * m_->opt.timestep);  // in fact within one physics step
}

TEST_P(PhysicsTest, ModelHasDeepMimicSizesAndMass) {
  EXPECT_EQ(m_->nq, kCharacterNq + 7);
  EXPECT_EQ(m_->nv, kCharacterNv + 6);
  double character_mass = 0;
  for (int b = 1; b < m_->nbody; ++b) {
    if (b != spec_->ball_body()) character_mass += m_->body_mass[b];
  }
  EXPECT_NEAR(character_mass, 45.0, 1e-9);
  EXPECT_NEAR(m_->body_mass[spec_->ball_body()], 0.45, 1e-12);
  EXPECT_NEAR(m_->geom_size[3 * spec_->ball_geom()], 0.11, 1e-12);
  // Hollow-sphere inertia 2/3·m·r².
  EXPECT_NEAR(m_->body_inertia[3 * spec_->ball_body()], 2.0 / 3.0 * 0.45 * 0.11 * 0.11, 1e-5);
  EXPECT_DOUBLE_EQ(m_->opt.timestep, GetParam().timestep);
  EXPECT_DOUBLE_EQ(spec_->control_dt(), 0.02);
}

TEST_P(PhysicsTest, CharacterDoesNotCollideWithItself) {
  // Cross the legs through each other: no self contacts may be generated.
  CharacterPose crossed = standing_;
  SetBallJointAxisRotation(*spec_, kRightHip, 0, 0.6, &crossed);
  SetBallJointAxisRotation(*spec_, kLeftHip, 0, -0.6, &crossed);
  mju_copy(d_->qpos, crossed.data(), kCharacterNq);
  PlaceBall(5, 5, 5);
  const int ball = spec_->ball_body();
  for (int c = 0; c < d_->ncon; ++c) {
    const int b1 = m_->geom_bodyid[d_->contact[c].geom1];
    const int b2 = m_->geom_bodyid[d_->contact[c].geom2];
    EXPECT_TRUE(b1 == 0 || b2 == 0 || b1 == ball || b2 == ball)
        << "self contact between bodies " << b1 << " and " << b2;
  }
}

INSTANTIATE_TEST_SUITE_P(Worlds, PhysicsTest,
                         ::testing::Values(World{"right_foot", 0.0025},
                                           World{"right_foot_planner_300hz", 1.0 / 300},
                                           World{"right_foot_planner_250hz", 0.004},
                                           World{"right_foot_planner_200hz", 0.005}),
                         [](const ::testing::TestParamInfo<World>& info) {
                           return "At" + std::to_string(std::lround(1 / info.param.timestep)) +
                                  "Hz";
                         });

}  // namespace
}  // namespace juggle::soccer_juggle
