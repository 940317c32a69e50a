// The HTTP server (cpp-httplib underneath): HTTP/1.1 answers with the handler's status, type
// and body, keep-alive, concurrent requests, gzip when asked, 405 for other methods, POST to its
// own handler (413 above 1 MiB), streamed answers (ended by the handler or the client), and the
// client helpers' errors.
#include "common/http_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

// A raw socket to 127.0.0.1:port that sends `requests` (already formatted; the last one says
// "Connection: close") and reads until the server closes.
std::string RawExchange(int port, const std::string& requests) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = htons(port);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
    ::close(fd);
    return "";
  }
  timeval tv{5, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
  ::send(fd, requests.data(), requests.size(), MSG_NOSIGNAL);
  std::string response;
  char buf[4096];
  ssize_t n;
  while ((n = ::recv(fd, buf, sizeof(buf), 0)) > 0) response.append(buf, n);
  ::close(fd);
  return response;
}

HttpResponse TestHandler(const HttpRequest& request) {
  if (request.path == "/x") return HttpResponse{200, "text/plain", "body of x\n"};
  if (request.path == "/echo") {
    return HttpResponse{200, "text/plain", "n=" + request.Param("n", "none") + "\n"};
  }
  if (request.path == "/big") {
    return HttpResponse{200, "application/json", std::string(100000, ' ') + "\n"};
  }
  return HttpResponse{404, "text/plain", "no such page: " + request.path + "\n"};
}

TEST(HttpServerTest, StartsOnAFreePortAndServesTheHandlersBodyOverHttp11) {
  absl::StatusOr<std::unique_ptr<HttpServer>> server = HttpServer::Start(0, false, TestHandler);
  ASSERT_TRUE(server.ok()) << server.status();
  ASSERT_GT((*server)->port(), 0);
  absl::StatusOr<std::string> body = HttpGet((*server)->port(), "/x");
  ASSERT_TRUE(body.ok()) << body.status();
  EXPECT_EQ(*body, "body of x\n");
  const std::string raw =
      RawExchange((*server)->port(), "GET /x HTTP/1.1\r\nHost: a\r\nConnection: close\r\n\r\n");
  EXPECT_THAT(raw, StartsWith("HTTP/1.1 200 OK\r\n"));
  EXPECT_THAT(raw, HasSubstr("Content-Length: 10\r\n"));
  EXPECT_THAT(raw, HasSubstr("Content-Type: text/plain\r\n"));
  EXPECT_THAT(raw, HasSubstr("Cache-Control: no-store\r\n"));
}

TEST(HttpServerTest, PassesDecodedQueryParametersToTheHandler) {
  absl::StatusOr<std::unique_ptr<HttpServer>> server = HttpServer::Start(0, false, TestHandler);
  ASSERT_TRUE(server.ok()) << server.status();
  EXPECT_EQ(*HttpGet((*server)->port(), "/echo?n=a%20b"), "n=a b\n");
  EXPECT_EQ(*HttpGet((*server)->port(), "/echo"), "n=none\n");
}

TEST(HttpServerTest, AnswersSeveralRequestsOnOneKeepAliveConnection) {
  absl::StatusOr<std::unique_ptr<HttpServer>> server = HttpServer::Start(0, false, TestHandler);
  ASSERT_TRUE(server.ok()) << server.status();
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = htons((*server)->port());
  ASSERT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)), 0);
  timeval tv{5, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
  // Three requests one after the other on the same connection, each answered in full.
  for (int i = 0; i < 3; ++i) {
    const std::string request = "GET /x HTTP/1.1\r\nHost: a\r\n\r\n";
    ASSERT_EQ(::send(fd, request.data(), request.size(), MSG_NOSIGNAL),
              static_cast<ssize_t>(request.size()))
        << "the server closed the connection after " << i << " answer(s)";
    std::string response;
    char buf[4096];
    while (response.find("body of x\n") == std::string::npos) {
      const ssize_t n = ::recv(fd, buf, sizeof(buf), 0);
      ASSERT_GT(n, 0) << "no complete answer to request " << i << ": " << response;
      response.append(buf, n);
    }
    EXPECT_THAT(response, StartsWith("HTTP/1.1 200 OK\r\n"));
    EXPECT_THAT(response, HasSubstr("Keep-Alive: timeout="));
  }
  ::close(fd);
}

