// The replay page's data on a tiny inline model: body transforms as mj_forward gives them,
// ball contacts found where (and only where) the ball touches, channel changes as events,
// episode selection, clear errors, and a page whose inlined scripts cannot close early.
#include "export/replay.h"

#include <cmath>
#include <cstring>
#include <memory>
#include <string>

#include "absl/strings/str_cat.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "record/testing/inline_model.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;

// A floor, a character (free root + hinged arm) and a ball: qpos = root 7, arm 1, ball 7.
constexpr char kModel[] = R"(
<mujoco>
  <asset><material name="blue" rgba="0.1 0.2 0.9 1"/></asset>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <body name="root" pos="0 0 1"><freejoint/>
      <geom type="capsule" size="0.05 0.2" material="blue"/>
      <body name="arm" pos="0 0 0.3"><joint name="hinge" type="hinge" axis="0 1 0"/>
        <geom name="hand" type="box" size="0.1 0.02 0.02" pos="0.1 0 0" rgba="1 0 0 1"/>
        <geom name="hidden" type="sphere" size="0.01" rgba="1 1 1 0"/>
      </body>
    </body>
    <body name="ball" pos="1 0 1"><freejoint/><geom type="sphere" size="0.1"/></body>
  </worldbody>
</mujoco>)";

std::unique_ptr<mjModel, testing::ModelDeleter> LoadInlineModel() {
  return testing::LoadInlineModel(kModel);
}

// Frame f: the arm at angle 0.1·f, the ball at height 1 - 0.3·f (touching the floor from
// frame 3 on: z ≤ radius). Episode 0: frames 0..3, episode 1: 4..5 (same time as frame 3).
// The node channel switches from "down" to "up" at frame 2.
Trajectory Recording() {
  TrajectoryBuilder b("test", "none.textproto", 0.02, 15, {"running", "time_limit", "diverged"},
                      {{"node", {"down", "up"}}, {"phase", {}}});
  for (int f = 0; f < 6; ++f) {
    const double ball_z = f < 3 ? 1 - 0.3 * f : 0.099;
    const double qpos[15] = {0.5, 0, 1, 1, 0, 0, 0, 0.1 * f, 1, 0, ball_z, 1, 0, 0, 0};
    const double annotations[2] = {f >= 2 && f < 4 ? 1.0 : 0.0, 0.1 * f};
    const int episode = f < 4 ? 0 : 1;
    const double time = 0.02 * (f < 4 ? f : f - 1);
    b.Append(time, episode, 0, f == 3 ? Outcome::kTimeLimit : Outcome::kRunning, annotations, qpos);
  }
  return b.Take();
}

TEST(ReplayTest, BodyTransformsAreTheWorldPosesOfEachSample) {
  auto m = LoadInlineModel();
  absl::StatusOr<ReplayData> r = BuildReplayData(m.get(), Recording());
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->body_names, (std::vector<std::string>{"root", "arm", "ball"}));
  EXPECT_EQ(r->follow, 0);
  ASSERT_EQ(r->num_frames(), 6);
  // The arm's origin is 0.3 m above the root; its orientation turns 0.1 rad per frame about y.
  const int nb = 3, frame = 2;
  EXPECT_NEAR(r->xpos[3 * (frame * nb + 1) + 0], 0.5, 1e-12);
  EXPECT_NEAR(r->xpos[3 * (frame * nb + 1) + 2], 1.3, 1e-12);
  EXPECT_NEAR(r->xquat[4 * (frame * nb + 1) + 0], std::cos(0.1), 1e-12);
  EXPECT_NEAR(r->xquat[4 * (frame * nb + 1) + 2], std::sin(0.1), 1e-12);
  EXPECT_NEAR(r->xpos[3 * (1 * nb + 2) + 2], 0.7, 1e-12);  // the ball at frame 1
}

TEST(ReplayTest, GeomsCarryTheirMaterialColourAndInvisibleOnesAreSkipped) {
  auto m = LoadInlineModel();
  absl::StatusOr<ReplayData> r = BuildReplayData(m.get(), Recording());
  ASSERT_TRUE(r.ok()) << r.status();
  ASSERT_EQ(r->geoms.size(), 4u);  // floor, capsule, hand, ball
  EXPECT_EQ(r->skipped_geoms, 1);
  EXPECT_EQ(r->geoms[0].type, "plane");
  EXPECT_EQ(r->geoms[0].body, -1);
  EXPECT_EQ(r->geoms[1].type, "capsule");
  EXPECT_FLOAT_EQ(r->geoms[1].rgba[2], 0.9f);  // the material's blue
  EXPECT_EQ(r->geoms[2].name, "hand");
  EXPECT_EQ(r->geoms[2].body, 1);
  EXPECT_DOUBLE_EQ(r->geoms[2].pos[0], 0.1);
  EXPECT_FLOAT_EQ(r->geoms[2].rgba[0], 1.0f);
}

