// tests/netfaults/fault_proxy: the proxy against a plain echo server on loopback (real sockets,
// real threads): bytes pass unchanged; latency stays within its jitter bounds; a paused
// direction holds its bytes until resumed; a stalled accept never answers; resets come at the
// seeded rate and the same seed resets the same connections at the same messages.
#include "tests/netfaults/fault_proxy.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle::netfaults {
namespace {

using Clock = std::chrono::steady_clock;
using ::testing::HasSubstr;

double Since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Echoes every byte back on every connection until destroyed.
class EchoServer {
 public:
  EchoServer() {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a));
    ::listen(fd_, 64);
    socklen_t len = sizeof(a);
    ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    thread_ = std::thread([this] {
      while (!stop_) {
        pollfd p{fd_, POLLIN, 0};
        if (::poll(&p, 1, 20) <= 0) continue;
        const int c = ::accept(fd_, nullptr, nullptr);
        if (c < 0) continue;
        clients_.emplace_back([this, c] {
          char buf[65536];
          while (!stop_) {
            pollfd q{c, POLLIN, 0};
            if (::poll(&q, 1, 20) <= 0) continue;
            const ssize_t n = ::recv(c, buf, sizeof(buf), 0);
            if (n <= 0) break;
            received_ += n;
            if (::send(c, buf, size_t(n), MSG_NOSIGNAL) != n) break;
          }
          ::close(c);
        });
      }
    });
  }
  ~EchoServer() {
    stop_ = true;
    thread_.join();
    for (std::thread& t : clients_) t.join();
    ::close(fd_);
  }
  int port() const { return port_; }
  int64_t received() const { return received_; }

 private:
  int fd_ = -1, port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<int64_t> received_{0};
  std::thread thread_;
  std::vector<std::thread> clients_;  // only the accept thread touches it until the join
};

int Connect(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(static_cast<uint16_t>(port));
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0) {
    ::close(fd);
    return -1;
  }
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
  return fd;
}

// Reads exactly n bytes within `seconds`; the bytes read, shorter on timeout, EOF or reset
// (*error then holds errno, or 0 for EOF/timeout).
std::string ReadN(int fd, size_t n, double seconds, int* error = nullptr) {
  std::string out;
  const auto start = Clock::now();
  if (error) *error = 0;
  while (out.size() < n && Since(start) < seconds) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 10) <= 0) continue;
    char buf[65536];
    const ssize_t r = ::recv(fd, buf, std::min(sizeof(buf), n - out.size()), 0);
    if (r < 0 && error) *error = errno;
    if (r <= 0) break;
    out.append(buf, size_t(r));
  }
  return out;
}

std::unique_ptr<FaultProxy> StartProxy(const EchoServer& echo, uint64_t seed = 1) {
  auto p = FaultProxy::Start("127.0.0.1", 0, "127.0.0.1", echo.port(), seed);
  EXPECT_TRUE(p.ok()) << p.status();
  return p.ok() ? std::move(*p) : nullptr;
}

TEST(FaultProxyTest, ForwardsAMegabyteBothWaysUnchanged) {
  EchoServer echo;
  auto proxy = StartProxy(echo);
  const int fd = Connect(proxy->port());
  ASSERT_GE(fd, 0);
  std::string data(1 << 20, '\0');
  std::mt19937_64 rng(3);
  for (char& ch : data) ch = static_cast<char>(rng());
  std::thread writer([&] { ::send(fd, data.data(), data.size(), MSG_NOSIGNAL); });
  const std::string back = ReadN(fd, data.size(), 20);
  writer.join();
  EXPECT_TRUE(back == data) << "got " << back.size() << " bytes, or different ones";
  // The proxy counts a segment after its send returns, so the client can hold the last bytes
  // before the count does (a race a loaded machine can expose; this test failed once in a full
  // suite at 0.07 s, its log since overwritten): wait for the counts, 2 s at most.
  const auto start = Clock::now();
  while ((proxy->stats().bytes_up < int64_t(data.size()) ||
          proxy->stats().bytes_down < int64_t(data.size())) &&
         Since(start) < 2) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_EQ(proxy->stats().bytes_up, int64_t(data.size()));
  EXPECT_EQ(proxy->stats().bytes_down, int64_t(data.size()));
  ::close(fd);
}

