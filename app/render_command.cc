// `juggle render`: renders a zero-action rollout (or a recorded one) to MP4 / PNG, writes a
// contact sheet, records trajectories for replay. The work is in render/render_job.h.
#include <cstdio>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "app/commands.h"
#include "app/flags.h"
#include "learner/learner_state.h"
#include "render/render_job.h"

namespace juggle {
namespace {

const std::vector<FlagSpec>& RenderFlags() {
  static const auto* specs = new std::vector<FlagSpec>{
      {"config", "", "run config (default configs/right_foot.textproto; with --replay: the "
                     "recording's)"},
      {"zero-action", "false", "zero feed-forward torques (the default without --checkpoint)"},
      {"checkpoint", "", "policy checkpoint file or run directory (mean action, no noise)"},
      {"seconds", "4", "simulated seconds (video length)"},
      {"seed", "-1", "env seed (-1: the config's seed)"},
      {"node", "", "DOWN node every episode starts at (default: a random initial node)"},
      {"out", "", "FILE.mp4 (H.264, 30 fps, via ffmpeg) or FILE.png (one frame)"},
      {"at", "-1", "time (s) of the --out=FILE.png frame (-1: the end)"},
      {"sheet", "", "contact sheet PNG: 4x3 frames over the first episode"},
      {"record", "", "write the trajectory (docs/recording.md)"},
      {"replay", "", "render a recorded trajectory instead of simulating"},
      {"width", "640", "frame width (pixels)"},
      {"height", "480", "frame height (pixels)"},
      {"quality", "low", "low: no shadows/reflections/MSAA (fast on CPU) | high"},
  };
  return *specs;
}

int Fail(const absl::Status& status) {
  std::fprintf(stderr, "error: %s\n", std::string(status.message()).c_str());
  return 1;
}

}  // namespace

int RunRender(int argc, char** argv, int first) {
  absl::StatusOr<Flags> flags = Flags::Parse(argc, argv, first, RenderFlags());
  if (!flags.ok()) return Fail(flags.status());
  if (flags->help()) {
    std::printf("usage: juggle render --out=FILE.mp4|FILE.png [--sheet=FILE.png] "
                "[--record=FILE] [--replay=FILE] [flags]\n%s",
                Flags::Usage(RenderFlags()).c_str());
    return 0;
  }
  if (!flags->positional().empty()) {
    return Fail(absl::InvalidArgumentError(
        absl::StrCat("unexpected argument '", flags->positional()[0], "'")));
  }
  auto seconds = flags->GetDouble("seconds");
  auto seed = flags->GetInt("seed");
  auto at = flags->GetDouble("at");
  auto width = flags->GetInt("width");
  auto height = flags->GetInt("height");
  for (const absl::Status& s :
       {seconds.status(), seed.status(), at.status(), width.status(), height.status()}) {
    if (!s.ok()) return Fail(s);
  }
  const std::string quality = flags->Get("quality");
  if (quality != "low" && quality != "high") {
    return Fail(absl::InvalidArgumentError("--quality must be low or high"));
  }

  RenderJobOptions o;
  o.replay = flags->Get("replay");
  o.config_path = flags->Get("config");
  if (!flags->Get("checkpoint").empty()) {
    if (!o.replay.empty()) {
      return Fail(absl::InvalidArgumentError("--checkpoint and --replay exclude each other"));
    }
    absl::StatusOr<LoadedCheckpoint> checkpoint = LoadCheckpoint(flags->Get("checkpoint"));
    if (!checkpoint.ok()) return Fail(checkpoint.status());
    if (o.config_path.empty()) o.config_path = checkpoint->config_path;
    if (o.config_path.empty()) {
      return Fail(absl::InvalidArgumentError("the checkpoint names no config: pass --config"));
    }
    absl::StatusOr<LoadedConfig> config = LoadRunConfig(o.config_path);
    if (!config.ok()) return Fail(config.status());
    absl::StatusOr<EigenPolicy> policy = PolicyFromCheckpoint(checkpoint->sections, *config);
    if (!policy.ok()) return Fail(policy.status());
    o.policy = std::make_shared<const EigenPolicy>(std::move(*policy));
    std::printf("policy from %s\n", checkpoint->path.c_str());
  }
  if (o.config_path.empty() && o.replay.empty()) o.config_path = "configs/right_foot.textproto";
  o.seconds = *seconds;
  o.seed = *seed;
  o.start_node = flags->Get("node");
  o.out = flags->Get("out");
  o.png_time = *at;
  o.sheet = flags->Get("sheet");
  o.record = flags->Get("record");
  o.render.width = static_cast<int>(*width);
  o.render.height = static_cast<int>(*height);
  o.render.high_quality = quality == "high";

  absl::StatusOr<RenderJobReport> report = RunRenderJob(o);
  if (!report.ok()) return Fail(report.status());
  std::string outcomes;
  for (Outcome e : report->episode_outcomes) absl::StrAppend(&outcomes, " ", OutcomeName(e));
  std::printf("%s: %.2f s, %d episode(s), ended:%s\n", report->config_path.c_str(),
              report->duration, report->episodes, outcomes.c_str());
  if (report->frames > 0) {
    std::printf("rendered %d frames at %dx%d (%s quality) on %s: %.1f frames/s\n",
                report->frames, o.render.width, o.render.height, quality.c_str(),
                report->gl_renderer.c_str(), report->frames_per_second());
  }
  for (const auto& [what, path] : {std::pair<const char*, std::string>{"out", o.out},
                                   {"sheet", o.sheet},
                                   {"record", o.record}}) {
    if (!path.empty()) std::printf("wrote %s: %s\n", what, path.c_str());
  }
  return 0;
}

}  // namespace juggle
