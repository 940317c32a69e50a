#include "render/render_job.h"

#include <chrono>
#include <cmath>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "common/adaptive_walk.h"
#include "common/config_loader.h"
#include "common/rng.h"
#include "common/status_macros.h"
#include "render/video_writer.h"

namespace juggle {
namespace {

using Clock = std::chrono::steady_clock;

bool IsPng(const std::string& path) { return absl::EndsWithIgnoreCase(path, ".png"); }
bool IsMp4(const std::string& path) { return absl::EndsWithIgnoreCase(path, ".mp4"); }

// Last sample of `episode`, or -1.
int EpisodeEnd(const Trajectory& t, int episode) {
  for (int i = static_cast<int>(t.samples.size()) - 1; i >= 0; --i) {
    if (t.samples[i].episode == episode) return i;
  }
  return -1;
}

std::unique_ptr<mjData, void (*)(mjData*)> MakeData(const mjModel* m) {
  return {mj_makeData(m), mj_deleteData};
}

// Renders a frame and adds its wall time to `report`.
absl::Status TimedFrame(const JuggleSpec& spec, const Trajectory& t, double time, mjData* scratch,
                        Renderer* renderer, Image* out, RenderJobReport* report) {
  const auto start = Clock::now();
  RETURN_IF_ERROR(RenderFrame(spec, t, time, scratch, renderer, out));
  report->render_seconds += std::chrono::duration<double>(Clock::now() - start).count();
  ++report->frames;
  return absl::OkStatus();
}

}  // namespace

Trajectory SimulateRollout(std::shared_ptr<const JuggleSpec> spec, double seconds,
                           uint64_t seed, int start_node, const EigenPolicy* policy) {
  Trajectory t;
  t.config_path = spec->config().config_path;
  t.control_dt = spec->control_dt();
  for (int n = 0; n < spec->graph().num_nodes(); ++n) {
    t.node_names.push_back(spec->graph().node(n).spec.name());
  }
  // The walk keeps its base weights: one env's events are not fed back (as a worker would
  // forward them to the learner).
  AdaptiveWalk walk(&spec->graph());
  JuggleEnv env(spec, Rng::ForStream(seed, 0, 0));
  auto reset = [&] {
    if (start_node >= 0) {
      env.ResetAt(start_node, walk);
    } else {
      env.Reset(walk);
    }
  };
  const int total_steps = std::max(0, static_cast<int>(std::ceil(seconds / t.control_dt - 1e-9)));
  t.samples.reserve(total_steps + 16);
  int episode = 0;
  reset();
  t.samples.push_back(CaptureSample(env));
  float action[kNumActions] = {0};
  std::vector<float> obs(spec->obs_dim());
  for (int step = 1; step <= total_steps; ++step) {
    if (policy != nullptr) {
      env.WriteObservation(obs.data());
      const RowMatrix mean = policy->MeanActions(obs.data(), 1);
      std::copy(mean.data(), mean.data() + kNumActions, action);
    }
    const StepResult r = env.Step(action, walk);
    TrajectorySample s = CaptureSample(env);
    s.time = step * t.control_dt;
    s.episode = episode;
    s.outcome = r.outcome;
    t.samples.push_back(s);
    if (r.outcome != Outcome::kRunning && step < total_steps) {
      ++episode;
      reset();
      TrajectorySample first = CaptureSample(env);
      first.time = step * t.control_dt;
      first.episode = episode;
      t.samples.push_back(first);
    }
  }
  return t;
}

absl::Status RenderFrame(const JuggleSpec& spec, const Trajectory& trajectory, double time,
                         mjData* scratch, Renderer* renderer, Image* out) {
  const FrameInfo info = PoseAt(spec, trajectory, time, scratch);
  std::string ending = "";
  const int end = EpisodeEnd(trajectory, info.episode);
  if (end >= 0 && trajectory.samples[end].outcome != Outcome::kRunning) {
    ending = absl::StrFormat("  (%s at %.2f s)", OutcomeName(trajectory.samples[end].outcome),
                             trajectory.samples[end].episode_time);
  }
  const std::string labels = "node\nphase\ntime\nepisode";
  const std::string values = absl::StrFormat(
      "%s\n%.2f\n%.2f s\n%d%s", trajectory.node_names[info.node], info.phase, info.episode_time,
      info.episode, ending);
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
    if (trajectory.samples.empty()) {
      return absl::InvalidArgumentError(absl::StrCat(o.replay, ": recording has no samples"));
    }
    if (config_path.empty()) config_path = trajectory.config_path;
  }
  ASSIGN_OR_RETURN(const LoadedConfig config, LoadRunConfig(config_path));
  ASSIGN_OR_RETURN(std::shared_ptr<const JuggleSpec> spec, JuggleSpec::Create(config));
  const ControlGraph& graph = spec->graph();
  if (!o.replay.empty()) {
    bool same = static_cast<int>(trajectory.node_names.size()) == graph.num_nodes();
    for (int n = 0; same && n < graph.num_nodes(); ++n) {
      same = trajectory.node_names[n] == graph.node(n).spec.name();
    }
    if (!same) {
      return absl::InvalidArgumentError(absl::StrCat(
          o.replay, ": its node names differ from the graph of ", config_path,
          "; pass the config it was recorded with (--config)"));
    }
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
    render.track_body = spec->root_body();
    ASSIGN_OR_RETURN(renderer, Renderer::Create(spec->model(), render));
  }
  if (o.replay.empty()) {
    const uint64_t seed = o.seed >= 0 ? static_cast<uint64_t>(o.seed) : config.run.seed();
    trajectory = SimulateRollout(spec, o.seconds, seed, start_node, o.policy.get());
  }

