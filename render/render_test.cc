// Offscreen rendering, video and PNG output, recording and replay.
#include "render/render_job.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "absl/strings/str_cat.h"
#include "common/testing/constant_policy.h"
#include "envs/registry.h"
#include "eval/controller.h"
#include "eval/episode_runner.h"
#include "record/trajectory.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "render/image.h"
#include "render/renderer.h"
#include "render/video_writer.h"
#include "envs/soccer_juggle/env.h"
#include "envs/testing/test_configs.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;
using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleSpec;
using soccer_juggle::kNumActions;

const char kConfig[] = "render/testdata/right_foot.textproto";

std::shared_ptr<const JuggleSpec> LoadTestSpec() {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(testing::RepoPath(kConfig));
  EXPECT_TRUE(config.ok()) << config.status();
  if (!config.ok()) return nullptr;
  absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec = JuggleSpec::Create(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return spec.ok() ? *spec : nullptr;
}

std::string TempPath(const std::string& name) {
  const char* dir = std::getenv("TEST_TMPDIR");
  return absl::StrCat(dir ? dir : "/tmp", "/juggle_render_test_", getpid(), "_", name);
}

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs a shell command and returns its stdout.
std::string Capture(const std::string& command) {
  std::string out;
  FILE* p = popen(command.c_str(), "r");
  if (p == nullptr) return out;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  pclose(p);
  return out;
}

double Variance(const Image& image) {
  double sum = 0, sum2 = 0;
  for (uint8_t v : image.rgb) {
    sum += v;
    sum2 += double(v) * v;
  }
  const double n = image.rgb.size();
  return sum2 / n - (sum / n) * (sum / n);
}

bool Differs(const Image& a, const Image& b, int x, int y, int threshold = 24) {
  const uint8_t* p = a.pixel(x, y);
  const uint8_t* q = b.pixel(x, y);
  return std::abs(p[0] - q[0]) + std::abs(p[1] - q[1]) + std::abs(p[2] - q[2]) > threshold;
}

class RenderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    spec_ = LoadTestSpec();
    ASSERT_NE(spec_, nullptr);
    down_ = *spec_->graph().FindNode("right_foot_down");
  }
  std::unique_ptr<Renderer> MakeRenderer(int width = 640, int height = 480) {
    RenderOptions options;
    options.width = width;
    options.height = height;
    options.track_body = spec_->root_body();
    absl::StatusOr<std::unique_ptr<Renderer>> r = Renderer::Create(spec_->model(), options);
    EXPECT_TRUE(r.ok()) << r.status();
    return r.ok() ? *std::move(r) : nullptr;
  }
  RenderJobOptions JobOptions() const {
    RenderJobOptions o;
    o.config_path = testing::RepoPath(kConfig);
    o.start_node = "right_foot_down";
    return o;
  }

  // A recorded rollout of `seconds` from stream (seed, 0, 0), episodes starting at the DOWN
  // node, with `policy`'s mean action (zero action if null).
  Trajectory Rollout(double seconds, uint64_t seed, const EigenPolicy* policy = nullptr) {
    std::unique_ptr<Controller> controller;
    if (policy != nullptr) {
      controller = std::make_unique<PolicyController>(
          std::shared_ptr<const EigenPolicy>(policy, [](const EigenPolicy*) {}));
    } else {
      controller = std::make_unique<ZeroController>(kNumActions);
    }
    absl::StatusOr<Trajectory> t =
        RecordRollout(spec_, controller.get(), seconds, seed, down_, kConfig);
    EXPECT_TRUE(t.ok()) << t.status();
    return t.ok() ? *std::move(t) : Trajectory();
  }

  std::shared_ptr<const JuggleSpec> spec_;
  int down_ = -1;
};

