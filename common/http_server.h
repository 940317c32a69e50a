// A minimal HTTP/1.0 server for GET requests (/metrics for Prometheus, / for a status page):
// one accept thread, one request per connection. Not for untrusted networks' load; it serves
// dashboards. Thread-safe: the handler is called from the server's thread.
#ifndef JUGGLE_COMMON_HTTP_SERVER_H_
#define JUGGLE_COMMON_HTTP_SERVER_H_

#include <atomic>
#include <functional>
#include <string>
#include <thread>

#include "absl/status/statusor.h"

namespace juggle {

struct HttpResponse {
  int status = 200;
  std::string content_type = "text/plain; version=0.0.4";
  std::string body;
};

class HttpServer {
 public:
  using Handler = std::function<HttpResponse(const std::string& path)>;
  ~HttpServer();
  // Listens on 127.0.0.1:port (0.0.0.0 if `all_interfaces`); port 0 picks a free port.
  static absl::StatusOr<std::unique_ptr<HttpServer>> Start(int port, bool all_interfaces,
                                                           Handler handler);
  int port() const { return port_; }
  void Stop();

 private:
  HttpServer() = default;
  void Serve();
  int fd_ = -1;
  int port_ = 0;
  Handler handler_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// GET http://127.0.0.1:port/path; returns the body (tests and tools).
absl::StatusOr<std::string> HttpGet(int port, const std::string& path);

}  // namespace juggle

#endif  // JUGGLE_COMMON_HTTP_SERVER_H_
