#include "common/http_server.h"

#include <sys/socket.h>

#include <atomic>
#include <memory>
#include <chrono>
#include <thread>

#include <httplib.h>

#include "absl/strings/str_cat.h"

namespace juggle {
namespace {

// Request threads: a browser keeps up to 6 keep-alive connections and each holds a thread
// while open, so a few more than one page needs; idle threads cost nothing.
constexpr int kRequestThreads = 8;

}  // namespace

std::string HttpRequest::Param(const std::string& key, const std::string& fallback) const {
  auto it = params.find(key);
  return it == params.end() ? fallback : it->second;
}

struct HttpServer::Impl {
  httplib::Server server;
  std::thread thread;
  std::atomic<bool> exited{false};  // the server thread returned from its accept loop
};

HttpServer::HttpServer() : impl_(std::make_unique<Impl>()) {}
HttpServer::~HttpServer() { Stop(); }

absl::StatusOr<std::unique_ptr<HttpServer>> HttpServer::Start(int port, bool all_interfaces,
                                                              Handler handler, Handler post) {
  std::unique_ptr<HttpServer> s(new HttpServer());
  httplib::Server& server = s->impl_->server;
  server.new_task_queue = [] { return new httplib::ThreadPool(kRequestThreads); };
  server.set_keep_alive_max_count(1000);
  server.set_keep_alive_timeout(10);
  server.set_read_timeout(5);
  server.set_write_timeout(5);
  server.set_payload_max_length(1 << 20);
  // httplib's default also sets SO_REUSEPORT, which lets a second server bind a port in use
  // (and steal half its connections): keep only SO_REUSEADDR (rebinding after a restart).
  server.set_socket_options([](socket_t sock) {
    const int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });
  const auto to_request = [](const httplib::Request& req, const char* method) {
    HttpRequest request;
    request.method = method;
    request.path = req.path;
    for (const auto& [key, value] : req.params) request.params[key] = value;
    request.authorization = req.get_header_value("Authorization");
    request.remote_address = req.remote_addr;
    return request;
  };
  const auto answer = [](HttpResponse response, httplib::Response& res) {
    res.status = response.status;
    res.set_header("Cache-Control",
                   response.cache_control.empty() ? "no-store" : response.cache_control);
    if (!response.stream) {
      res.set_content(std::move(response.body), response.content_type.c_str());
      return;
    }
    auto stream = std::move(response.stream);
    auto done = std::move(response.stream_done);
    res.set_header("X-Accel-Buffering", "no");
    res.set_chunked_content_provider(
        response.content_type,
        [stream](size_t, httplib::DataSink& sink) {
          const HttpResponse::ChunkWriter write = [&sink](const std::string& chunk) {
            return sink.is_writable() && sink.write(chunk.data(), chunk.size());
          };
          if (stream(write)) return true;
          sink.done();
          return true;
        },
        [done](bool) {
          if (done) done();
        });
  };
  server.Get(".*", [handler, to_request, answer](const httplib::Request& req,
                                                 httplib::Response& res) {
    answer(handler(to_request(req, "GET")), res);
  });
  const auto refuse = [](const httplib::Request&, httplib::Response& res) {
    res.status = 405;
    res.set_header("Allow", "GET, HEAD");
    res.set_content("only GET and HEAD\n", "text/plain");
  };
  if (post) {
    server.Post(".*", [post, to_request, answer](const httplib::Request& req,
                                                 httplib::Response& res) {
      HttpRequest request = to_request(req, "POST");
      request.body = req.body;
      answer(post(request), res);
    });
  } else {
    server.Post(".*", refuse);
  }
  server.Put(".*", refuse);
  server.Patch(".*", refuse);
  server.Delete(".*", refuse);
  server.set_exception_handler(
      [](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
        res.status = 500;
        res.set_content("internal error\n", "text/plain");
      });
  const std::string host = all_interfaces ? "0.0.0.0" : "127.0.0.1";
  if (port == 0) {
    s->port_ = server.bind_to_any_port(host);
    if (s->port_ <= 0) return absl::UnavailableError("http: cannot listen on any port");
  } else {
    if (!server.bind_to_port(host, port)) {
      return absl::UnavailableError(absl::StrCat("http: cannot listen on port ", port));
    }
    s->port_ = port;
  }
  Impl* impl = s->impl_.get();
  impl->thread = std::thread([impl] {
    impl->server.listen_after_bind();
    impl->exited = true;
  });
  // Stop() only stops a running server: wait until the thread is in its accept loop.
  while (!server.is_running() && !impl->exited) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (impl->exited) {
    impl->thread.join();
    return absl::UnavailableError(absl::StrCat("http: the server on port ", s->port_,
                                               " stopped as it started"));
  }
  return s;
}

void HttpServer::Stop() {
  if (!impl_ || !impl_->thread.joinable()) return;
  impl_->server.stop();
  impl_->thread.join();
}

namespace {

// A client of 127.0.0.1:port with the helpers' 5 s timeouts.
std::unique_ptr<httplib::Client> LocalClient(int port) {
  auto client = std::make_unique<httplib::Client>("127.0.0.1", port);
  client->set_connection_timeout(5);
  client->set_read_timeout(5);
  return client;
}

// The answer of a request to 127.0.0.1:port, or UNAVAILABLE when none came.
absl::StatusOr<HttpResult> ToResult(httplib::Result result, int port) {
  if (!result) {
    return absl::UnavailableError(absl::StrCat("cannot connect to 127.0.0.1:", port, ": ",
                                               httplib::to_string(result.error())));
  }
  HttpResult out;
  out.status = result->status;
  out.content_type = result->get_header_value("Content-Type");
  out.body = std::move(result->body);
  return out;
}

}  // namespace

absl::StatusOr<HttpResult> HttpFetch(int port, const std::string& path) {
  return ToResult(LocalClient(port)->Get(path), port);
}

absl::StatusOr<HttpResult> HttpPost(int port, const std::string& path, const std::string& body,
                                    const std::string& content_type,
                                    const std::string& authorization) {
  httplib::Headers headers;
  if (!authorization.empty()) headers.emplace("Authorization", authorization);
  return ToResult(LocalClient(port)->Post(path.c_str(), headers, body, content_type.c_str()),
                  port);
}

absl::Status HttpStream(int port, const std::string& path,
                        const std::function<bool(const std::string& data)>& on_data) {
  std::unique_ptr<httplib::Client> client = LocalClient(port);
  int status = 0;
  std::string error_body;
  httplib::Result result = client->Get(
      path.c_str(),
      [&status](const httplib::Response& response) {
        status = response.status;
        return true;
      },
      [&](const char* data, size_t length) {
        if (status != 200) {
          error_body.append(data, length);
          return true;
        }
        return on_data(std::string(data, length));
      });
  if (status != 0 && status != 200) {
    return absl::FailedPreconditionError(absl::StrCat("HTTP ", status, ": ", error_body));
  }
  if (!result && status == 0) {
    return absl::UnavailableError(absl::StrCat("cannot connect to 127.0.0.1:", port, ": ",
                                               httplib::to_string(result.error())));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::string> HttpGet(int port, const std::string& path) {
  absl::StatusOr<HttpResult> result = HttpFetch(port, path);
  if (!result.ok()) return result.status();
  return std::move(result->body);
}

}  // namespace juggle
