#include "render/render_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "common/file_io.h"
#include "common/status_macros.h"
#include "envs/mujoco_model.h"
#include "envs/policy_config.h"
#include "envs/registry.h"
#include "eval/controller.h"
#include "eval/episode_runner.h"
#include "render/video_writer.h"

namespace juggle {
namespace {

using Clock = std::chrono::steady_clock;

bool IsPng(const std::string& path) { return absl::EndsWithIgnoreCase(path, ".png"); }
bool IsMp4(const std::string& path) { return absl::EndsWithIgnoreCase(path, ".mp4"); }

// Renders a frame and adds its wall time to `report`.
absl::Status TimedFrame(const mjModel* model, const Trajectory& t, double time, mjData* scratch,
                        Renderer* renderer, Image* out, RenderJobReport* report) {
  const auto start = Clock::now();
  RETURN_IF_ERROR(RenderFrame(model, t, time, scratch, renderer, out));
  report->render_seconds += std::chrono::duration<double>(Clock::now() - start).count();
  ++report->frames;
  return absl::OkStatus();
}

// The highest any ball (a body whose name starts with "ball") reaches over `t`'s samples (m);
// 0 without balls. Poses `scratch`.
double HighestBall(const mjModel* model, const Trajectory& t, mjData* scratch) {
  std::vector<int> balls;
  for (int b = 0; b < model->nbody; ++b) {
    const char* name = mj_id2name(model, mjOBJ_BODY, b);
    if (name != nullptr && absl::StartsWith(name, "ball")) balls.push_back(b);
  }
  double top = 0;
  for (int i = 0; !balls.empty() && i < t.num_samples(); ++i) {
    PoseAt(model, t, t.time[i], scratch);
    for (int b : balls) top = std::max(top, scratch->xpos[3 * b + 2]);
  }
  return top;
}

}  // namespace

absl::Status RenderFrame(const mjModel* model, const Trajectory& trajectory, double time,
                         mjData* scratch, Renderer* renderer, Image* out) {
  const FrameInfo info = PoseAt(model, trajectory, time, scratch);
  std::string ending = "";
  const int end = trajectory.EpisodeEnd(info.episode);
  if (end >= 0 && trajectory.outcome(end) != Outcome::kRunning) {
    ending = absl::StrFormat("  (%s at %.2f s)", trajectory.Label(end, kOutcomeChannel),
                             trajectory.value(end, kEpisodeTimeChannel));
  }
  // The family's channels (node, phase, ...), then time and episode.
  std::string labels, values;
  for (int c = kOutcomeChannel + 1; c < trajectory.num_channels(); ++c) {
    absl::StrAppend(&labels, trajectory.channels[c].name, "\n");
    absl::StrAppend(&values, trajectory.channels[c].labels.empty()
                                 ? absl::StrFormat("%.2f", trajectory.value(info.sample, c))
                                 : trajectory.Label(info.sample, c),
                    "\n");
  }
  absl::StrAppend(&labels, "time\nepisode");
  absl::StrAppend(&values, absl::StrFormat("%.2f s\n%d%s", info.episode_time, info.episode, ending));
  return renderer->Render(scratch, labels, values, out);
}

absl::StatusOr<RenderJobReport> RunRenderJob(const RenderJobOptions& o) {
  // Options and output paths first, so nothing is simulated for a run that cannot finish.
  if (o.out.empty() && o.sheet.empty() && o.record.empty()) {
    return absl::InvalidArgumentError("nothing to do: give --out=FILE.mp4|FILE.png, --sheet or "
                                      "--record");
  }
  if (!o.out.empty() && !IsPng(o.out) && !IsMp4(o.out)) {
    return absl::InvalidArgumentError(
        absl::StrCat("--out must end in .mp4 or .png, got ", o.out));
  }
  if (!o.sheet.empty() && !IsPng(o.sheet)) {
    return absl::InvalidArgumentError(absl::StrCat("--sheet must end in .png, got ", o.sheet));
  }
  if (!o.replay.empty() && !o.record.empty()) {
    return absl::InvalidArgumentError("--record and --replay exclude each other");
  }
  if (o.replay.empty() && !(o.seconds > 0)) {
    return absl::InvalidArgumentError(absl::StrCat("--seconds must be > 0, got ", o.seconds));
  }
  if (o.fps <= 0 || o.sheet_columns < 1 || o.sheet_rows < 1 || o.sheet_downscale < 1) {
    return absl::InvalidArgumentError("fps, sheet grid and downscale must be positive");
  }
  if (IsMp4(o.out) && (o.render.width % 2 || o.render.height % 2)) {
    return absl::InvalidArgumentError(absl::StrCat("MP4 needs an even width and height, got ",
                                                   o.render.width, "x", o.render.height));
  }
  if (IsMp4(o.out) && FindOnPath("ffmpeg").empty()) {
    return absl::FailedPreconditionError(
        "ffmpeg not found on PATH; MP4 output pipes frames to it: apt-get install ffmpeg");
  }
  for (const std::string& path : {o.out, o.sheet, o.record}) {
    if (!path.empty()) RETURN_IF_ERROR(CheckWritable(path));
  }

  // The rollout: recorded or simulated.
  Trajectory trajectory;
  std::string config_path = o.config_path;
  if (!o.replay.empty()) {
    ASSIGN_OR_RETURN(trajectory, ReadTrajectory(o.replay));
    if (trajectory.num_samples() == 0) {
      return absl::InvalidArgumentError(absl::StrCat(o.replay, ": recording has no samples"));
    }
    if (config_path.empty()) config_path = trajectory.config_path;
  }
  LoadedConfig config;
  if (o.config.has_value()) {
    config = *o.config;
  } else {
    ASSIGN_OR_RETURN(config, LoadConfigOrPolicy(config_path, nullptr));
  }
  ASSIGN_OR_RETURN(std::shared_ptr<const EnvSpec> spec, CreateEnvSpec(config));
  const mjModel* model = spec->model();
  const ControlGraph& graph = spec->graph();
  if (!o.replay.empty() && (trajectory.family != spec->family() || trajectory.nq != model->nq)) {
    return absl::InvalidArgumentError(absl::StrCat(
        o.replay, ": recorded with a ", trajectory.family, " model of nq ", trajectory.nq,
        ", but ", config_path, " makes a ", spec->family(), " model of nq ", model->nq,
        "; pass the config it was recorded with (--config)"));
  }
  int start_node = -1;
  if (!o.start_node.empty()) {
    const std::optional<int> n = graph.FindNode(o.start_node);
    if (!n.has_value() || graph.node(*n).spec.stage() != config::DOWN) {
      return absl::InvalidArgumentError(absl::StrCat(
          "--node=", o.start_node, ": not a DOWN node of ", config_path));
    }
    start_node = *n;
  }

  // A renderer only when frames are wanted (a record-only run needs no GL).
  std::unique_ptr<Renderer> renderer;
  if (!o.out.empty() || !o.sheet.empty()) {
    RenderOptions render = o.render;
    render.track_body = mj_name2id(model, mjOBJ_BODY, "root");
    ASSIGN_OR_RETURN(renderer, Renderer::Create(model, render));
  }
  if (o.replay.empty()) {
    const uint64_t seed = o.seed >= 0 ? static_cast<uint64_t>(o.seed) : config.run.seed();
    std::unique_ptr<Controller> controller;
    if (o.controller) {
      ASSIGN_OR_RETURN(controller, o.controller(spec, config));
    } else if (o.policy) {
      controller = std::make_unique<PolicyController>(o.policy);
    } else {
      controller = std::make_unique<ZeroController>(spec->act_dim());
    }
    ASSIGN_OR_RETURN(trajectory, RecordRollout(spec, controller.get(), o.seconds, seed,
                                               start_node, config_path));
  }

  RenderJobReport report;
  report.config_path = config_path;
  report.duration = trajectory.duration();
  report.episodes = trajectory.episode(trajectory.num_samples() - 1) + 1;
  for (int e = 0; e < report.episodes; ++e) {
    report.episode_outcomes.push_back(trajectory.Label(trajectory.EpisodeEnd(e), kOutcomeChannel));
  }
  if (renderer != nullptr) report.gl_renderer = renderer->gl_renderer();
  if (!o.record.empty()) RETURN_IF_ERROR(WriteTrajectory(trajectory, o.record));

  MjDataPtr scratch(mj_makeData(model));
  // Tall patterns (a 7-ball cascade's apex) stay in the frame.
  if (renderer != nullptr) renderer->FitHeight(HighestBall(model, trajectory, scratch.get()));
  Image frame;
  if (IsMp4(o.out)) {
    const double seconds = o.replay.empty() ? o.seconds : report.duration;
    const int num_frames = std::max(1, static_cast<int>(std::lround(seconds * o.fps)));
    ASSIGN_OR_RETURN(std::unique_ptr<VideoWriter> video,
                     VideoWriter::Open(o.out, o.render.width, o.render.height, o.fps));
    for (int k = 0; k < num_frames; ++k) {
      RETURN_IF_ERROR(TimedFrame(model, trajectory, static_cast<double>(k) / o.fps,
                                 scratch.get(), renderer.get(), &frame, &report));
      RETURN_IF_ERROR(video->AddFrame(frame));
    }
    RETURN_IF_ERROR(video->Close());
  } else if (IsPng(o.out)) {
    const double time = o.png_time >= 0 ? o.png_time : report.duration;
    RETURN_IF_ERROR(
        TimedFrame(model, trajectory, time, scratch.get(), renderer.get(), &frame, &report));
    RETURN_IF_ERROR(WritePng(o.out, frame));
  }
  if (!o.sheet.empty()) {
    // Frames evenly spaced over the first episode, the last one just before its end so that
    // it shows the final state rather than the next episode's reset.
    const double end = trajectory.time[trajectory.EpisodeEnd(0)];
    const int tiles = o.sheet_columns * o.sheet_rows;
    std::vector<Image> shrunk;
    for (int k = 0; k < tiles; ++k) {
      const double time = tiles > 1 ? std::max(0.0, end * k / (tiles - 1) - 1e-6) : 0.0;
      RETURN_IF_ERROR(
          TimedFrame(model, trajectory, time, scratch.get(), renderer.get(), &frame, &report));
      shrunk.push_back(Downscale(frame, o.sheet_downscale));
    }
    RETURN_IF_ERROR(WritePng(o.sheet, ContactSheet(shrunk, o.sheet_columns)));
  }
  return report;
}

}  // namespace juggle
