// Metrics (Prometheus text rendering) and the small HTTP server that serves it.
#include "common/metrics.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <string>

#include "common/http_server.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::StartsWith;

TEST(MetricsTest, RendersLabelledCounterWithHelpAndType) {
  Metrics m;
  m.Declare("juggle_chunks_rejected_total", "counter", "Chunks rejected, by reason.");
  m.Add("juggle_chunks_rejected_total", 1, {{"reason", "nan"}});
  m.Add("juggle_chunks_rejected_total", 1, {{"reason", "nan"}});
  m.Add("juggle_chunks_rejected_total", 1, {{"reason", "shape"}});
  const std::string text = m.RenderPrometheus();
  EXPECT_THAT(text, HasSubstr("# HELP juggle_chunks_rejected_total Chunks rejected, by reason.\n"
                              "# TYPE juggle_chunks_rejected_total counter\n"));
  EXPECT_THAT(text, HasSubstr("\njuggle_chunks_rejected_total{reason=\"nan\"} 2\n"));
  EXPECT_THAT(text, HasSubstr("\njuggle_chunks_rejected_total{reason=\"shape\"} 1\n"));
}

TEST(MetricsTest, RendersSeveralLabelsSortedByNameAndUnlabelledSeriesBare) {
  Metrics m;
  m.Declare("g", "gauge", "A gauge.");
  m.Set("g", 0.5);
  m.Set("g", 3, {{"slot", "1"}, {"host", "a"}});
  const std::string text = m.RenderPrometheus();
  EXPECT_THAT(text, HasSubstr("\ng 0.5\n"));
  EXPECT_THAT(text, HasSubstr("\ng{host=\"a\",slot=\"1\"} 3\n"));
}

TEST(MetricsTest, SetReplacesAndAddAccumulates) {
  Metrics m;
  m.Declare("c", "counter", "c");
  m.Declare("g", "gauge", "g");
  m.Add("c", 2);
  m.Add("c", 3);
  m.Set("g", 7);
  m.Set("g", 4);
  EXPECT_EQ(m.Get("c"), 5);
  EXPECT_EQ(m.Get("g"), 4);
}

TEST(MetricsTest, HistogramBucketsAreCumulativeWithInfSumAndCount) {
  Metrics m;
  m.Declare("lag", "histogram", "Policy lag.", {1, 5, 10});
  for (double v : {0.5, 3.0, 7.0, 20.0}) m.Observe("lag", v);
  const std::string text = m.RenderPrometheus();
  EXPECT_THAT(text, HasSubstr("# HELP lag Policy lag.\n# TYPE lag histogram\n"
                              "lag_bucket{le=\"1\"} 1\n"
                              "lag_bucket{le=\"5\"} 2\n"
                              "lag_bucket{le=\"10\"} 3\n"
                              "lag_bucket{le=\"+Inf\"} 4\n"
                              "lag_sum 30.5\n"
                              "lag_count 4\n"));
}

TEST(MetricsTest, HistogramValueOnABucketBoundaryCountsInThatBucket) {
  Metrics m;
  m.Declare("h", "histogram", "h", {0, 1});
  m.Observe("h", 0);
  const std::string text = m.RenderPrometheus();
  EXPECT_THAT(text, HasSubstr("h_bucket{le=\"0\"} 1\n"));
  EXPECT_THAT(text, HasSubstr("h_bucket{le=\"1\"} 1\n"));
}

TEST(MetricsTest, EraseRemovesOnlyTheSeriesWithThatExactLabelValue) {
  Metrics m;
  m.Declare("age", "gauge", "Heartbeat age.");
  m.Set("age", 1.5, {{"slot", "1"}});
  m.Set("age", 2.5, {{"slot", "10"}});
  m.Set("age", 3.5, {{"slot", "0"}});
  m.Erase("age", "slot", "1");
  const std::string text = m.RenderPrometheus();
  EXPECT_THAT(text, Not(HasSubstr("age{slot=\"1\"}")));
  EXPECT_THAT(text, HasSubstr("age{slot=\"10\"} 2.5\n"));
  EXPECT_THAT(text, HasSubstr("age{slot=\"0\"} 3.5\n"));
  EXPECT_EQ(m.Get("age", {{"slot", "1"}}), 0);
  EXPECT_EQ(m.Get("age", {{"slot", "10"}}), 2.5);
}

