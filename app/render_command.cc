// `juggle render`: renders a rollout (a policy's mean action, zero action, or a recording) to
// MP4 / PNG, writes a contact sheet, records trajectories for replay. The work is in
// render/render_job.h.
#include <cstdio>
#include <string>

#include "absl/strings/str_cat.h"
#include "app/commands.h"
#include "app/controller_factory.h"
#include "app/planner_flags.h"
#include "app/policy_source.h"
#include "render/render_job.h"

namespace juggle {
namespace {

struct RenderFlags {
  RenderJobOptions job;
  std::string policy;
  bool zero_action = false;
  std::string controller;  // "", "policy", "zero" or "planner"
  PlannerFlags planner;
  std::string quality = "low";
};

int Render(RenderFlags f) {
  RenderJobOptions& o = f.job;
  if (f.controller == "planner") {
    if (!f.policy.empty() || f.zero_action || !o.replay.empty()) {
      return UsageError("--controller=planner excludes --policy, --zero-action and --replay");
    }
    ControllerChoice planner;
    planner.kind = "planner";
    planner.planner_set = f.planner.set;
    absl::StatusOr<ControllerFactory> factory = MakeControllerFactory(std::move(planner));
    if (!factory.ok()) return Fail(factory.status());
    o.controller = *factory;
  } else if (f.controller == "policy" && f.policy.empty()) {
    return UsageError("--controller=policy needs --policy=PATH");
  }
  if (!f.policy.empty()) {
    if (!o.replay.empty()) return UsageError("--policy and --replay exclude each other");
    if (f.zero_action) return UsageError("--policy and --zero-action exclude each other");
    absl::StatusOr<PolicySource> source = LoadPolicySource(f.policy, o.config_path);
    if (!source.ok()) return Fail(source.status());
    o.config_path = RecordedConfigName(source->config);
    o.config = source->config;
    o.policy = source->policy;
    std::printf("policy from %s\n", source->path.c_str());
  }
  if (o.config_path.empty() && o.replay.empty()) o.config_path = "configs/right_foot.textproto";
  o.render.high_quality = f.quality == "high";
  absl::StatusOr<RenderJobReport> report = RunRenderJob(o);
  if (!report.ok()) return Fail(report.status());
  std::string outcomes;
  for (const std::string& e : report->episode_outcomes) absl::StrAppend(&outcomes, " ", e);
  std::printf("%s: %.2f s, %d episode(s), ended:%s\n", report->config_path.c_str(),
              report->duration, report->episodes, outcomes.c_str());
  if (report->frames > 0) {
    std::printf("rendered %d frames at %dx%d (%s quality) on %s: %.1f frames/s\n",
                report->frames, o.render.width, o.render.height, f.quality.c_str(),
                report->gl_renderer.c_str(), report->frames_per_second());
  }
  for (const auto& [what, path] : {std::pair<const char*, std::string>{"out", o.out},
                                   {"sheet", o.sheet},
                                   {"record", o.record}}) {
    if (!path.empty()) std::printf("wrote %s: %s\n", what, path.c_str());
  }
  return 0;
}

}  // namespace

CommandBody AddRenderCommand(CLI::App* cmd) {
  auto f = std::make_shared<RenderFlags>();
  RenderJobOptions& o = f->job;
  cmd->add_option("--config", o.config_path,
                  "run config, or an exported policy whose stored config to use (default "
                  "configs/right_foot.textproto; with --policy: the policy's; with --replay: "
                  "the recording's)");
  cmd->add_flag("--zero-action", f->zero_action,
                "zero feed-forward torques (the default without --policy)");
  cmd->add_option("--policy,--checkpoint", f->policy,
                  "policy: checkpoint file, run directory or exported .jglpolicy (mean action)");
  cmd->add_option("--controller", f->controller,
                  "what acts: policy (--policy), zero (the default without --policy) or planner "
                  "(the config's planner settings, docs/planner.md)")
      ->check(CLI::IsMember({"policy", "zero", "planner"}));
  AddPlannerFlags(cmd, &f->planner);
  cmd->add_option("--seconds", o.seconds, "simulated seconds (video length)")
      ->check(Between(0, 3600))
      ->capture_default_str();
  cmd->add_option("--seed", o.seed, "env seed (-1: the config's seed)")
      ->check(AtLeast(-1))
      ->capture_default_str();
  cmd->add_option("--node", o.start_node,
                  "DOWN node every episode starts at (default: a random initial node)");
  cmd->add_option("--out", o.out, "FILE.mp4 (H.264, 30 fps, via ffmpeg) or FILE.png (one frame)");
  cmd->add_option("--at", o.png_time, "time (s) of the --out=FILE.png frame (-1: the end)")
      ->capture_default_str();
  cmd->add_option("--sheet", o.sheet, "contact sheet PNG: 4x3 frames over the first episode");
  cmd->add_option("--record", o.record, "write the trajectory (docs/recording.md)");
  cmd->add_option("--replay", o.replay, "render a recorded trajectory instead of simulating");
  cmd->add_option("--width", o.render.width, "frame width (pixels)")
      ->check(Between(16, 8192))
      ->capture_default_str();
  cmd->add_option("--height", o.render.height, "frame height (pixels)")
      ->check(Between(16, 8192))
      ->capture_default_str();
  cmd->add_option("--quality", f->quality, "low: no shadows/reflections/MSAA (fast on CPU) | high")
      ->check(CLI::IsMember({"low", "high"}))
      ->capture_default_str();
  return [f] { return Render(*f); };
}

}  // namespace juggle