  RenderJobReport report;
  report.config_path = config_path;
  report.duration = Duration(trajectory);
  report.episodes = trajectory.samples.back().episode + 1;
  for (int e = 0; e < report.episodes; ++e) {
    report.episode_outcomes.push_back(trajectory.samples[EpisodeEnd(trajectory, e)].outcome);
  }
  if (renderer != nullptr) report.gl_renderer = renderer->gl_renderer();
  if (!o.record.empty()) RETURN_IF_ERROR(WriteTrajectory(trajectory, o.record));

  auto scratch = MakeData(spec->model());
  Image frame;
  if (IsMp4(o.out)) {
    const double seconds = o.replay.empty() ? o.seconds : report.duration;
    const int num_frames = std::max(1, static_cast<int>(std::lround(seconds * o.fps)));
    ASSIGN_OR_RETURN(std::unique_ptr<VideoWriter> video,
                     VideoWriter::Open(o.out, o.render.width, o.render.height, o.fps));
    for (int k = 0; k < num_frames; ++k) {
      RETURN_IF_ERROR(TimedFrame(*spec, trajectory, static_cast<double>(k) / o.fps,
                                 scratch.get(), renderer.get(), &frame, &report));
      RETURN_IF_ERROR(video->AddFrame(frame));
    }
    RETURN_IF_ERROR(video->Close());
  } else if (IsPng(o.out)) {
    const double time = o.png_time >= 0 ? o.png_time : report.duration;
    RETURN_IF_ERROR(
        TimedFrame(*spec, trajectory, time, scratch.get(), renderer.get(), &frame, &report));
    RETURN_IF_ERROR(WritePng(o.out, frame));
  }
  if (!o.sheet.empty()) {
    // Frames evenly spaced over the first episode, the last one just before its end so that
    // it shows the final state rather than the next episode's reset.
    const double end = trajectory.samples[EpisodeEnd(trajectory, 0)].time;
    const int tiles = o.sheet_columns * o.sheet_rows;
    std::vector<Image> shrunk;
    for (int k = 0; k < tiles; ++k) {
      const double time = tiles > 1 ? std::max(0.0, end * k / (tiles - 1) - 1e-6) : 0.0;
      RETURN_IF_ERROR(
          TimedFrame(*spec, trajectory, time, scratch.get(), renderer.get(), &frame, &report));
      shrunk.push_back(Downscale(frame, o.sheet_downscale));
    }
    RETURN_IF_ERROR(WritePng(o.sheet, ContactSheet(shrunk, o.sheet_columns)));
  }
  return report;
}

}  // namespace juggle