TEST(MetricsTest, GetReturnsSeriesValuesHistogramCountAndZeroForUnknown) {
  Metrics m;
  m.Declare("c", "counter", "c");
  m.Declare("h", "histogram", "h", {1});
  m.Add("c", 4, {{"reason", "nan"}});
  m.Observe("h", 0.5);
  m.Observe("h", 2);
  EXPECT_EQ(m.Get("c", {{"reason", "nan"}}), 4);
  EXPECT_EQ(m.Get("c", {{"reason", "other"}}), 0);
  EXPECT_EQ(m.Get("c"), 0);
  EXPECT_EQ(m.Get("h"), 2);
  EXPECT_EQ(m.Get("never_declared"), 0);
}

// GET `path` over a raw socket; returns the whole response (status line, headers, body).
std::string RawGet(int port, const std::string& path) {
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
  const std::string req = "GET " + path + " HTTP/1.0\r\n\r\n";
  ::send(fd, req.data(), req.size(), MSG_NOSIGNAL);
  std::string response;
  char buf[4096];
  ssize_t n;
  while ((n = ::recv(fd, buf, sizeof(buf), 0)) > 0) response.append(buf, n);
  ::close(fd);
  return response;
}

HttpResponse TestHandler(const std::string& path) {
  if (path == "/x") return HttpResponse{200, "text/plain", "body of x\n"};
  return HttpResponse{404, "text/plain", "no such page: " + path + "\n"};
}

TEST(HttpServerTest, StartsOnAFreePortAndServesTheHandlersBody) {
  absl::StatusOr<std::unique_ptr<HttpServer>> server = HttpServer::Start(0, false, TestHandler);
  ASSERT_TRUE(server.ok()) << server.status();
  ASSERT_GT((*server)->port(), 0);
  absl::StatusOr<std::string> body = HttpGet((*server)->port(), "/x");
  ASSERT_TRUE(body.ok()) << body.status();
  EXPECT_EQ(*body, "body of x\n");
  const std::string raw = RawGet((*server)->port(), "/x");
  EXPECT_THAT(raw, StartsWith("HTTP/1.0 200 OK\r\n"));
  EXPECT_THAT(raw, HasSubstr("Content-Length: 10\r\n"));
}

TEST(HttpServerTest, AnswersAnUnknownPathWith404AndTheHandlersBody) {
  absl::StatusOr<std::unique_ptr<HttpServer>> server = HttpServer::Start(0, false, TestHandler);
  ASSERT_TRUE(server.ok()) << server.status();
  const std::string raw = RawGet((*server)->port(), "/missing");
  EXPECT_THAT(raw, StartsWith("HTTP/1.0 404 "));
  EXPECT_THAT(raw, HasSubstr("\r\n\r\nno such page: /missing\n"));
  absl::StatusOr<std::string> body = HttpGet((*server)->port(), "/missing");
  ASSERT_TRUE(body.ok()) << body.status();
  EXPECT_EQ(*body, "no such page: /missing\n");
}

TEST(HttpServerTest, RefusesNonGetRequestsWith405) {
  absl::StatusOr<std::unique_ptr<HttpServer>> server = HttpServer::Start(0, false, TestHandler);
  ASSERT_TRUE(server.ok()) << server.status();
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = htons((*server)->port());
  ASSERT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)), 0);
  const std::string req = "POST /x HTTP/1.0\r\n\r\n";
  ::send(fd, req.data(), req.size(), MSG_NOSIGNAL);
  std::string response;
  char buf[1024];
  ssize_t n;
  while ((n = ::recv(fd, buf, sizeof(buf), 0)) > 0) response.append(buf, n);
  ::close(fd);
  EXPECT_THAT(response, StartsWith("HTTP/1.0 405 "));
}

TEST(HttpServerTest, ServesMetricsRenderedAtRequestTime) {
  Metrics m;
  m.Declare("juggle_policy_version", "gauge", "Current policy version.");
  absl::StatusOr<std::unique_ptr<HttpServer>> server =
      HttpServer::Start(0, false, [&m](const std::string&) {
        return HttpResponse{200, "text/plain; version=0.0.4", m.RenderPrometheus()};
      });
  ASSERT_TRUE(server.ok()) << server.status();
  m.Set("juggle_policy_version", 3);
  absl::StatusOr<std::string> body = HttpGet((*server)->port(), "/metrics");
  ASSERT_TRUE(body.ok()) << body.status();
  EXPECT_THAT(*body, HasSubstr("\njuggle_policy_version 3\n"));
}

TEST(HttpServerTest, HttpGetFailsWithUnavailableAfterTheServerStops) {
  absl::StatusOr<std::unique_ptr<HttpServer>> server = HttpServer::Start(0, false, TestHandler);
  ASSERT_TRUE(server.ok()) << server.status();
  const int port = (*server)->port();
  (*server)->Stop();
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

}  // namespace
}  // namespace juggle