TEST(FaultProxyTest, RoundTripsTakeTheAddedLatencyWithinItsJitter) {
  EchoServer echo;
  auto proxy = StartProxy(echo);
  Faults f;
  ASSERT_TRUE(ApplyControlLine("latency up 0.1 0.02", &f).ok());
  ASSERT_TRUE(ApplyControlLine("latency down 0.05", &f).ok());
  proxy->SetFaults(f);
  const int fd = Connect(proxy->port());
  double lo = 1e9, hi = 0;
  for (int i = 0; i < 10; ++i) {
    const auto t = Clock::now();
    ASSERT_EQ(::send(fd, "ping", 4, MSG_NOSIGNAL), 4);
    ASSERT_EQ(ReadN(fd, 4, 2), "ping");
    lo = std::min(lo, Since(t));
    hi = std::max(hi, Since(t));
  }
  // 0.15 s ± 0.02 s, plus scheduling slack on a loaded machine.
  EXPECT_GE(lo, 0.13 - 0.002);
  EXPECT_LE(hi, 0.17 + 0.05);
  ::close(fd);
}

TEST(FaultProxyTest, APausedDownstreamDeliversRequestsButHoldsRepliesUntilResumed) {
  EchoServer echo;
  auto proxy = StartProxy(echo);
  const int fd = Connect(proxy->port());
  ASSERT_EQ(::send(fd, "a", 1, MSG_NOSIGNAL), 1);
  ASSERT_EQ(ReadN(fd, 1, 2), "a");
  Faults f;
  ASSERT_TRUE(ApplyControlLine("pause down", &f).ok());
  proxy->SetFaults(f);
  ASSERT_EQ(::send(fd, "bc", 2, MSG_NOSIGNAL), 2);
  EXPECT_EQ(ReadN(fd, 2, 0.5), "") << "a reply crossed the one-way partition";
  EXPECT_EQ(echo.received(), 3) << "the request did not get through";
  ASSERT_TRUE(ApplyControlLine("resume down", &f).ok());
  proxy->SetFaults(f);
  EXPECT_EQ(ReadN(fd, 2, 2), "bc") << "the held reply was not delivered after the heal";
  ::close(fd);
}

