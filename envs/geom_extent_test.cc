#include "envs/geom_extent.h"

#include "envs/mujoco_model.h"
#include "envs/testing/test_configs.h"
#include "gtest/gtest.h"
#include "record/testing/inline_model.h"

namespace juggle {
namespace {

// A cuboid mesh authored away from the origin (1..1.6, 1..1.4, 1..1.2) in a body turned 90°
// about z: MuJoCo moves its vertices to the volume's centre and principal axes.
constexpr char kModel[] = R"(<mujoco>
  <asset>
    <mesh name="cuboid" vertex="1 1 1  1.6 1 1  1 1.4 1  1.6 1.4 1
                                1 1 1.2  1.6 1 1.2  1 1.4 1.2  1.6 1.4 1.2"/>
  </asset>
  <worldbody>
    <geom name="plane" type="plane" size="1 1 0.1"/>
    <body pos="0 0 2" euler="0 0 90">
      <geom name="box" type="box" size="0.3 0.05 0.2"/>
      <geom name="sphere" type="sphere" size="0.07"/>
      <geom name="capsule" type="capsule" size="0.05 0.2"/>
      <geom name="cylinder" type="cylinder" size="0.05 0.2"/>
      <geom name="mesh" type="mesh" mesh="cuboid"/>
    </body>
  </worldbody>
</mujoco>)";

testing::InlineModel Compile() { return testing::LoadInlineModel(kModel); }

TEST(GeomExtentTest, PrimitivesAreBoundedByTheirHalfSizesAndRadiiAboutTheirOwnCentre) {
  testing::InlineModel m = Compile();
  ASSERT_NE(m, nullptr);
  auto bounds = [&](const char* name) {
    return MeasureGeomBounds(m.get(), mj_name2id(m.get(), mjOBJ_GEOM, name));
  };
  EXPECT_EQ(bounds("box").half_extents, (std::array<double, 3>{0.3, 0.05, 0.2}));
  EXPECT_EQ(bounds("sphere").half_extents, (std::array<double, 3>{0.07, 0.07, 0.07}));
  EXPECT_NEAR(bounds("capsule").longest(), 0.25, 1e-12);
  EXPECT_DOUBLE_EQ(bounds("capsule").thinnest(), 0.05);
  EXPECT_DOUBLE_EQ(bounds("cylinder").longest(), 0.2);
  EXPECT_DOUBLE_EQ(bounds("box").thinnest(), 0.05);
  EXPECT_DOUBLE_EQ(bounds("box").longest(), 0.3);
  EXPECT_EQ(bounds("plane").half_extents, (std::array<double, 3>{0, 0, 0}));
  EXPECT_FALSE(bounds("box").mesh);
  // A primitive's centre is MuJoCo's geom_xpos, exactly.
  MjDataPtr d(mj_makeData(m.get()));
  mj_kinematics(m.get(), d.get());
  double centre[3];
  GeomBoundsCentre(bounds("capsule"), m.get(), d.get(), centre);
  const int capsule = mj_name2id(m.get(), mjOBJ_GEOM, "capsule");
  for (int k = 0; k < 3; ++k) EXPECT_EQ(centre[k], d->geom_xpos[3 * capsule + k]);
}

TEST(GeomExtentTest, AMeshIsBoundedWhereItsVerticesWereAuthoredInItsBody) {
  // The cuboid 1..1.6 × 1..1.4 × 1..1.2 in a body at (0, 0, 2) turned 90° about z: its bounds'
  // centre is (1.3, 1.2, 1.1) in the body, i.e. (-1.2, 1.3, 3.1) in the world, whatever frame
  // MuJoCo gives the mesh's geom (its volume's principal axes).
  testing::InlineModel m = Compile();
  ASSERT_NE(m, nullptr);
  const GeomBounds b = MeasureGeomBounds(m.get(), mj_name2id(m.get(), mjOBJ_GEOM, "mesh"));
  EXPECT_TRUE(b.mesh);
  const double half[3] = {0.3, 0.2, 0.1}, middle[3] = {1.3, 1.2, 1.1};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(b.half_extents[k], half[k], 1e-6) << k;  // the vertices are floats
    EXPECT_NEAR(b.centre_in_body[k], middle[k], 1e-6) << k;
  }
  MjDataPtr d(mj_makeData(m.get()));
  mj_kinematics(m.get(), d.get());
  double centre[3];
  GeomBoundsCentre(b, m.get(), d.get(), centre);
  EXPECT_NEAR(centre[0], -1.2, 1e-6);
  EXPECT_NEAR(centre[1], 1.3, 1e-6);
  EXPECT_NEAR(centre[2], 3.1, 1e-6);
}

TEST(GeomExtentTest, TheFootballBootIsBoundedByTheBoxFootWithAHigherTop) {
  // The pitch's boot (configs/models/football_pitch.xml) against the juggling scene's box: the
  // same length and sole, the same centre along the foot, a top raised to the collar (y 0.02).
  absl::StatusOr<MjModelPtr> pitch =
      LoadModelXml(testing::RepoPath("configs/models/football_pitch.xml"), "test");
  absl::StatusOr<MjModelPtr> scene =
      LoadModelXml(testing::RepoPath("configs/models/juggle_scene.xml"), "test");
  ASSERT_TRUE(pitch.ok()) << pitch.status();
  ASSERT_TRUE(scene.ok()) << scene.status();
  for (const char* foot : {"right_foot", "left_foot"}) {
    const int boot = mj_name2id(pitch->get(), mjOBJ_GEOM, foot);
    const int box = mj_name2id(scene->get(), mjOBJ_GEOM, foot);
    ASSERT_EQ((*pitch)->geom_type[boot], mjGEOM_MESH) << foot;
    ASSERT_EQ((*scene)->geom_type[box], mjGEOM_BOX) << foot;
    const GeomBounds b = MeasureGeomBounds(pitch->get(), boot);
    EXPECT_NEAR(b.half_extents[0], 0.0885, 1e-6);         // heel to toe
    EXPECT_NEAR(b.centre_in_body[0], 0.045, 1e-6);         // the box's centre along the foot
    EXPECT_NEAR(b.centre_in_body[1], (-0.05 + 0.02) / 2, 1e-6);  // sole to collar
    EXPECT_NEAR(b.half_extents[2], 0.048, 1e-6);          // the widest cross-section
    EXPECT_NEAR(b.longest(), MeasureGeomBounds(scene->get(), box).longest(), 1e-6);
  }
}

}  // namespace
}  // namespace juggle