// A tall pattern's apex fits the frame: the camera rises and backs off for a high top, and a
// top the default framing already shows changes nothing.
TEST_F(RenderTest, FitHeightFramesATallPatternAndLeavesALowOneAlone) {
  std::unique_ptr<Renderer> renderer = MakeRenderer();
  ASSERT_NE(renderer, nullptr);
  const RenderOptions before = renderer->options();
  renderer->FitHeight(1.4);  // the soccer ball's apex
  EXPECT_EQ(renderer->options().lookat_height, before.lookat_height);
  EXPECT_EQ(renderer->options().distance, before.distance);
  renderer->FitHeight(4.0);
  const double half_fovy = 0.5 * spec_->model()->vis.global.fovy * mjPI / 180.0;
  EXPECT_DOUBLE_EQ(renderer->options().lookat_height, 2.1);
  // From the look-at point, the ray to the apex plus margin is inside half the field of view.
  EXPECT_LE(std::atan((4.2 - 2.1) / renderer->options().distance), half_fovy);
  EXPECT_GT(renderer->options().distance, before.distance);
}

TEST_F(RenderTest, FrameShowsAnUprightHumanoidSilhouetteInTheCentre) {
  std::unique_ptr<Renderer> renderer = MakeRenderer();
  ASSERT_NE(renderer, nullptr);
  AdaptiveWalk walk(&spec_->graph());
  JuggleEnv env(spec_, Rng(3));
  env.ResetAt(down_, walk);
  Image with, without;
  ASSERT_TRUE(renderer->Render(env.data(), "", "", &with).ok());
  EXPECT_GT(Variance(with), 200.0);

  // Same camera (it follows the root's x, y only), character sunk 100 m below the floor.
  std::unique_ptr<mjData, void (*)(mjData*)> away(mj_makeData(spec_->model()), mj_deleteData);
  mju_copy(away->qpos, env.data()->qpos, spec_->model()->nq);
  away->qpos[2] -= 100;
  mj_forward(spec_->model(), away.get());
  ASSERT_TRUE(renderer->Render(away.get(), "", "", &without).ok());

  int centre_diff = 0, x0 = with.width, x1 = -1, y0 = with.height, y1 = -1;
  for (int y = 0; y < with.height; ++y) {
    for (int x = 0; x < with.width; ++x) {
      if (!Differs(with, without, x, y)) continue;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
      if (x >= with.width / 4 && x < 3 * with.width / 4 && y >= with.height / 4 &&
          y < 3 * with.height / 4) {
        ++centre_diff;
      }
    }
  }
  const int centre_pixels = with.width * with.height / 4;
  EXPECT_GT(centre_diff, centre_pixels / 20) << "character silhouette missing from the centre";
  // Upright: the silhouette (and its shadow-free footprint) is taller than wide, and it spans
  // a good part of the image height.
  ASSERT_GE(x1, x0);
  EXPECT_GT(y1 - y0, 1.3 * (x1 - x0)) << "bbox x " << x0 << ".." << x1 << " y " << y0 << ".."
                                     << y1;
  EXPECT_GT(y1 - y0, with.height / 3);
}

TEST_F(RenderTest, Mp4OfTwoSecondsHasSixtyFrames) {
  RenderJobOptions o = JobOptions();
  o.seconds = 2;
  o.out = TempPath("two_seconds.mp4");
  absl::StatusOr<RenderJobReport> report = RunRenderJob(o);
  ASSERT_TRUE(report.ok()) << report.status();
  EXPECT_EQ(report->frames, 60);
  const std::string probe = "ffprobe -v error -count_frames -select_streams v:0 "
                            "-show_entries stream=nb_read_frames,width,height,codec_name "
                            "-of csv=p=0 " + ShellQuote(o.out);
  EXPECT_EQ(Capture(probe), "h264,640,480,60\n");
  std::remove(o.out.c_str());
}