TEST(ReplayTest, AMeshIsDrawnAsItsHullInItsGeomsFrameAndReachesThePage) {
  // A tetrahedron authored off the origin: MuJoCo moves its vertices to the volume's centroid
  // (for a tetrahedron, the mean of its vertices) and keeps the hull's four triangles.
  auto m = testing::LoadInlineModel(R"(
<mujoco>
  <asset><mesh name="tetra" vertex="1 1 1  1.3 1 1  1 1.3 1  1 1 1.3"/></asset>
  <worldbody><body name="boot"><freejoint/><geom name="boot" type="mesh" mesh="tetra"/></body>
  </worldbody>
</mujoco>)");
  const ReplayScene scene = BuildReplayScene(m.get());
  ASSERT_EQ(scene.geoms.size(), 1u);
  EXPECT_EQ(scene.skipped_geoms, 0);
  const ReplayGeom& g = scene.geoms[0];
  EXPECT_EQ(g.type, "mesh");
  ASSERT_EQ(g.vertices.size(), 12u);
  ASSERT_EQ(g.faces.size(), 12u);
  for (int index : g.faces) EXPECT_TRUE(index >= 0 && index < 4) << index;
  for (int k = 0; k < 3; ++k) {
    const double mean = (g.vertices[k] + g.vertices[3 + k] + g.vertices[6 + k] + g.vertices[9 + k]) / 4;
    EXPECT_NEAR(mean, 0, 1e-6) << k;
  }
  const std::string json = ReplayGeomsJson(scene.geoms);
  EXPECT_THAT(json, HasSubstr("\"type\":\"mesh\""));
  EXPECT_THAT(json, HasSubstr("\"faces\":["));
  EXPECT_THAT(json, HasSubstr("\"vertices\":["));
}

TEST(ReplayTest, BallContactsAreFoundOnlyWhereTheBallTouches) {
  auto m = LoadInlineModel();
  absl::StatusOr<ReplayData> r = BuildReplayData(m.get(), Recording());
  ASSERT_TRUE(r.ok()) << r.status();
  std::vector<int> frames;
  for (const ReplayContact& c : r->contacts) {
    EXPECT_EQ(c.ball, "ball");
    EXPECT_EQ(c.other, "floor");
    frames.push_back(c.frame);
  }
  EXPECT_EQ(frames, (std::vector<int>{3, 4, 5}));
}

TEST(ReplayTest, NodeChangesEpisodeStartsAndEndingsBecomeEvents) {
  auto m = LoadInlineModel();
  absl::StatusOr<ReplayData> r = BuildReplayData(m.get(), Recording());
  ASSERT_TRUE(r.ok()) << r.status();
  std::vector<std::string> events;
  for (const ReplayEvent& e : r->events) {
    events.push_back(absl::StrCat(e.frame, ":", e.channel, "=", e.label));
  }
  EXPECT_EQ(events, (std::vector<std::string>{"0:episode=0", "0:node=down", "2:node=up",
                                              "3:outcome=time_limit", "4:episode=1",
                                              "4:node=down"}));
}

TEST(ReplayTest, OneEpisodeStartsAtTimeZero) {
  auto m = LoadInlineModel();
  absl::StatusOr<ReplayData> r = BuildReplayData(m.get(), Recording(), 1);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->samples, (std::vector<int>{4, 5}));
  ASSERT_EQ(r->time.size(), 2u);
  EXPECT_EQ(r->time[0], 0.0);
  EXPECT_NEAR(r->time[1], 0.02, 1e-12);
}

TEST(ReplayTest, RefusesEmptyRecordingsMissingEpisodesAndOtherModels) {
  auto m = LoadInlineModel();
  TrajectoryBuilder empty("test", "none.textproto", 0.02, 15, {"running"}, {});
  EXPECT_THAT(BuildReplayData(m.get(), empty.trajectory()).status().message(),
              HasSubstr("no samples"));
  EXPECT_THAT(BuildReplayData(m.get(), Recording(), 7).status().message(),
              HasSubstr("no episode 7 (episodes 0..1)"));
  Trajectory other = Recording();
  other.nq = 8;
  EXPECT_THAT(BuildReplayData(m.get(), other).status().message(),
              HasSubstr("nq 8 but the model 15"));
}

TEST(ReplayTest, JsonHoldsFixedPointTransformsAndTheChannels) {
  auto m = LoadInlineModel();
  absl::StatusOr<ReplayData> r = BuildReplayData(m.get(), Recording());
  ASSERT_TRUE(r.ok()) << r.status();
  const std::string json = ReplayJson(*r);
  EXPECT_THAT(json, HasSubstr("\"scale\":10000"));
  EXPECT_THAT(json, HasSubstr("\"bodies\":[\"root\",\"arm\",\"ball\"]"));
  EXPECT_THAT(json, HasSubstr("{\"name\":\"node\",\"labels\":[\"down\",\"up\"]}"));
  // Frame 0: root at (0.5, 0, 1) -> 5000,0,10000; the arm 0.3 m higher.
  EXPECT_THAT(json, HasSubstr("\"xpos\":[5000,0,10000,5000,0,13000,10000,0,10000,"));
  EXPECT_THAT(json, HasSubstr("\"time\":[0,200,400,600,600,800]"));
}

TEST(ReplayTest, InlinedScriptsCannotCloseTheirElementEarly) {
  auto m = LoadInlineModel();
  absl::StatusOr<ReplayData> r = BuildReplayData(m.get(), Recording());
  ASSERT_TRUE(r.ok()) << r.status();
  ReplayLibraries libs{"var three = '</script><b>';", "var orbit = 1;"};
  const std::string html = ReplayHtml(*r, libs, "a <title>");
  EXPECT_THAT(html, HasSubstr("var three = '<\\/script><b>';"));
  EXPECT_THAT(html, HasSubstr("<title>a &lt;title></title>"));
  EXPECT_THAT(html, ::testing::Not(HasSubstr("<!-- juggle:")));
  size_t closes = 0;
  for (size_t at = html.find("</script>"); at != std::string::npos;
       at = html.find("</script>", at + 1)) {
    ++closes;
  }
  EXPECT_EQ(closes, 5u);  // three.js, OrbitControls, the data, scene.js, replay.js
}

TEST(ReplayTest, MissingThreeJsNamesTheDebianPackage) {
  absl::StatusOr<ReplayLibraries> libs = LoadReplayLibraries("/nonexistent/three");
  EXPECT_EQ(libs.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(libs.status().message(), HasSubstr("apt-get install libjs-three"));
}

}  // namespace
}  // namespace juggle
