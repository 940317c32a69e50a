// The trajectory format: a bit-exact round trip, clear errors for damaged files, and poses
// interpolated between samples (exact at the samples) on a tiny inline model.
#include "record/trajectory.h"

#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "record/testing/inline_model.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;

// A free body and a hinge: qpos = [x y z qw qx qy qz, angle].
constexpr char kModel[] = R"(
<mujoco>
  <worldbody>
    <body name="root"><freejoint/><geom size="0.1"/>
      <body pos="0 0 0.3"><joint name="hinge" type="hinge"/><geom size="0.05"/></body>
    </body>
  </worldbody>
</mujoco>)";

std::unique_ptr<mjModel, testing::ModelDeleter> LoadInlineModel() {
  return testing::LoadInlineModel(kModel);
}

// Two episodes: episode 0 has samples at t = 0, 0.1, 0.2 (ends "fell"), episode 1 at 0.2, 0.3.
Trajectory TwoEpisodes() {
  TrajectoryBuilder b("test_family", "configs/x.textproto", 0.1, 8,
                      {"running", "time_limit", "diverged", "fell"},
                      {{"node", {"down", "up"}}, {"phase", {}}});
  const double qa[8] = {0, 0, 1, 1, 0, 0, 0, 0.0};
  const double qb[8] = {0.2, 0, 1, std::cos(0.5), std::sin(0.5), 0, 0, 1.0};  // 1 rad about x
  const double n0[2] = {0, 0.25}, n1[2] = {1, 0.75};
  b.Append(0.0, 0, 0.0, Outcome::kRunning, n0, qa);
  b.Append(0.1, 0, 0.1, Outcome::kRunning, n1, qb);
  b.Append(0.2, 0, 0.2, FamilyOutcome(0), n1, qa);
  b.Append(0.2, 1, 0.0, Outcome::kRunning, n0, qb);
  b.Append(0.3, 1, 0.1, Outcome::kTimeLimit, n0, qa);
  return b.Take();
}

std::string TempPath(const std::string& name) { return ::testing::TempDir() + "/" + name; }

TEST(TrajectoryTest, WriteThenReadGivesBitIdenticalSamplesAndHeader) {
  const Trajectory t = TwoEpisodes();
  const std::string path = TempPath("round_trip.traj");
  ASSERT_TRUE(WriteTrajectory(t, path).ok());
  absl::StatusOr<Trajectory> r = ReadTrajectory(path);
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->family, "test_family");
  EXPECT_EQ(r->config_path, "configs/x.textproto");
  EXPECT_EQ(r->control_dt, 0.1);
  EXPECT_EQ(r->nq, 8);
  ASSERT_EQ(r->num_channels(), 5);
  EXPECT_EQ(r->channels[3].name, "node");
  EXPECT_EQ(r->channels[3].labels, (std::vector<std::string>{"down", "up"}));
  EXPECT_TRUE(r->channels[4].labels.empty());
  EXPECT_EQ(r->time, t.time);
  EXPECT_EQ(r->values, t.values);
  EXPECT_EQ(r->qpos, t.qpos);
  EXPECT_EQ(r->Label(2, kOutcomeChannel), "fell");
  EXPECT_EQ(r->Label(1, r->FindChannel("node")), "up");
  EXPECT_EQ(r->EpisodeEnd(0), 2);
  EXPECT_EQ(r->EpisodeEnd(1), 4);
  EXPECT_EQ(r->EpisodeEnd(2), -1);
}

TEST(TrajectoryTest, TruncatedFileIsRejectedNamingTheFile) {
  const std::string path = TempPath("truncated.traj");
  ASSERT_TRUE(WriteTrajectory(TwoEpisodes(), path).ok());
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes.substr(0, bytes.size() - 5);
  absl::StatusOr<Trajectory> r = ReadTrajectory(path);
  ASSERT_EQ(r.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(r.status().message()), HasSubstr(path));
  EXPECT_THAT(std::string(r.status().message()), HasSubstr("truncated"));
}

TEST(TrajectoryTest, ARecordCountWhoseByteSizeOverflowsIsRejectedNotAllocated) {
  // 2^61 records of 5+ doubles: records × doubles × 8 wraps to a small number.
  const std::string path = TempPath("hostile.traj");
  ASSERT_TRUE(WriteTrajectory(TwoEpisodes(), path).ok());
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  const size_t data = bytes.find("\ndata ");
  ASSERT_NE(data, std::string::npos) << "the header's data line";
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      << bytes.substr(0, data) << "\ndata 2305843009213693952\n";
  absl::StatusOr<Trajectory> r = ReadTrajectory(path);
  ASSERT_EQ(r.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(r.status().message()), HasSubstr("truncated"));
}