TEST(HttpServerTest, ServesRequestsConcurrentlyWhileAHandlerBlocks) {
  std::mutex mu;
  std::condition_variable cv;
  bool release = false;
  absl::StatusOr<std::unique_ptr<HttpServer>> server =
      HttpServer::Start(0, false, [&](const HttpRequest& r) {
        if (r.path == "/slow") {
          std::unique_lock<std::mutex> lock(mu);
          cv.wait_for(lock, std::chrono::seconds(10), [&] { return release; });
          return HttpResponse{200, "text/plain", "slow\n"};
        }
        return HttpResponse{200, "text/plain", "fast\n"};
      });
  ASSERT_TRUE(server.ok()) << server.status();
  const int port = (*server)->port();
  std::thread slow([&] { EXPECT_EQ(*HttpGet(port, "/slow"), "slow\n"); });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  // The slow request holds one thread; another request is answered meanwhile.
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(*HttpGet(port, "/fast"), "fast\n");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
  {
    std::lock_guard<std::mutex> lock(mu);
    release = true;
  }
  cv.notify_all();
  slow.join();
}

TEST(HttpServerTest, CompressesWithGzipWhenTheClientAcceptsIt) {
  absl::StatusOr<std::unique_ptr<HttpServer>> server = HttpServer::Start(0, false, TestHandler);
  ASSERT_TRUE(server.ok()) << server.status();
  const std::string raw = RawExchange(
      (*server)->port(),
      "GET /big HTTP/1.1\r\nHost: a\r\nAccept-Encoding: gzip\r\nConnection: close\r\n\r\n");
  EXPECT_THAT(raw, HasSubstr("Content-Encoding: gzip\r\n"));
  // 100,001 bytes of spaces compress to a few hundred.
  EXPECT_LT(raw.size(), 2000u);
}

TEST(HttpServerTest, AnswersAnUnknownPathWith404AndTheHandlersBody) {
  absl::StatusOr<std::unique_ptr<HttpServer>> server = HttpServer::Start(0, false, TestHandler);
  ASSERT_TRUE(server.ok()) << server.status();
  absl::StatusOr<HttpResult> result = HttpFetch((*server)->port(), "/missing");
  ASSERT_TRUE(result.ok()) << result.status();
  EXPECT_EQ(result->status, 404);
  EXPECT_EQ(result->body, "no such page: /missing\n");
  EXPECT_EQ(*HttpGet((*server)->port(), "/missing"), "no such page: /missing\n");
}

TEST(HttpServerTest, RefusesNonGetRequestsWith405) {
  absl::StatusOr<std::unique_ptr<HttpServer>> server = HttpServer::Start(0, false, TestHandler);
  ASSERT_TRUE(server.ok()) << server.status();
  const std::string raw = RawExchange(
      (*server)->port(),
      "POST /x HTTP/1.1\r\nHost: a\r\nContent-Length: 0\r\nConnection: close\r\n\r\n");
  EXPECT_THAT(raw, StartsWith("HTTP/1.1 405 "));
  EXPECT_THAT(raw, HasSubstr("Allow: GET, HEAD\r\n"));
}

TEST(HttpServerTest, HttpGetFailsWithUnavailableAfterTheServerStops) {
  absl::StatusOr<std::unique_ptr<HttpServer>> server = HttpServer::Start(0, false, TestHandler);
  ASSERT_TRUE(server.ok()) << server.status();
  const int port = (*server)->port();
  (*server)->Stop();
  (*server)->Stop();  // idempotent
  absl::StatusOr<std::string> body = HttpGet(port, "/x");
  EXPECT_EQ(body.status().code(), absl::StatusCode::kUnavailable);
  EXPECT_THAT(std::string(body.status().message()),
              HasSubstr("cannot connect to 127.0.0.1:" + std::to_string(port)));
}

