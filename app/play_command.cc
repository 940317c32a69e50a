// `juggle play`: the character juggles live in the browser (docs/play.md). The simulation runs
// here at the speed of the clock (play/play_session.h) with a policy, the zero action or the
// planner; the page (play/play_server.h) draws it and sends skill choices, pokes, pauses and
// restarts. The toss family plays the two-arm runtime with the siteswap chosen live. The last
// line is key=value pairs.
#include <chrono>
#include <cstdio>
#include <thread>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "app/commands.h"
#include "app/controller_factory.h"
#include "app/planner_flags.h"
#include "app/policy_source.h"
#include "app/signals.h"
#include "common/transport_security.h"
#include "envs/policy_config.h"
#include "envs/registry.h"
#include "export/replay.h"
#include "play/env_world.h"
#include "play/frame_hub.h"
#include "play/play_page.h"
#include "play/play_server.h"
#include "play/play_session.h"
#include "play/siteswap_world.h"

namespace juggle {
namespace {

struct PlayFlags {
  std::string config;
  std::string controller;  // "", "zero", "policy", "planner"
  std::string policy;
  PlannerFlags planner;
  int port = 8080;
  std::string bind = "127.0.0.1";
  std::string token_file;
  uint64_t seed = 1000;
  uint64_t start = 0;
  double speed = 1.0;
  bool paused = false;
  int max_viewers = 4;
  double seconds = 0;
  std::string pattern = "3";
  std::string three_dir = kDefaultThreeJsDir;
};

absl::StatusOr<std::unique_ptr<play::PlayWorld>> MakeWorld(const PlayFlags& f) {
  if (!f.policy.empty()) {
    absl::StatusOr<PolicySource> source = LoadPolicySource(f.policy, f.config);
    if (!source.ok()) return source.status();
    if (source->spec->family() == "toss") {
      return absl::InvalidArgumentError(
          "toss: play runs the two-arm runtime with its base controllers; --policy is for the "
          "soccer family");
    }
    ControllerChoice choice;
    choice.kind = "policy";
    choice.policy = source->policy;
    absl::StatusOr<std::unique_ptr<Controller>> controller =
        MakeController(choice, source->spec, source->config);
    if (!controller.ok()) return controller.status();
    return std::unique_ptr<play::PlayWorld>(std::make_unique<play::EnvWorld>(
        source->spec, *std::move(controller), nullptr, f.seed));
  }
  std::string note;
  absl::StatusOr<LoadedConfig> config = LoadConfigOrPolicy(f.config, &note);
  if (!config.ok()) return config.status();
  if (!note.empty()) std::fprintf(stderr, "%s\n", note.c_str());
  if (absl::Status s = ApplyPlannerFlags(f.planner, &*config); !s.ok()) return s;
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  if (!spec.ok()) return spec.status();
  if ((*spec)->family() == "toss") {
    if (!f.controller.empty() && f.controller != "zero") {
      return absl::InvalidArgumentError(
          "toss: play runs the two-arm runtime with the config's base controllers "
          "(--controller=zero or none)");
    }
    absl::StatusOr<std::unique_ptr<play::SiteswapWorld>> world =
        play::SiteswapWorld::Create(*spec, f.pattern, f.seed);
    if (!world.ok()) return world.status();
    return std::unique_ptr<play::PlayWorld>(*std::move(world));
  }
  ControllerChoice choice;
  choice.kind = f.controller.empty() ? "zero" : f.controller;
  if (choice.kind == "policy") {
    return absl::InvalidArgumentError("--controller=policy needs --policy=PATH");
  }
  planner::PlannerController* planner = nullptr;
  choice.on_planner = [&planner](planner::PlannerController* p) { planner = p; };
  absl::StatusOr<std::unique_ptr<Controller>> controller = MakeController(choice, *spec, *config);
  if (!controller.ok()) return controller.status();
  auto world = std::make_unique<play::EnvWorld>(*spec, *std::move(controller), planner, f.seed);
  if (planner != nullptr) {
    const auto& p = config->run.planner();
    world->set_budget(absl::StrCat(p.samples(), " samples x ", p.iterations(), " iterations"));
  }
  return std::unique_ptr<play::PlayWorld>(std::move(world));
}

int Play(const PlayFlags& f) {
  if (!f.policy.empty() && !f.controller.empty() && f.controller != "policy") {
    return UsageError("--policy runs the policy: it excludes --controller=" + f.controller);
  }
  if (f.config.empty() && f.policy.empty()) return UsageError("--config (or --policy) is needed");
  const bool all_interfaces = f.bind != "127.0.0.1";
  if (f.bind != "127.0.0.1" && f.bind != "0.0.0.0") {
    return UsageError("--bind is 127.0.0.1 (this machine only) or 0.0.0.0 (every interface)");
  }
  std::string token;
  if (all_interfaces || !f.token_file.empty()) {
    absl::StatusOr<std::string> t = LoadToken(f.token_file);
    if (!t.ok()) return Fail(t.status());
    token = *t;
    if (token.empty()) {
      return UsageError("--bind=0.0.0.0 needs a token: --token_file=FILE or JUGGLE_TOKEN");
    }
  }
  absl::StatusOr<ReplayLibraries> libraries = LoadReplayLibraries(f.three_dir);
  if (!libraries.ok()) return Fail(libraries.status());
  absl::StatusOr<std::unique_ptr<play::PlayWorld>> world = MakeWorld(f);
  if (!world.ok()) return Fail(world.status());
  const std::string family = (*world)->family();

  play::FrameHub hub(f.max_viewers, /*queue_capacity=*/8);
  play::SessionOptions options;
  options.speed = f.speed;
  options.first_seed = f.start;
  options.start_paused = f.paused;
  play::PlaySession session(*std::move(world), &hub, options);
  play::PlayServerOptions server_options;
  server_options.port = f.port;
  server_options.all_interfaces = all_interfaces;
  server_options.token = token;
  absl::StatusOr<std::unique_ptr<play::PlayServer>> server = play::PlayServer::Start(
      &session, &hub,
      play::PlayHtml(*libraries, absl::StrCat("juggle play: ", f.config.empty() ? f.policy
                                                                                 : f.config)),
      server_options);
  if (!server.ok()) return Fail(server.status());
  session.Start();
  std::printf("serving http://%s:%d/ (%s, Ctrl-C stops)\n", f.bind.c_str(), (*server)->port(),
              family.c_str());
  std::printf("url=http://%s:%d/ family=%s\n", f.bind.c_str(), (*server)->port(), family.c_str());
  std::fflush(stdout);
  std::atomic<bool>* stop = InstallStopSignals();
  const auto start = std::chrono::steady_clock::now();
  auto last_report = start;
  while (!stop->load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const auto now = std::chrono::steady_clock::now();
    if (f.seconds > 0 && std::chrono::duration<double>(now - start).count() >= f.seconds) break;
    if (now - last_report >= std::chrono::seconds(10)) {
      last_report = now;
      const play::SessionTimes t = session.times();
      std::printf("t=%.0f s: %.1f simulated s, %.2fx achieved, %d viewer(s), %lld frames dropped\n",
                  t.wall_seconds, t.sim_seconds, session.achieved_speed(), hub.viewers(),
                  static_cast<long long>(hub.dropped()));
      std::fflush(stdout);
    }
  }
  (*server)->Stop();
  session.Stop();
  const play::SessionTimes t = session.times();
  std::printf(
      "family=%s steps=%lld frames=%lld sim_s=%.2f wall_s=%.2f speed=%.3f step_s=%.4f "
      "frame_s=%.4f stream_share=%.4f episodes=%lld published=%lld dropped=%lld\n",
      family.c_str(), static_cast<long long>(t.steps), static_cast<long long>(t.frames),
      t.sim_seconds, t.wall_seconds, t.wall_seconds > 0 ? t.sim_seconds / t.wall_seconds : 0,
      t.step_seconds, t.frame_seconds, t.stream_share(),
      static_cast<long long>(session.episodes()), static_cast<long long>(hub.published()),
      static_cast<long long>(hub.dropped()));
  return 0;
}

}  // namespace

CommandBody AddPlayCommand(CLI::App* cmd) {
  auto f = std::make_shared<PlayFlags>();
  cmd->add_option("--config", f->config,
                  "run config (soccer or toss), or an exported policy whose stored config to use");
  cmd->add_option("--controller", f->controller,
                  "what acts (soccer): zero (the default), planner (the config's planner, "
                  "docs/planner.md) or policy (--policy)")
      ->check(CLI::IsMember({"zero", "planner", "policy"}));
  cmd->add_option("--policy,--checkpoint", f->policy,
                  "policy: checkpoint file, run directory or exported .jglpolicy (mean action)");
  AddPlannerFlags(cmd, &f->planner);
  cmd->add_option("--port", f->port, "HTTP port (0: a free one)")
      ->check(Between(0, 65535))
      ->capture_default_str();
  cmd->add_option("--bind", f->bind,
                  "127.0.0.1 (this machine only) or 0.0.0.0 (every interface: needs a token)")
      ->capture_default_str();
  cmd->add_option("--token_file", f->token_file,
                  "the token viewers must send (else JUGGLE_TOKEN); required with --bind=0.0.0.0");
  cmd->add_option("--seed", f->seed, "run seed: start s is `juggle eval --seed=SEED` episode s")
      ->capture_default_str();
  cmd->add_option("--start", f->start, "the first episode's start (then +1 per restart)")
      ->capture_default_str();
  cmd->add_option("--speed", f->speed, "simulated seconds per wall second asked for")
      ->check(CLI::Range(0.05, 4.0))
      ->capture_default_str();
  cmd->add_flag("--paused", f->paused, "start paused (the page resumes)");
  cmd->add_option("--max-viewers", f->max_viewers, "pages that may watch at once")
      ->check(Between(1, 6))
      ->capture_default_str();
  cmd->add_option("--seconds", f->seconds, "stop after this many wall seconds (0: at Ctrl-C)")
      ->check(CLI::Range(0.0, 1e7))
      ->capture_default_str();
  cmd->add_option("--pattern", f->pattern, "toss: the siteswap to start with")
      ->capture_default_str();
  cmd->add_option("--three-dir", f->three_dir,
                  "folder of three.js r111 (three.min.js, examples/js/controls/OrbitControls.js)")
      ->capture_default_str();
  return [f] { return Play(*f); };
}

}  // namespace juggle
