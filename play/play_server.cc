#include "play/play_server.h"

#include <chrono>
#include <utility>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "nlohmann/json.hpp"

namespace juggle::play {
namespace {

using Json = nlohmann::json;

HttpResponse JsonAnswer(int status, const Json& body) {
  return HttpResponse(status, "application/json",
                      body.dump(-1, ' ', false, Json::error_handler_t::replace) + "\n");
}

HttpResponse Refusal(int status, const std::string& message) {
  return JsonAnswer(status, {{"ok", false}, {"error", message}});
}

// Constant-time comparison: the token is a secret.
bool SameSecret(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

}  // namespace

PlayServer::PlayServer(PlaySession* session, FrameHub* hub, std::string page,
                       PlayServerOptions options)
    : session_(session), hub_(hub), page_(std::move(page)), options_(std::move(options)) {}

PlayServer::~PlayServer() { Stop(); }

absl::StatusOr<std::unique_ptr<PlayServer>> PlayServer::Start(PlaySession* session,
                                                              FrameHub* hub, std::string page,
                                                              PlayServerOptions options) {
  if (options.all_interfaces && options.token.empty()) {
    return absl::InvalidArgumentError(
        "serving the live page beyond 127.0.0.1 needs a token (--token_file or JUGGLE_TOKEN)");
  }
  std::unique_ptr<PlayServer> s(
      new PlayServer(session, hub, std::move(page), std::move(options)));
  PlayServer* self = s.get();
  absl::StatusOr<std::unique_ptr<HttpServer>> http = HttpServer::Start(
      s->options_.port, s->options_.all_interfaces,
      [self](const HttpRequest& r) { return self->Get(r); },
      [self](const HttpRequest& r) { return self->Post(r); });
  if (!http.ok()) return http.status();
  s->http_ = *std::move(http);
  return s;
}

void PlayServer::Stop() {
  hub_->Close();
  if (http_) http_->Stop();
}

int64_t PlayServer::controller() const {
  std::lock_guard<std::mutex> lock(mu_);
  return controller_;
}

bool PlayServer::Authorized(const HttpRequest& request) const {
  if (options_.token.empty()) return true;
  return SameSecret(request.authorization, "Bearer " + options_.token) ||
         SameSecret(request.Param("token"), options_.token);
}

void PlayServer::ViewerLeft(int64_t viewer) {
  hub_->Leave(viewer);
  std::lock_guard<std::mutex> lock(mu_);
  if (controller_ == viewer) controller_ = 0;
}

HttpResponse PlayServer::Stream() {
  const std::optional<int64_t> viewer = hub_->Join();
  if (!viewer.has_value()) {
    return HttpResponse(503, "text/plain",
                        "the live page has as many viewers as it takes; try again later\n");
  }
  HttpResponse r;
  r.content_type = "text/event-stream";
  const int64_t id = *viewer;
  const Json hello = {{"type", "hello"}, {"viewer", id}, {"controller", controller()}};
  auto first = std::make_shared<std::string>(
      absl::StrCat("retry: 1000\ndata: ", hello.dump(), "\n\n", session_->LatestFrame()));
  auto idle = std::make_shared<int>(0);
  FrameHub* hub = hub_;
  r.stream = [hub, id, first, idle](const HttpResponse::ChunkWriter& write) {
    if (!first->empty()) {
      const bool ok = write(*first);
      first->clear();
      return ok;
    }
    std::optional<std::string> message = hub->Take(id, std::chrono::milliseconds(250));
    if (message.has_value()) {
      *idle = 0;
      return write(*message);
    }
    // Nothing to send: a comment every ~2 s finds out whether the viewer is still there.
    if (++*idle >= 8) {
      *idle = 0;
      return write(": idle\n\n");
    }
    return !hub->closed() && hub->has_viewer(id);
  };
  r.stream_done = [this, id] { ViewerLeft(id); };
  return r;
}

HttpResponse PlayServer::Get(const HttpRequest& request) {
  if (!Authorized(request)) return Refusal(401, "this page needs the token");
  if (request.path == "/" || request.path == "/index.html") {
    return HttpResponse(200, "text/html; charset=utf-8", page_);
  }
  if (request.path == "/api/scene") return JsonAnswer(200, session_->Scene());
  if (request.path == "/api/stream") return Stream();
  if (request.path == "/api/stats") {
    const SessionTimes t = session_->times();
    return JsonAnswer(200, {{"steps", t.steps},
                            {"frames", t.frames},
                            {"step_seconds", t.step_seconds},
                            {"frame_seconds", t.frame_seconds},
                            {"stream_share", t.stream_share()},
                            {"sim_seconds", t.sim_seconds},
                            {"wall_seconds", t.wall_seconds},
                            {"achieved_speed", session_->achieved_speed()},
                            {"episodes", session_->episodes()},
                            {"viewers", hub_->viewers()},
                            {"published", hub_->published()},
                            {"dropped", hub_->dropped()},
                            {"controller", controller()}});
  }
  return Refusal(404, absl::StrCat("no page ", request.path.substr(0, 64)));
}

HttpResponse PlayServer::Post(const HttpRequest& request) {
  if (!Authorized(request)) return Refusal(401, "this page needs the token");
  if (request.path != "/api/command") {
    return Refusal(404, absl::StrCat("no command endpoint ", request.path.substr(0, 64)));
  }
  int64_t viewer = 0;
  if (!absl::SimpleAtoi(request.Param("viewer"), &viewer) || viewer <= 0) {
    return Refusal(400, "the command needs ?viewer=ID (the id of the page's stream)");
  }
  if (!hub_->has_viewer(viewer)) {
    return Refusal(403, absl::StrCat("no viewer ", viewer, " is watching: open the stream first"));
  }
  absl::StatusOr<PlayCommand> command = ParsePlayCommand(request.body, options_.limits);
  if (!command.ok()) {
    const bool too_long = request.body.size() > options_.limits.max_bytes;
    return Refusal(too_long ? 413 : 400, std::string(command.status().message()));
  }
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (command->kind == CommandKind::kRelease) {
      if (controller_ == viewer) controller_ = 0;
      return JsonAnswer(200, {{"ok", true}, {"message", "control released"}, {"controller", 0}});
    }
    if (controller_ != 0 && controller_ != viewer) {
      return Refusal(403, absl::StrCat("viewer ", controller_,
                                       " has control; watch, or wait until it releases it"));
    }
    controller_ = viewer;
    if (command->kind == CommandKind::kClaim) {
      return JsonAnswer(200, {{"ok", true}, {"message", "you have control"},
                              {"controller", viewer}});
    }
  }
  absl::StatusOr<std::string> done = session_->Submit(*command);
  if (!done.ok()) {
    const int status = done.status().code() == absl::StatusCode::kDeadlineExceeded ? 503 : 400;
    return Refusal(status, std::string(done.status().message()));
  }
  return JsonAnswer(200, {{"ok", true}, {"message", *done}, {"controller", viewer}});
}

}  // namespace juggle::play