TEST(HttpServerTest, StartFailsWithUnavailableWhenThePortIsTaken) {
  absl::StatusOr<std::unique_ptr<HttpServer>> first = HttpServer::Start(0, false, TestHandler);
  ASSERT_TRUE(first.ok()) << first.status();
  absl::StatusOr<std::unique_ptr<HttpServer>> second =
      HttpServer::Start((*first)->port(), false, TestHandler);
  EXPECT_EQ(second.status().code(), absl::StatusCode::kUnavailable);
  EXPECT_THAT(std::string(second.status().message()),
              HasSubstr("cannot listen on port " + std::to_string((*first)->port())));
}

TEST(HttpServerTest, APostHandlerGetsTheBodyAndTheAuthorizationHeader) {
  std::string seen_body, seen_auth, seen_method;
  absl::StatusOr<std::unique_ptr<HttpServer>> server = HttpServer::Start(
      0, false, TestHandler, [&](const HttpRequest& r) {
        seen_body = r.body;
        seen_auth = r.authorization;
        seen_method = r.method;
        return HttpResponse{201, "application/json", "{\"n\":" + r.Param("n", "0") + "}\n"};
      });
  ASSERT_TRUE(server.ok()) << server.status();
  absl::StatusOr<HttpResult> r =
      HttpPost((*server)->port(), "/cmd?n=3", "{\"cmd\":\"x\"}", "application/json", "Bearer t");
  ASSERT_TRUE(r.ok()) << r.status();
  EXPECT_EQ(r->status, 201);
  EXPECT_EQ(r->body, "{\"n\":3}\n");
  EXPECT_EQ(seen_body, "{\"cmd\":\"x\"}");
  EXPECT_EQ(seen_auth, "Bearer t");
  EXPECT_EQ(seen_method, "POST");
  // Bodies over 1 MiB never reach the handler.
  seen_body.clear();
  absl::StatusOr<HttpResult> huge = HttpPost((*server)->port(), "/cmd", std::string(2 << 20, 'x'));
  ASSERT_TRUE(huge.ok()) << huge.status();
  EXPECT_EQ(huge->status, 413);
  EXPECT_EQ(seen_body, "");
}

TEST(HttpServerTest, AStreamedAnswerArrivesPieceByPieceAndEndsItsStreamOnce) {
  std::atomic<int> done{0};
  absl::StatusOr<std::unique_ptr<HttpServer>> server =
      HttpServer::Start(0, false, [&](const HttpRequest&) {
        HttpResponse r;
        r.content_type = "text/event-stream";
        auto n = std::make_shared<int>(0);
        r.stream = [n](const HttpResponse::ChunkWriter& write) {
          if (*n == 3) return false;
          ++*n;
          return write("data: " + std::to_string(*n) + "\n\n");
        };
        r.stream_done = [&done] { ++done; };
        return r;
      });
  ASSERT_TRUE(server.ok()) << server.status();
  std::string received;
  absl::Status s = HttpStream((*server)->port(), "/events", [&](const std::string& data) {
    received += data;
    return true;
  });
  ASSERT_TRUE(s.ok()) << s;
  EXPECT_EQ(received, "data: 1\n\ndata: 2\n\ndata: 3\n\n");
  for (int i = 0; i < 100 && done.load() == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(done.load(), 1);
}

TEST(HttpServerTest, AStreamEndsWhenTheClientLeavesAndStopDoesNotWaitForever) {
  std::atomic<int> done{0};
  absl::StatusOr<std::unique_ptr<HttpServer>> server =
      HttpServer::Start(0, false, [&](const HttpRequest&) {
        HttpResponse r;
        r.content_type = "text/event-stream";
        r.stream = [](const HttpResponse::ChunkWriter& write) {
          std::this_thread::sleep_for(std::chrono::milliseconds(20));
          return write(": tick\n\n");
        };
        r.stream_done = [&done] { ++done; };
        return r;
      });
  ASSERT_TRUE(server.ok()) << server.status();
  int pieces = 0;
  // The client reads three pieces, then hangs up.
  absl::Status s = HttpStream((*server)->port(), "/events", [&](const std::string&) {
    return ++pieces < 3;
  });
  EXPECT_GE(pieces, 3);
  for (int i = 0; i < 300 && done.load() == 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(done.load(), 1);
  const auto start = std::chrono::steady_clock::now();
  (*server)->Stop();
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
}

}  // namespace
}  // namespace juggle