TEST(TrajectoryTest, OldVersionAndWrongMagicAreRejected) {
  const std::string old_path = TempPath("v1.traj");
  std::ofstream(old_path) << "juggle-trajectory 1 record_doubles=56 nq=43\n";
  EXPECT_THAT(std::string(ReadTrajectory(old_path).status().message()), HasSubstr("version 1"));
  const std::string png = TempPath("not.traj");
  std::ofstream(png) << "\x89PNG\r\n";
  EXPECT_THAT(std::string(ReadTrajectory(png).status().message()), HasSubstr("bad magic"));
  EXPECT_EQ(ReadTrajectory(TempPath("missing.traj")).status().code(), absl::StatusCode::kNotFound);
}

TEST(TrajectoryTest, CategoricalValueOutsideItsLabelsIsRejected) {
  Trajectory t = TwoEpisodes();
  t.values[1 * t.num_channels() + 3] = 7;  // node 7 of 2
  const std::string path = TempPath("bad_node.traj");
  ASSERT_TRUE(WriteTrajectory(t, path).ok());
  EXPECT_THAT(std::string(ReadTrajectory(path).status().message()),
              HasSubstr("record 1: node 7 outside its 2 labels"));
}

TEST(TrajectoryTest, LabelsThatWouldBreakTheHeaderCannotBeWritten) {
  Trajectory t = TwoEpisodes();
  t.channels[3].labels[0] = "two words";
  EXPECT_EQ(WriteTrajectory(t, TempPath("bad_label.traj")).code(),
            absl::StatusCode::kInvalidArgument);
}

TEST(TrajectoryTest, PoseAtASampleIsItsQposAndBetweenSamplesInterpolates) {
  auto model = LoadInlineModel();
  ASSERT_NE(model, nullptr);
  ASSERT_EQ(model->nq, 8);
  const Trajectory t = TwoEpisodes();
  std::unique_ptr<mjData, void (*)(mjData*)> d(mj_makeData(model.get()), mj_deleteData);
  FrameInfo at = PoseAt(model.get(), t, 0.1, d.get());
  EXPECT_EQ(at.sample, 1);
  EXPECT_EQ(0, std::memcmp(d->qpos, t.qpos_at(1), 8 * sizeof(double)));
  // Halfway between samples 0 and 1: position and hinge linear, the free joint's rotation half.
  at = PoseAt(model.get(), t, 0.05, d.get());
  EXPECT_EQ(at.sample, 0);
  EXPECT_NEAR(at.episode_time, 0.05, 1e-12);
  EXPECT_NEAR(d->qpos[0], 0.1, 1e-12);
  EXPECT_NEAR(d->qpos[7], 0.5, 1e-12);
  EXPECT_NEAR(d->qpos[3], std::cos(0.25), 1e-9);
  EXPECT_NEAR(d->qpos[4], std::sin(0.25), 1e-9);
  // At a reset (t = 0.2) the new episode is shown; after the end, the last sample.
  at = PoseAt(model.get(), t, 0.2, d.get());
  EXPECT_EQ(at.episode, 1);
  EXPECT_EQ(0, std::memcmp(d->qpos, t.qpos_at(3), 8 * sizeof(double)));
  at = PoseAt(model.get(), t, 9.0, d.get());
  EXPECT_EQ(at.sample, 4);
}

TEST(TrajectoryTest, AppendEpisodeRenumbersAndShiftsToTheEnd) {
  const Trajectory source = TwoEpisodes();
  Trajectory into = TwoEpisodes();
  AppendEpisode(source, 1, 5, &into);
  ASSERT_EQ(into.num_samples(), 7);
  EXPECT_EQ(into.episode(5), 5);
  EXPECT_NEAR(into.time[5], 0.3, 1e-12);  // starts where `into` ended
  EXPECT_NEAR(into.time[6], 0.4, 1e-12);
  EXPECT_EQ(0, std::memcmp(into.qpos_at(6), source.qpos_at(4), 8 * sizeof(double)));
}

}  // namespace
}  // namespace juggle
