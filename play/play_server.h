// The live page's HTTP side (`juggle play`, docs/play.md), over common/http_server.h:
//   GET  /             the page (web/play.html with three.js, web/scene.js, web/play.js)
//   GET  /api/scene    the scene and what the page may choose (PlaySession::Scene)
//   GET  /api/stream   server-sent events: {"type": "hello", "viewer": ID, ...} first, then
//                      frames; a viewer is one stream (at most max_viewers; more: 503)
//   POST /api/command?viewer=ID   one command (play/play_commands.h) as JSON: 200
//                      {"ok": true, "message"}; refused: 400 (malformed, or the world cannot
//                      take it), 403 (another viewer has control), 413 (too large)
//   GET  /api/stats    the session's times, the stream's share of them, viewers, drops
// One viewer controls at a time: the first to send a command (or "claim") while nobody does;
// it keeps control until it sends "release" or its stream ends. Everyone else watches.
// With a token every request must carry it (Authorization: Bearer, or ?token= for the
// stream): 401 otherwise. Thread-safe.
#ifndef JUGGLE_PLAY_PLAY_SERVER_H_
#define JUGGLE_PLAY_PLAY_SERVER_H_

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>

#include "absl/status/statusor.h"
#include "common/http_server.h"
#include "play/frame_hub.h"
#include "play/play_commands.h"
#include "play/play_session.h"

namespace juggle::play {

struct PlayServerOptions {
  int port = 8080;              // 0: a free port
  bool all_interfaces = false;  // 0.0.0.0 instead of 127.0.0.1 (then `token` is required)
  std::string token;            // "" : no token asked
  CommandLimits limits;
};

class PlayServer {
 public:
  // Serves `page` and `session`'s scene, stream and commands. INVALID_ARGUMENT for
  // all_interfaces without a token; UNAVAILABLE when the port cannot be bound.
  static absl::StatusOr<std::unique_ptr<PlayServer>> Start(PlaySession* session, FrameHub* hub,
                                                           std::string page,
                                                           PlayServerOptions options);
  ~PlayServer();
  int port() const { return http_->port(); }
  // Closes the streams and stops serving. Idempotent.
  void Stop();
  // The viewer in control (0: none).
  int64_t controller() const;

 private:
  PlayServer(PlaySession* session, FrameHub* hub, std::string page, PlayServerOptions options);
  HttpResponse Get(const HttpRequest& request);
  HttpResponse Post(const HttpRequest& request);
  HttpResponse Stream();
  bool Authorized(const HttpRequest& request) const;
  void ViewerLeft(int64_t viewer);

  PlaySession* session_;
  FrameHub* hub_;
  std::string page_;
  PlayServerOptions options_;
  std::unique_ptr<HttpServer> http_;
  mutable std::mutex mu_;
  int64_t controller_ = 0;
};

}  // namespace juggle::play

#endif  // JUGGLE_PLAY_PLAY_SERVER_H_