TEST_F(RenderTest, ReplayedTrajectoryRendersTheFramesOfTheLiveSimulation) {
  std::unique_ptr<Renderer> renderer = MakeRenderer(320, 240);
  ASSERT_NE(renderer, nullptr);
  const Trajectory live = Rollout(1.0, 7);
  const std::string path = TempPath("live.traj");
  ASSERT_TRUE(WriteTrajectory(live, path).ok());
  absl::StatusOr<Trajectory> replay = ReadTrajectory(path);
  ASSERT_TRUE(replay.ok()) << replay.status();
  std::remove(path.c_str());
  ASSERT_EQ(replay->num_samples(), live.num_samples());
  EXPECT_EQ(replay->channels[replay->FindChannel("node")].labels,
            live.channels[live.FindChannel("node")].labels);
  EXPECT_EQ(replay->config_path, live.config_path);

  // Independent path: step an env by hand and render its own state after k control steps.
  AdaptiveWalk walk(&spec_->graph());
  JuggleEnv env(spec_, Rng::ForStream(7, 0, 0));
  env.ResetAt(down_, walk);
  const float zero[kNumActions] = {0};
  constexpr int kSteps = 10;
  for (int i = 0; i < kSteps; ++i) ASSERT_EQ(env.Step(zero, walk).outcome, Outcome::kRunning);
  std::unique_ptr<mjData, void (*)(mjData*)> state(mj_makeData(spec_->model()), mj_deleteData);
  mju_copy(state->qpos, env.data()->qpos, spec_->model()->nq);
  mj_forward(spec_->model(), state.get());  // env's xpos lags its qpos by one substep
  Image from_env, from_replay;
  ASSERT_TRUE(renderer->Render(state.get(), "", "", &from_env).ok());
  std::unique_ptr<mjData, void (*)(mjData*)> scratch(mj_makeData(spec_->model()), mj_deleteData);
  PoseAt(spec_->model(), *replay, kSteps * spec_->control_dt(), scratch.get());
  ASSERT_TRUE(renderer->Render(scratch.get(), "", "", &from_replay).ok());
  EXPECT_TRUE(from_env.rgb == from_replay.rgb);

  // Every video frame time, live vs replay, including interpolated ones.
  for (double t : {0.0, 1.0 / 30, 7.0 / 30, 0.5, 29.0 / 30}) {
    Image a, b;
    ASSERT_TRUE(RenderFrame(spec_->model(), live, t, scratch.get(), renderer.get(), &a).ok());
    ASSERT_TRUE(RenderFrame(spec_->model(), *replay, t, scratch.get(), renderer.get(), &b).ok());
    EXPECT_TRUE(a.rgb == b.rgb) << "t=" << t;
  }
}

TEST_F(RenderTest, RecordThenReplayJobWritesTheSamePngAndASmallSheet) {
  RenderJobOptions live = JobOptions();
  live.seconds = 1.5;
  live.out = TempPath("live.png");
  live.png_time = 0.7;
  live.record = TempPath("rollout.traj");
  live.sheet = TempPath("sheet.png");
  absl::StatusOr<RenderJobReport> a = RunRenderJob(live);
  ASSERT_TRUE(a.ok()) << a.status();
  EXPECT_EQ(a->frames, 1 + 12);

  RenderJobOptions replay;
  replay.replay = live.record;  // config from the recording
  replay.out = TempPath("replay.png");
  replay.png_time = 0.7;
  absl::StatusOr<RenderJobReport> b = RunRenderJob(replay);
  ASSERT_TRUE(b.ok()) << b.status();
  const std::string live_png = ReadAll(live.out);
  EXPECT_GT(live_png.size(), 1000u);
  EXPECT_TRUE(live_png == ReadAll(replay.out));

  struct stat st;
  ASSERT_EQ(stat(live.sheet.c_str(), &st), 0);
  EXPECT_LT(st.st_size, 500 * 1000);
  for (const std::string& p : {live.out, live.record, live.sheet, replay.out}) {
    std::remove(p.c_str());
  }
}

