// The ballistic formulas against a free ball stepped in MuJoCo and against the flight's own
// equation, z(t) = z + vz·t − g·t²/2.
#include "envs/ballistic.h"

#include <cmath>
#include <string>

#include <mujoco/mujoco.h>

#include "envs/mujoco_model.h"
#include "gtest/gtest.h"
#include "record/testing/inline_model.h"

namespace juggle {
namespace {

constexpr double kG = 9.81;

// z(t) and ż(t) of the flight.
double HeightAt(double z, double vz, double t) { return z + vz * t - 0.5 * kG * t * t; }
double VerticalSpeedAt(double vz, double t) { return vz - kG * t; }

TEST(BallisticTest, SecondsToFallIsTheLaterRootOfTheFlight) {
  struct Case {
    double z, vz, h;
  };
  // Rising, falling, at rest; a height below the ball, and above it (reached on the way up).
  for (const Case& c : {Case{1.4, 0.0, 0.5}, Case{0.5, 4.0, 0.5}, Case{0.6, 3.0, 0.5},
                        Case{1.0, -2.0, 0.5}, Case{0.3, 5.0, 1.0}, Case{0.3, 5.0, 0.3}}) {
    const double t = SecondsToFall(c.vz, c.z - c.h, kG);
    EXPECT_NEAR(HeightAt(c.z, c.vz, t), c.h, 1e-12) << c.z << " " << c.vz << " " << c.h;
    EXPECT_LE(VerticalSpeedAt(c.vz, t), 0.0) << "on the way down";
    EXPECT_GE(t, 0.0);
  }
  // Thrown up at 3 m/s: back at its own height after 2·vz/g; from rest, √(2·drop/g).
  EXPECT_NEAR(SecondsToFall(3.0, 0.0, kG), 6.0 / kG, 1e-12);
  EXPECT_NEAR(SecondsToFall(0.0, 0.9, kG), std::sqrt(2 * 0.9 / kG), 1e-12);
  // A falling ball at the height: now.
  EXPECT_EQ(SecondsToFall(-2.0, 0.0, kG), 0.0);
  // 1 m/s up from 0.5 m peaks at 0.55 m: 2 m is out of reach.
  EXPECT_TRUE(std::isnan(SecondsToFall(1.0, 0.5 - 2.0, kG)));
}

TEST(BallisticTest, DescendingCrossingAndApexOfAFreeBallSteppedInMuJoCo) {
  // RK4 integrates a constant acceleration exactly: the stepped ball is the true flight.
  const std::string mjcf = R"(
    <mujoco>
      <option timestep="0.0005" integrator="RK4" gravity="0 0 -9.81"/>
      <worldbody>
        <body name="ball">
          <freejoint/>
          <geom type="sphere" size="0.11" mass="0.45" contype="0" conaffinity="0"/>
        </body>
      </worldbody>
    </mujoco>)";
  testing::InlineModel model = testing::LoadInlineModel(mjcf);
  ASSERT_NE(model, nullptr);
  MjDataPtr data(mj_makeData(model.get()));
  const double pos[3] = {0.2, -0.1, 0.55};  // above h, rising
  const double vel[3] = {0.8, 0.3, 4.2};
  const double h = 0.5;
  mju_copy(data->qpos, pos, 3);
  mju_copy(data->qvel, vel, 3);
  const BallisticCrossing predicted = DescendingCrossing(pos, vel, kG, h);
  const double apex = ApexHeight(pos[2], vel[2], kG);
  const double dt = model->opt.timestep;
  double highest = pos[2], prev_z = pos[2], t = 0;
  while (true) {
    mj_step(model.get(), data.get());
    t += dt;
    const double z = data->qpos[2];
    highest = std::max(highest, z);
    if (data->qvel[2] < 0 && prev_z >= h && z < h) break;  // crossed h on the way down
    prev_z = z;
    ASSERT_LT(t, 10.0) << "never came down";
  }
  // The crossing lies within the last step; its time and place to within a step's motion.
  const double fraction = (prev_z - h) / (prev_z - data->qpos[2]);
  const double crossing_t = t - dt + fraction * dt;
  EXPECT_NEAR(predicted.t, crossing_t, 1e-6);
  EXPECT_NEAR(predicted.x, pos[0] + vel[0] * crossing_t, 1e-6);
  EXPECT_NEAR(predicted.x, data->qpos[0] - vel[0] * (t - crossing_t), 1e-6);
  EXPECT_NEAR(predicted.y, data->qpos[1] - vel[1] * (t - crossing_t), 1e-6);
  EXPECT_NEAR(apex, highest, 1e-6);
}

TEST(BallisticTest, ABallBelowTheHeightThatNeverCrossesItCrossesNowWhereItIs) {
  const double pos[3] = {0.1, 0.2, 0.3};
  for (double vz : {-1.0, 0.0, 1.0}) {  // 1 m/s rises 5 cm: never reaches 0.5 m
    const double vel[3] = {1.0, -1.0, vz};
    const BallisticCrossing c = DescendingCrossing(pos, vel, kG, 0.5);
    EXPECT_EQ(c.t, 0.0) << vz;
    EXPECT_EQ(c.x, 0.1) << vz;
    EXPECT_EQ(c.y, 0.2) << vz;
  }
  EXPECT_EQ(ApexHeight(0.3, -1.0, kG), 0.3) << "coming down: the apex is behind it";
}

TEST(BallisticTest, ABallRisingThroughTheHeightCrossesOnItsWayDown) {
  // Just kicked from 0.45 m at 4 m/s: up through 0.5 m, apex, down through 0.5 m again.
  const double pos[3] = {0.0, 0.0, 0.45};
  const double vel[3] = {0.5, 0.1, 4.0};
  const BallisticCrossing c = DescendingCrossing(pos, vel, kG, 0.5);
  // Independently: the flight is symmetric about its apex at vz/g.
  const double up = (vel[2] - std::sqrt(vel[2] * vel[2] - 2 * kG * 0.05)) / kG;
  EXPECT_NEAR(c.t, 2 * vel[2] / kG - up, 1e-12);
  EXPECT_NEAR(pos[2] + vel[2] * c.t - 0.5 * kG * c.t * c.t, 0.5, 1e-12);
  EXPECT_NEAR(c.x, 0.5 * c.t, 1e-12);
}

}  // namespace
}  // namespace juggle
