// A rollout as data, for any env family: one sample per control step (plus one per reset) with
// the whole model's qpos and named annotation channels, enough to re-render, replay in a
// browser or export without simulating. GL-free and family-free (docs/recording.md).
//
// File format (version 2): text header lines, then little-endian float64 records.
//   juggle-trajectory 2
//   family soccer_juggle            the env family (RunConfig oneof name)
//   config configs/right_foot.textproto   the run config it was recorded with
//   control_dt 0.02                 seconds per control step
//   nq 50                           qpos size of the family's model
//   channel episode                 one line per channel, in record order; a channel with
//   channel episode_time            labels is categorical: its values index the comma-separated
//   channel outcome running,time_limit,...   label list
//   channel node right_foot_down,right_foot_up
//   channel phase
//   data 123                        number of records that follow, then a single '\n'
// Each record: time, one value per channel, then nq qpos values.
// The first three channels are always episode (0-based), episode_time (s since the episode's
// reset) and outcome (how the step that produced the sample ended the episode; 0 = running);
// the family's annotation channels (EnvSpec::annotation_channels) follow.
#ifndef JUGGLE_RECORD_TRAJECTORY_H_
#define JUGGLE_RECORD_TRAJECTORY_H_

#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "absl/status/statusor.h"
#include "common/outcome.h"

namespace juggle {

constexpr char kTrajectoryMagic[] = "juggle-trajectory";
constexpr int kTrajectoryVersion = 2;
// Indices of the standard channels.
constexpr int kEpisodeChannel = 0;
constexpr int kEpisodeTimeChannel = 1;
constexpr int kOutcomeChannel = 2;

// A recorded channel: its name and, for categorical channels, the names of its values.
struct AnnotationChannel {
  std::string name;
  std::vector<std::string> labels;  // empty: a number
};

struct Trajectory {
  std::string family;
  std::string config_path;
  double control_dt = 0;
  int nq = 0;
  std::vector<AnnotationChannel> channels;
  // Sorted by time. A reset sample has the same time as the last sample of the episode before.
  std::vector<double> time;    // [samples]
  std::vector<double> values;  // [samples, channels]
  std::vector<double> qpos;    // [samples, nq]

  int num_samples() const { return static_cast<int>(time.size()); }
  int num_channels() const { return static_cast<int>(channels.size()); }
  double value(int sample, int channel) const {
    return values[static_cast<size_t>(sample) * channels.size() + channel];
  }
  const double* qpos_at(int sample) const { return &qpos[static_cast<size_t>(sample) * nq]; }
  int episode(int sample) const { return static_cast<int>(value(sample, kEpisodeChannel)); }
  Outcome outcome(int sample) const {
    return static_cast<Outcome>(static_cast<int>(value(sample, kOutcomeChannel)));
  }
  // Index of the channel named `name`, or -1.
  int FindChannel(const std::string& name) const;
  // The label of a categorical channel's value at `sample` ("" for numeric channels).
  std::string Label(int sample, int channel) const;
  // Duration (time of the last sample; 0 when empty).
  double duration() const { return time.empty() ? 0 : time.back(); }
  // Last sample of `episode`, or -1.
  int EpisodeEnd(int episode) const;
};

// Builds a Trajectory sample by sample: the standard channels plus a family's own.
// Thread-compatible.
class TrajectoryBuilder {
 public:
  // `outcome_names` label the outcome channel; `family_channels` follow the standard ones.
  TrajectoryBuilder(std::string family, std::string config_path, double control_dt, int nq,
                    std::vector<std::string> outcome_names,
                    std::vector<AnnotationChannel> family_channels);
  // Appends a sample. REQUIRES: `annotations` holds one value per family channel, `qpos` nq.
  void Append(double time, int episode, double episode_time, Outcome outcome,
              const double* annotations, const double* qpos);
  const Trajectory& trajectory() const { return t_; }
  Trajectory Take() { return std::move(t_); }

 private:
  Trajectory t_;
};

// Appends `episode` of `from` (every sample whose episode channel is `episode`) to `into`,
// renumbered as episode `new_episode` and shifted to start at `into`'s end.
// REQUIRES: same family, nq and channels.
void AppendEpisode(const Trajectory& from, int episode, int new_episode, Trajectory* into);

// Writes `trajectory` to `path`. INVALID_ARGUMENT if a label has a comma, space or newline, or
// the config path a newline; file errors name the path.
absl::Status WriteTrajectory(const Trajectory& trajectory, const std::string& path);

// Reads a file written by WriteTrajectory. NOT_FOUND for a missing file; INVALID_ARGUMENT,
// naming the file, for a wrong magic or version, a malformed header, a truncated record, a
// categorical value outside its labels or time going backwards.
absl::StatusOr<Trajectory> ReadTrajectory(const std::string& path);

// What a frame shows besides the pose.
struct FrameInfo {
  int sample = 0;           // index of the last sample at or before the time
  int episode = 0;
  double episode_time = 0;  // interpolated
};

// Writes the state at `time` into `data`'s qpos (zero qvel) and runs mj_forward. Between two
// samples of one episode, positions are interpolated linearly and quaternions (free and ball
// joints) spherically; at a sample's exact time its qpos is copied bit for bit. At the time
// of a reset the new episode is shown. Times outside the recording clamp to its ends.
// REQUIRES: non-empty `trajectory` of `model` (nq equal); `data` belongs to `model`.
FrameInfo PoseAt(const mjModel* model, const Trajectory& trajectory, double time, mjData* data);

}  // namespace juggle

#endif  // JUGGLE_RECORD_TRAJECTORY_H_
