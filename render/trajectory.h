// A rollout as data: one sample per control step (plus one per reset), enough to re-render it
// without simulating. File format (docs/recording.md): one text header line, then
// kTrajectoryRecordDoubles little-endian float64 values per sample.
//
//   juggle-trajectory 1 record_doubles=56 nq=43 control_dt=0.02 nodes=a,b config=PATH\n
//
// Record layout (index: field): 0 time (s since the start of the recording; the video clock),
// 1 episode (0-based), 2 episode_time (s), 3 node index, 4 phase, 5 outcome (juggle::Outcome of
// the step that produced the sample; 0 while running), 6..48 character qpos (43),
// 49..51 ball position, 52..55 ball quaternion (w, x, y, z).
#ifndef JUGGLE_RENDER_TRAJECTORY_H_
#define JUGGLE_RENDER_TRAJECTORY_H_

#include <array>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "absl/status/statusor.h"
#include "worker/juggle_env.h"
#include "worker/juggle_spec.h"

namespace juggle {

constexpr char kTrajectoryMagic[] = "juggle-trajectory";
constexpr int kTrajectoryVersion = 1;
constexpr int kTrajectoryRecordDoubles = 6 + kCharacterNq + 3 + 4;  // 56

struct TrajectorySample {
  double time = 0;          // s since the start of the recording
  int episode = 0;
  double episode_time = 0;  // s since the episode's reset
  int node = 0;             // current control-graph node after the step
  double phase = 0;         // φ after the step
  Outcome outcome = Outcome::kRunning;  // set on the last sample of a finished episode
  CharacterPose qpos{};
  std::array<double, 3> ball_pos{};
  std::array<double, 4> ball_quat{1, 0, 0, 0};
};

struct Trajectory {
  std::string config_path;
  double control_dt = 0;
  std::vector<std::string> node_names;
  // Sorted by time. A reset sample has the same time as the last sample of the episode before.
  std::vector<TrajectorySample> samples;
};

// Writes `trajectory` to `path`. INVALID_ARGUMENT if a node name or the config path contains
// a newline (or a node name a comma or space); file errors name the path.
absl::Status WriteTrajectory(const Trajectory& trajectory, const std::string& path);

// Reads a file written by WriteTrajectory. NOT_FOUND for a missing file; INVALID_ARGUMENT, naming
// the file, for a wrong magic, version, nq or record size, or a truncated record.
absl::StatusOr<Trajectory> ReadTrajectory(const std::string& path);

// Captures the env's current state as a sample (time, episode, outcome are the caller's).
TrajectorySample CaptureSample(const JuggleEnv& env);

// What a frame shows besides the pose: the sample it came from.
struct FrameInfo {
  int sample = 0;           // index of the last sample at or before the time
  int episode = 0;
  double episode_time = 0;  // interpolated
  int node = 0;
  double phase = 0;
  Outcome outcome = Outcome::kRunning;
};

// Writes the state at `time` into `data`'s qpos (zero qvel) and runs mj_forward. Between two
// samples of one episode, positions are interpolated linearly and quaternions (free and ball
// joints) spherically; at a sample's exact time its qpos is copied bit for bit. At the time
// of a reset the new episode is shown. Times outside the recording clamp to its ends.
// REQUIRES: non-empty `trajectory`; `data` belongs to `spec`'s model.
FrameInfo PoseAt(const JuggleSpec& spec, const Trajectory& trajectory, double time,
                 mjData* data);

// Duration of the recording (time of its last sample).
double Duration(const Trajectory& trajectory);

}  // namespace juggle

#endif  // JUGGLE_RENDER_TRAJECTORY_H_