TEST(ImageTest, PngDecodesToTheSamePixelsWithFfmpeg) {
  Image image;
  image.Resize(37, 21);  // odd sizes exercise row strides and filters
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      uint8_t* p = &image.rgb[3 * (y * image.width + x)];
      p[0] = static_cast<uint8_t>(7 * x);
      p[1] = static_cast<uint8_t>(11 * y + x * x);
      p[2] = static_cast<uint8_t>((x * 31) ^ (y * 17));
    }
  }
  const std::string path = TempPath("pattern.png");
  ASSERT_TRUE(WritePng(path, image).ok());
  const std::string raw = Capture("ffmpeg -v error -i " + ShellQuote(path) +
                                  " -f rawvideo -pix_fmt rgb24 -");
  std::remove(path.c_str());
  EXPECT_TRUE(raw == std::string(image.rgb.begin(), image.rgb.end()));
}

TEST_F(RenderTest, MissingFfmpegIsAnErrorThatNamesThePackage) {
  const std::string old_path = std::getenv("PATH");
  setenv("PATH", "/nonexistent", 1);
  RenderJobOptions o = JobOptions();
  o.out = TempPath("never.mp4");
  absl::StatusOr<RenderJobReport> r = RunRenderJob(o);
  setenv("PATH", old_path.c_str(), 1);
  EXPECT_EQ(r.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(r.status().message(), HasSubstr("apt-get install ffmpeg"));
}

TEST_F(RenderTest, UnwritableOutputIsAnErrorBeforeSimulating) {
  RenderJobOptions o = JobOptions();
  o.out = "/nonexistent-dir/frame.png";
  absl::StatusOr<RenderJobReport> r = RunRenderJob(o);
  EXPECT_EQ(r.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(r.status().message(), HasSubstr("cannot write /nonexistent-dir/frame.png"));
}

TEST_F(RenderTest, UnknownOutputExtensionIsRejected) {
  RenderJobOptions o = JobOptions();
  o.out = TempPath("frame.gif");
  EXPECT_EQ(RunRenderJob(o).status().code(), absl::StatusCode::kInvalidArgument);
}

TEST_F(RenderTest, TruncatedRecordingIsRejected) {
  const Trajectory t = Rollout(0.1, 1);
  const std::string path = TempPath("truncated.traj");
  ASSERT_TRUE(WriteTrajectory(t, path).ok());
  ASSERT_EQ(truncate(path.c_str(), ReadAll(path).size() - 3), 0);
  absl::StatusOr<Trajectory> r = ReadTrajectory(path);
  std::remove(path.c_str());
  EXPECT_EQ(r.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(r.status().message(), HasSubstr("truncated"));
}

// A policy with constant, clearly non-zero mean actions: tanh(0.5) for every action.
std::shared_ptr<const EigenPolicy> ConstantPolicy(int obs_dim) {
  return std::make_shared<const EigenPolicy>(juggle::testing::ConstantPolicy(obs_dim, kNumActions, 0.5f));
}

TEST_F(RenderTest, PolicyRolloutDiffersFromZeroActionRollout) {
  const Trajectory zero = Rollout(0.3, 7);
  const auto policy = ConstantPolicy(spec_->obs_dim());
  const Trajectory acted = Rollout(0.3, 7, policy.get());
  ASSERT_GT(zero.num_samples(), 10);
  ASSERT_GT(acted.num_samples(), 10);
  // Same start, different motion once the policy's torques act (0.2 s in).
  EXPECT_EQ(0, std::memcmp(zero.qpos_at(0), acted.qpos_at(0), zero.nq * sizeof(double)));
  double diff = 0;
  for (int i = 0; i < zero.nq; ++i) diff += std::abs(zero.qpos_at(10)[i] - acted.qpos_at(10)[i]);
  EXPECT_GT(diff, 0.05);
}

}  // namespace
}  // namespace juggle
