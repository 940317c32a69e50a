// `juggle render` as a library call: simulate a rollout of any env family with a policy's mean
// action or zero action (eval/episode_runner.h, RecordRollout), or read a recorded one, then
// write any of an MP4, a single PNG frame, a contact sheet and a recording.
//
// Frames are rendered at video time t = k / fps from the control-step samples: between two
// samples of an episode the pose is interpolated (record/trajectory.h, PoseAt), so the video
// runs in real time whatever the control rate, and a replay renders exactly the frames of the
// live run.
#ifndef JUGGLE_RENDER_RENDER_JOB_H_
#define JUGGLE_RENDER_RENDER_JOB_H_

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "common/config_loader.h"
#include "common/eigen_policy.h"
#include "eval/controller.h"
#include "render/image.h"
#include "render/renderer.h"
#include "envs/env.h"
#include "record/trajectory.h"

namespace juggle {

struct RenderJobOptions {
  // Run config: a config file or an exported policy (its stored config, envs/policy_config.h).
  // With `replay`, empty means the config named in the recording.
  std::string config_path;
  // The run config itself, when the caller has loaded it (a policy's stored copy); then
  // `config_path` only names it in reports and recordings.
  std::optional<LoadedConfig> config;
  double seconds = 4;        // simulated seconds (live only; a replay renders all of it)
  int64_t seed = -1;         // -1: the config's seed. Env stream (seed, worker 0, env 0).
  std::string start_node;    // DOWN node every episode starts at; empty: random initial node
  std::string out;           // FILE.mp4 (video) or FILE.png (one frame); empty: none
  double png_time = -1;      // time (s) of the PNG frame; < 0: the end of the rollout
  std::string sheet;         // contact sheet PNG of the first episode; empty: none
  int sheet_columns = 4;
  int sheet_rows = 3;
  int sheet_downscale = 2;   // tiles are frames shrunk by this factor
  std::string record;        // write the trajectory here; empty: none
  std::string replay;        // render this recording instead of simulating
  int fps = 30;
  RenderOptions render;      // size and quality; the camera tracks the root
  // Policy acting with its mean action (no exploration noise); null: zero action ...
  std::shared_ptr<const EigenPolicy> policy;
  // ... or, when set, the controller this makes for the job's spec and config (the planner).
  ControllerFactory controller;
};

struct RenderJobReport {
  std::string config_path;
  std::string gl_renderer;    // empty if nothing was rendered
  int episodes = 0;
  std::vector<std::string> episode_outcomes;  // how each episode ended ("running": cut by the end)
  double duration = 0;        // s of rollout
  int frames = 0;             // frames rendered (video + png + sheet)
  double render_seconds = 0;  // wall time in pose + render + readback (not encoding)
  double frames_per_second() const { return render_seconds > 0 ? frames / render_seconds : 0; }
};

// Runs the job. Errors: INVALID_ARGUMENT for bad options (unknown output extension, nothing to
// do, unknown or non-DOWN --node, --record with --replay, recording/config mismatch);
// config and model errors from LoadConfigOrPolicy / CreateEnvSpec; FAILED_PRECONDITION for a
// missing GL provider or ffmpeg (naming the package); PERMISSION_DENIED / NOT_FOUND for an
// output path that cannot be written. Every output path is checked before simulating.
absl::StatusOr<RenderJobReport> RunRenderJob(const RenderJobOptions& options);

// Renders the frame at `time` of `trajectory` with its caption (the family's channels, episode
// time, episode and how it ends). `scratch` is a work mjData of `model`.
absl::Status RenderFrame(const mjModel* model, const Trajectory& trajectory, double time,
                         mjData* scratch, Renderer* renderer, Image* out);

}  // namespace juggle

#endif  // JUGGLE_RENDER_RENDER_JOB_H_
