// `juggle export-bvh`: writes one episode of a recording as a BVH motion file (export/bvh.h)
// and the balls' path as CSV beside it. The last line is key=value pairs.
#include <chrono>
#include <cstdio>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "app/commands.h"
#include "export/bvh.h"
#include "export/trajectory_model.h"
#include "common/file_io.h"

namespace juggle {
namespace {

struct ExportBvhFlags {
  std::string trajectory;
  std::string out = "motion.bvh";
  std::string balls;
  std::string config;
  int episode = 0;
};

// motion.bvh -> motion.balls.csv
std::string DefaultBallsPath(const std::string& out) {
  const bool bvh = absl::EndsWithIgnoreCase(out, ".bvh");
  const std::string stem = bvh ? out.substr(0, out.size() - 4) : out;
  return stem + ".balls.csv";
}

int ExportBvhCommand(const ExportBvhFlags& f) {
  const auto start = std::chrono::steady_clock::now();
  absl::StatusOr<Trajectory> t = ReadTrajectory(f.trajectory);
  if (!t.ok()) return Fail(t.status());
  if (t->num_samples() == 0) {
    return Fail(absl::InvalidArgumentError(
        absl::StrCat(f.trajectory, ": the recording has no samples: nothing to export")));
  }
  const std::string balls = f.balls.empty() ? DefaultBallsPath(f.out) : f.balls;
  if (absl::Status s = CheckWritable(f.out); !s.ok()) return Fail(s);
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec =
      LoadTrajectorySpec(*t, f.trajectory, f.config);
  if (!spec.ok()) return Fail(spec.status());
  absl::StatusOr<BvhExport> bvh = ExportBvh((*spec)->model(), *t, f.episode);
  if (!bvh.ok()) {
    return Fail(absl::Status(bvh.status().code(),
                             absl::StrCat(f.trajectory, ": ", bvh.status().message())));
  }
  if (absl::Status s = WriteFile(f.out, bvh->bvh); !s.ok()) return Fail(s);
  if (!bvh->balls_csv.empty()) {
    if (absl::Status s = WriteFile(balls, bvh->balls_csv); !s.ok()) return Fail(s);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("out=%s balls=%s family=%s episode=%d frames=%d frame_time=%.6f joints=%d "
              "channels=%d bytes=%zu export_s=%.3f\n",
              f.out.c_str(), bvh->balls_csv.empty() ? "none" : balls.c_str(), t->family.c_str(),
              f.episode, bvh->frames, bvh->frame_time, bvh->joints, bvh->channels,
              bvh->bvh.size(), seconds);
  return 0;
}

}  // namespace

CommandBody AddExportBvhCommand(CLI::App* cmd) {
  auto f = std::make_shared<ExportBvhFlags>();
  cmd->add_option("--trajectory", f->trajectory,
                  "recording to export (juggle render/eval/toss --record; docs/replay_and_export.md)")
      ->required();
  cmd->add_option("--out", f->out, "BVH file to write (Y up, metres, degrees)")
      ->capture_default_str();
  cmd->add_option("--balls", f->balls,
                  "CSV of the balls' centres per frame, BVH axes (default: OUT with .balls.csv)");
  cmd->add_option("--episode", f->episode, "episode of the recording to export")
      ->check(AtLeast(0))
      ->capture_default_str();
  cmd->add_option("--config", f->config,
                  "run config, or exported policy (.jglpolicy: its stored config), to load "
                  "the model from (default: the one the recording names)");
  return [f] { return ExportBvhCommand(*f); };
}

}  // namespace juggle
