// The project's HTTP server and client, over cpp-httplib (Debian libcpp-httplib-dev 0.11.4):
// HTTP/1.1 with keep-alive, a pool of request threads (concurrent requests), gzip when the
// client accepts it, Content-Length and Cache-Control on every answer. GET (and HEAD) go to
// one handler; POST goes to a second handler when one is given (bodies up to 1 MiB, larger ones
// 413); other methods are refused with 405. An answer may be streamed instead (chunked; e.g.
// server-sent events). The learner serves /metrics, /healthz and the dashboard with it
// (learner/http_routes.h); `juggle play` its live page (play/play_server.h).
// Thread-safety: the handler is called concurrently from the pool's threads; Start/Stop from
// one owner thread. The client functions are thread-safe.
#ifndef JUGGLE_COMMON_HTTP_SERVER_H_
#define JUGGLE_COMMON_HTTP_SERVER_H_

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>

#include "absl/status/statusor.h"

namespace juggle {

struct HttpRequest {
  std::string method;                         // "GET" (HEAD too) or "POST"
  std::string path;                           // without the query string
  std::map<std::string, std::string> params;  // query parameters, decoded
  std::string body;                           // POST's body
  std::string authorization;                  // the Authorization header, or ""
  std::string remote_address;                 // the client's IP address
  // The parameter `key`, or `fallback` when absent.
  std::string Param(const std::string& key, const std::string& fallback = "") const;
};

struct HttpResponse {
  HttpResponse() = default;
  HttpResponse(int status, std::string content_type, std::string body,
               std::string cache_control = "")
      : status(status),
        content_type(std::move(content_type)),
        body(std::move(body)),
        cache_control(std::move(cache_control)) {}
  int status = 200;
  std::string content_type = "text/plain; version=0.0.4";
  std::string body;
  // Empty: "no-store" (live data); e.g. "public, max-age=86400" for static files.
  std::string cache_control;
  // Set: the answer is streamed (chunked, `content_type`, `body` ignored). Called again and
  // again on the request's thread with a writer until it returns false (the stream ends); the
  // writer returns false once the client is gone. Each call should return within a second or
  // so (the server's Stop waits for it): wait for data with a timeout.
  using ChunkWriter = std::function<bool(const std::string& chunk)>;
  std::function<bool(const ChunkWriter& write)> stream;
  // With `stream`: called once when the stream is over, however it ended (the client left, the
  // server stopped, `stream` returned false).
  std::function<void()> stream_done;
};

class HttpServer {
 public:
  using Handler = std::function<HttpResponse(const HttpRequest& request)>;
  ~HttpServer();
  // Listens on 127.0.0.1:port (0.0.0.0 if `all_interfaces`); port 0 picks a free port.
  // `post`, if given, answers POST requests (else 405). UNAVAILABLE when the port cannot be
  // bound.
  static absl::StatusOr<std::unique_ptr<HttpServer>> Start(int port, bool all_interfaces,
                                                           Handler handler,
                                                           Handler post = nullptr);
  int port() const { return port_; }
  // Stops listening and waits for the server thread. Idempotent.
  void Stop();

 private:
  struct Impl;
  HttpServer();
  std::unique_ptr<Impl> impl_;
  int port_ = 0;
};

// What a GET returned.
struct HttpResult {
  int status = 0;
  std::string content_type;
  std::string body;
};

// GET http://127.0.0.1:port/path (path may carry a query string, already URL-encoded).
// UNAVAILABLE when nothing answers within 5 s. Any HTTP status is a result.
absl::StatusOr<HttpResult> HttpFetch(int port, const std::string& path);
// POST `body` (of `content_type`) to http://127.0.0.1:port/path, with an Authorization header
// when `authorization` is not empty. As HttpFetch.
absl::StatusOr<HttpResult> HttpPost(int port, const std::string& path, const std::string& body,
                                    const std::string& content_type = "application/json",
                                    const std::string& authorization = "");
// Reads the streamed answer of GET http://127.0.0.1:port/path, handing each received piece to
// `on_data` until it returns false or the server ends the stream. UNAVAILABLE when nothing
// answers; the status of a non-200 answer otherwise (FAILED_PRECONDITION with its body).
absl::Status HttpStream(int port, const std::string& path,
                        const std::function<bool(const std::string& data)>& on_data);
// The body of GET http://127.0.0.1:port/path whatever its status (tests and tools).
absl::StatusOr<std::string> HttpGet(int port, const std::string& path);

}  // namespace juggle

#endif  // JUGGLE_COMMON_HTTP_SERVER_H_