TEST(FaultProxyTest, AStalledAcceptNeverAnswersAndIsClosedWhenItsClientHangsUp) {
  EchoServer echo;
  auto proxy = StartProxy(echo);
  Faults f;
  f.stall_new = true;
  proxy->SetFaults(f);
  const int fd = Connect(proxy->port());
  ASSERT_GE(fd, 0) << "a stalled proxy still accepts";
  ASSERT_EQ(::send(fd, "hello", 5, MSG_NOSIGNAL), 5);
  EXPECT_EQ(ReadN(fd, 5, 0.5), "");
  EXPECT_EQ(echo.received(), 0);
  // Lifting the stall does not revive a stalled connection (a hung peer stays hung) ...
  proxy->SetFaults(Faults());
  EXPECT_EQ(ReadN(fd, 5, 0.3), "");
  EXPECT_EQ(proxy->stats().stalled, 1);
  EXPECT_EQ(proxy->stats().open, 1);
  ::close(fd);
  EXPECT_TRUE([&] {
    for (int i = 0; i < 100 && proxy->stats().open != 0; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return proxy->stats().open == 0;
  }()) << "the stalled connection was not closed after its client hung up";
  // ... but new connections flow again.
  const int again = Connect(proxy->port());
  ASSERT_EQ(::send(again, "x", 1, MSG_NOSIGNAL), 1);
  EXPECT_EQ(ReadN(again, 1, 2), "x");
  ::close(again);
}

TEST(FaultProxyTest, ResetAllSendsAResetToTheClient) {
  EchoServer echo;
  auto proxy = StartProxy(echo);
  const int fd = Connect(proxy->port());
  ASSERT_EQ(::send(fd, "a", 1, MSG_NOSIGNAL), 1);
  ASSERT_EQ(ReadN(fd, 1, 2), "a");
  proxy->ResetAll();
  int error = 0;
  EXPECT_EQ(ReadN(fd, 1, 2, &error), "");
  EXPECT_EQ(error, ECONNRESET);
  EXPECT_EQ(proxy->stats().resets, 1);
  ::close(fd);
}

// Runs `connections` sequential connections of up to `messages` request/echo round trips each;
// returns, per connection, the message at which it was reset (-1: never).
std::vector<int> ResetSchedule(uint64_t seed, double probability, int connections, int messages) {
  EchoServer echo;
  auto proxy = StartProxy(echo, seed);
  Faults f;
  f.reset_probability = probability;
  proxy->SetFaults(f);
  std::vector<int> at;
  for (int c = 0; c < connections; ++c) {
    const int fd = Connect(proxy->port());
    int reset_at = -1;
    for (int m = 0; m < messages && reset_at < 0; ++m) {
      if (::send(fd, "msg", 3, MSG_NOSIGNAL) != 3 || ReadN(fd, 3, 2) != "msg") reset_at = m;
    }
    at.push_back(reset_at);
    ::close(fd);
  }
  return at;
}

TEST(FaultProxyTest, ResetsComeAtTheSeededRateAndTheSameSeedRepeatsThem) {
  const std::vector<int> a = ResetSchedule(11, 0.1, 20, 10);
  const std::vector<int> b = ResetSchedule(11, 0.1, 20, 10);
  const std::vector<int> c = ResetSchedule(12, 0.1, 20, 10);
  EXPECT_EQ(a, b) << "the same seed reset other connections or messages";
  EXPECT_NE(a, c) << "another seed gave the same schedule";
  // Each round trip draws twice (request and echo): P(survive 10) = 0.9^20 = 12 %.
  int survived = 0;
  for (int at : a) survived += at < 0;
  EXPECT_LE(survived, 8) << "far fewer resets than 10 % per segment";
  EXPECT_LT(survived, 20);
}

TEST(FaultProxyTest, RefusedConnectionsAreResetAtOnce) {
  EchoServer echo;
  auto proxy = StartProxy(echo);
  Faults f;
  f.refuse_probability = 1;
  proxy->SetFaults(f);
  const int fd = Connect(proxy->port());
  int error = 0;
  EXPECT_EQ(ReadN(fd, 1, 2, &error), "");
  EXPECT_EQ(error, ECONNRESET);
  EXPECT_EQ(echo.received(), 0);
  ::close(fd);
}

TEST(FaultProxyTest, ControlLinesSetFaultsAndBadLinesNameThemselves) {
  Faults f;
  ASSERT_TRUE(ApplyControlLine("latency both 0.1 0.02", &f).ok());
  EXPECT_DOUBLE_EQ(f.upstream.latency_s, 0.1);
  EXPECT_DOUBLE_EQ(f.downstream.jitter_s, 0.02);
  ASSERT_TRUE(ApplyControlLine("pause down", &f).ok());
  EXPECT_TRUE(f.downstream.paused);
  EXPECT_FALSE(f.upstream.paused);
  ASSERT_TRUE(ApplyControlLine("reset_probability 0.05", &f).ok());
  ASSERT_TRUE(ApplyControlLine("stall_new on", &f).ok());
  EXPECT_THAT(Describe(f), HasSubstr("down paused"));
  EXPECT_THAT(Describe(f), HasSubstr("reset 5.0%"));
  ASSERT_TRUE(ApplyControlLine("heal", &f).ok());
  EXPECT_FALSE(f.stall_new);
  EXPECT_EQ(f.reset_probability, 0);
  const absl::Status bad = ApplyControlLine("latency sideways 1", &f);
  EXPECT_EQ(bad.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(bad.message()), HasSubstr("\"latency sideways 1\""));
  EXPECT_FALSE(ApplyControlLine("reset_probability 2", &f).ok());
  EXPECT_FALSE(ApplyControlLine("latency up 0.1 0.5", &f).ok());  // jitter above latency
  EXPECT_FALSE(ApplyControlLine("explode", &f).ok());
}

}  // namespace
}  // namespace juggle::netfaults
