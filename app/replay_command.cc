// `juggle replay`: turns a recording (any family) into one self-contained HTML page that plays
// it in 3D in a browser (export/replay.h), written to a file or served on 127.0.0.1.
// The last line is key=value pairs.
#include <chrono>
#include <cstdio>
#include <thread>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "app/commands.h"
#include "app/signals.h"
#include "common/http_server.h"
#include "export/replay.h"
#include "export/trajectory_model.h"
#include "common/file_io.h"

namespace juggle {
namespace {

struct ReplayFlags {
  std::string trajectory;
  std::string out = "replay.html";
  int serve_port = 0;
  bool serve = false;
  std::string config;
  int episode = -1;
  std::string three_dir = kDefaultThreeJsDir;
};

int Replay(const ReplayFlags& f) {
  const auto start = std::chrono::steady_clock::now();
  absl::StatusOr<Trajectory> t = ReadTrajectory(f.trajectory);
  if (!t.ok()) return Fail(t.status());
  if (t->num_samples() == 0) {
    return Fail(absl::InvalidArgumentError(
        absl::StrCat(f.trajectory, ": the recording has no samples: nothing to replay")));
  }
  absl::StatusOr<ReplayLibraries> libraries = LoadReplayLibraries(f.three_dir);
  if (!libraries.ok()) return Fail(libraries.status());
  if (!f.serve) {
    if (absl::Status s = CheckWritable(f.out); !s.ok()) return Fail(s);
  }
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec =
      LoadTrajectorySpec(*t, f.trajectory, f.config);
  if (!spec.ok()) return Fail(spec.status());
  absl::StatusOr<ReplayData> data = BuildReplayData((*spec)->model(), *t, f.episode);
  if (!data.ok()) {
    return Fail(absl::Status(data.status().code(),
                             absl::StrCat(f.trajectory, ": ", data.status().message())));
  }
  const std::string html =
      ReplayHtml(*data, *libraries, absl::StrCat("juggle replay: ", f.trajectory));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string summary = absl::StrCat(
      "family=", data->family, " frames=", data->num_frames(), " bodies=", data->body_ids.size(),
      " geoms=", data->geoms.size(), " contacts=", data->contacts.size(),
      " events=", data->events.size(), " duration_s=", data->time.back(), " bytes=", html.size(),
      " build_s=", absl::StrFormat("%.3f", seconds));
  if (!f.serve) {
    if (absl::Status s = WriteFile(f.out, html); !s.ok()) return Fail(s);
    std::printf("out=%s %s\n", f.out.c_str(), summary.c_str());
    return 0;
  }
  absl::StatusOr<std::unique_ptr<HttpServer>> server =
      HttpServer::Start(f.serve_port, /*all_interfaces=*/false, [&html](const HttpRequest& request) {
        const std::string& path = request.path;
        HttpResponse r;
        if (path == "/" || path == "/index.html" || path == "/replay.html") {
          r.content_type = "text/html; charset=utf-8";
          r.body = html;
        } else {
          r.status = 404;
          r.body = "not found\n";
        }
        return r;
      });
  if (!server.ok()) return Fail(server.status());
  std::printf("serving http://127.0.0.1:%d/ (Ctrl-C stops)\n", (*server)->port());
  std::printf("url=http://127.0.0.1:%d/ %s\n", (*server)->port(), summary.c_str());
  std::fflush(stdout);
  std::atomic<bool>* stop = InstallStopSignals();
  while (!stop->load()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  (*server)->Stop();
  return 0;
}

}  // namespace

CommandBody AddReplayCommand(CLI::App* cmd) {
  auto f = std::make_shared<ReplayFlags>();
  cmd->add_option("--trajectory", f->trajectory,
                  "recording to play (juggle render/eval/toss --record; docs/replay_and_export.md)")
      ->required();
  cmd->add_option("--out", f->out, "the self-contained HTML page to write")->capture_default_str();
  cmd->add_flag("--serve{8000}", f->serve_port,
                "serve the page on http://127.0.0.1:PORT/ until Ctrl-C instead of writing it "
                "(--serve: port 8000; --serve=0: a free port)")
      ->check(Between(0, 65535));
  cmd->add_option("--config", f->config,
                  "run config, or exported policy (.jglpolicy: its stored config), to load "
                  "the model from (default: the one the recording names)");
  cmd->add_option("--episode", f->episode, "play only this episode (-1: all, one after another)")
      ->check(AtLeast(-1))
      ->capture_default_str();
  cmd->add_option("--three-dir", f->three_dir,
                  "folder of three.js r111 (three.min.js, examples/js/controls/OrbitControls.js)")
      ->capture_default_str();
  return [f, cmd] {
    ReplayFlags flags = *f;
    flags.serve = cmd->count("--serve") > 0;
    // CLI11 reads `--serve=0` as a flag turned off (−1): it means a free port.
    if (flags.serve && flags.serve_port < 0) flags.serve_port = 0;
    return Replay(flags);
  };
}

}  // namespace juggle
