// Token authentication and TLS / mutual TLS of the rollout service, for real: certificates made
// by `openssl` (a CA, the learner's certificate for 127.0.0.1, a worker certificate, and one
// signed by another CA), an in-process learner driven by raw stubs, and `juggle learner` +
// `juggle worker` processes that train together over mTLS with a token from a file (and whose
// HTTP endpoints listen on 127.0.0.1 only).
#include <sys/stat.h>

#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include <grpcpp/grpcpp.h>

#include "absl/strings/str_cat.h"
#include "common/testing/temp_dir.h"
#include "envs/registry.h"
#include "common/transport_security.h"
#include "worker/health_probe.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "learner/learner_server.h"
#include "proto/rollout.grpc.pb.h"
#include "tests/service_test_util.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
using testing::ChildProcess;
using testing::FreePort;
using testing::ScrapeMetric;
using testing::WaitFor;

constexpr char kToken[] = "s3cret-token-0123456789";

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Makes the certificates once for the suite, in a temporary directory.
class Certificates {
 public:
  static const Certificates& Get() {
    static const Certificates* certs = new Certificates();
    return *certs;
  }
  std::string dir;
  bool ok = false;
  std::string Path(const std::string& name) const { return dir + "/" + name; }

 private:
  Certificates() {
    dir = MakeTempDir("juggle_tls_");
    // EC keys (fast to make); the learner's certificate names 127.0.0.1 and localhost.
    const std::string script = absl::StrCat(
        "set -e; cd ", dir, "\n",
        "key() { openssl ecparam -name prime256v1 -genkey -noout -out $1 2>/dev/null; }\n",
        "ca() { key $1.key; openssl req -x509 -new -key $1.key -out $1.pem -days 2 "
        "-subj /CN=$1 2>/dev/null; }\n",
        "leaf() { key $1.key; openssl req -new -key $1.key -out $1.csr -subj /CN=$3 2>/dev/null;"
        " printf '%s\\n' \"$4\" > $1.ext;"
        " openssl x509 -req -in $1.csr -CA $2.pem -CAkey $2.key -CAcreateserial -out $1.pem"
        " -days 2 -extfile $1.ext 2>/dev/null; }\n",
        "ca ca; ca rogue_ca\n",
        "leaf learner ca localhost 'subjectAltName=DNS:localhost,IP:127.0.0.1'\n",
        "leaf worker ca worker 'extendedKeyUsage=clientAuth'\n",
        "leaf rogue_worker rogue_ca worker 'extendedKeyUsage=clientAuth'\n",
        "printf '", kToken, "\\n' > token; printf 'wrong-token\\n' > wrong_token\n");
    ok = !dir.empty() && std::system(("bash -c '" + EscapeSingleQuotes(script) + "'").c_str()) == 0;
  }
  static std::string EscapeSingleQuotes(const std::string& s) {
    std::string out;
    for (char c : s) {
      if (c == '\'') out += "'\\''";
      else out += c;
    }
    return out;
  }
};

// An in-process learner (right-foot config) with the given security.
class SecureLearner {
 public:
  explicit SecureLearner(const TransportSecurity& security) {
    dir_ = MakeTempDir("juggle_secure_");
    absl::StatusOr<LoadedConfig> config = LoadRunConfig("tests/data/tiny_right_foot.textproto");
    EXPECT_TRUE(config.ok()) << config.status();
    if (!config.ok()) return;
    LearnerOptions options;
    options.config = *std::move(config);
    options.run_dir = dir_ + "/run";
    ::mkdir(options.run_dir.c_str(), 0755);
    options.port = 0;
    options.metrics_port = LearnerOptions::kAnyFreePort;
    options.listen_all_interfaces = false;
    options.security = security;
    absl::StatusOr<std::unique_ptr<LearnerServer>> server = LearnerServer::Start(std::move(options));
    EXPECT_TRUE(server.ok()) << server.status();
    if (server.ok()) server_ = *std::move(server);
  }
  ~SecureLearner() {
    if (server_) server_->Shutdown();
    std::system(("rm -rf " + dir_).c_str());
  }
  LearnerServer* server() { return server_.get(); }
  std::string address() const { return absl::StrCat("127.0.0.1:", server_->port()); }

 private:
  std::string dir_;
  std::unique_ptr<LearnerServer> server_;
};

grpc::Status Register(const std::shared_ptr<grpc::Channel>& channel, const std::string& token) {
  auto stub = rpc::Rollout::NewStub(channel);
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
  if (!token.empty()) ctx.AddMetadata(kAuthorizationHeader, BearerValue(token));
  rpc::RegisterRequest req;
  req.set_requested_slot(-1);
  req.set_num_envs(1);
  req.set_hostname("secure-test");
  rpc::RegisterResponse resp;
  return stub->Register(&ctx, req, &resp);
}

// The local addresses (hex, as /proc/net/tcp and tcp6 write them) of the sockets listening on
// `port`: 0100007F is 127.0.0.1; 00000000 and 32 zeros are every interface (IPv4, IPv6).
std::vector<std::string> ListeningAddresses(int port) {
  std::istringstream table(ReadAll("/proc/net/tcp") + ReadAll("/proc/net/tcp6"));
  std::vector<std::string> addresses;
  std::string line;
  char wanted[8];
  std::snprintf(wanted, sizeof(wanted), ":%04X", port);
  while (std::getline(table, line)) {
    std::istringstream fields(line);
    std::string slot, local, remote, state;
    fields >> slot >> local >> remote >> state;
    if (state == "0A" && local.size() > 5 && local.substr(local.size() - 5) == wanted) {
      addresses.push_back(local.substr(0, local.size() - 5));
    }
  }
  return addresses;
}

// The learner's side: the token, its certificate and, for mutual TLS, the clients' CA.
TransportSecurity LearnerSecurity(const Certificates& c, bool mutual) {
  TransportSecurity s;
  s.token = kToken;
  s.cert_file = c.Path("learner.pem");
  s.key_file = c.Path("learner.key");
  if (mutual) s.ca_file = c.Path("ca.pem");
  return s;
}

std::shared_ptr<grpc::Channel> TlsChannel(const std::string& address, const Certificates& c,
                                          const std::string& client = "") {
  TransportSecurity s;
  s.ca_file = c.Path("ca.pem");
  if (!client.empty()) {
    s.cert_file = c.Path(client + ".pem");
    s.key_file = c.Path(client + ".key");
  }
  absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> creds = MakeChannelCredentials(s);
  EXPECT_TRUE(creds.ok()) << creds.status();
  return grpc::CreateChannel(address, *creds);
}

TEST(TransportSecurityTest, TokenMatchesOnlyTheExactBearerValue) {
  EXPECT_TRUE(TokenMatches("abc", "Bearer abc"));
  EXPECT_FALSE(TokenMatches("abc", "Bearer abd"));
  EXPECT_FALSE(TokenMatches("abc", "Bearer abcd"));
  EXPECT_FALSE(TokenMatches("abc", "abc"));
  EXPECT_FALSE(TokenMatches("abc", ""));
  EXPECT_TRUE(TokenMatches("", "")) << "no token configured: everything passes";
}

TEST(TransportSecurityTest, LoadTokenReadsTheFileOrTheEnvironmentAndRejectsBadTokens) {
  const Certificates& c = Certificates::Get();
  ASSERT_TRUE(c.ok) << "openssl failed in " << c.dir;
  ::unsetenv("JUGGLE_TOKEN");
  EXPECT_EQ(LoadToken("").value_or("?"), "") << "neither: no token";
  EXPECT_EQ(LoadToken(c.Path("token")).value_or("?"), kToken) << "trailing newline stripped";
  ::setenv("JUGGLE_TOKEN", "from-env", 1);
  EXPECT_EQ(LoadToken("").value_or("?"), "from-env");
  EXPECT_EQ(LoadToken(c.Path("token")).value_or("?"), kToken) << "the file wins";
  ::setenv("JUGGLE_TOKEN", "has space", 1);
  EXPECT_EQ(LoadToken("").status().code(), absl::StatusCode::kInvalidArgument);
  ::unsetenv("JUGGLE_TOKEN");
  const absl::StatusOr<std::string> missing = LoadToken(c.Path("no_such_file"));
  EXPECT_EQ(missing.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(missing.status().message()), HasSubstr("no_such_file"));
}

TEST(TransportSecurityTest, MismatchedTlsSettingsAreRefusedWithTheirReason) {
  const Certificates& c = Certificates::Get();
  ASSERT_TRUE(c.ok);
  TransportSecurity cert_only;
  cert_only.cert_file = c.Path("learner.pem");
  EXPECT_THAT(std::string(MakeServerCredentials(cert_only).status().message()),
              HasSubstr("give both a certificate"));
  TransportSecurity ca_only;
  ca_only.ca_file = c.Path("ca.pem");
  EXPECT_THAT(std::string(MakeServerCredentials(ca_only).status().message()),
              HasSubstr("needs the learner's own certificate"));
  TransportSecurity missing;
  missing.cert_file = c.Path("nope.pem");
  missing.key_file = c.Path("learner.key");
  EXPECT_EQ(MakeServerCredentials(missing).status().code(), absl::StatusCode::kNotFound);
}

TEST(SecureServiceTest, EveryRpcNeedsTheTokenOverTls) {
  const Certificates& c = Certificates::Get();
  ASSERT_TRUE(c.ok);
  SecureLearner learner(LearnerSecurity(c, /*mutual=*/false));
  ASSERT_NE(learner.server(), nullptr);
  auto tls = TlsChannel(learner.address(), c);

  const grpc::Status none = Register(tls, "");
  EXPECT_EQ(none.error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_THAT(none.error_message(), HasSubstr("requires a token"));
  EXPECT_EQ(Register(tls, "wrong-token").error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_TRUE(Register(tls, kToken).ok());

  // The other RPCs check it too.
  auto stub = rpc::Rollout::NewStub(tls);
  {
    grpc::ClientContext ctx;
    rpc::HeartbeatRequest req;
    rpc::HeartbeatResponse resp;
    EXPECT_EQ(stub->Heartbeat(&ctx, req, &resp).error_code(), grpc::StatusCode::UNAUTHENTICATED);
  }
  {
    grpc::ClientContext ctx;
    rpc::PolicyRequest req;
    req.set_min_version(-1);
    auto reader = stub->GetPolicy(&ctx, req);
    rpc::PolicyChunk chunk;
    EXPECT_FALSE(reader->Read(&chunk));
    EXPECT_EQ(reader->Finish().error_code(), grpc::StatusCode::UNAUTHENTICATED);
  }
  {
    grpc::ClientContext ctx;
    auto stream = stub->StreamTrajectories(&ctx);
    stream->WritesDone();
    EXPECT_EQ(stream->Finish().error_code(), grpc::StatusCode::UNAUTHENTICATED);
  }
  const Metrics& m = learner.server()->metrics();
  EXPECT_EQ(m.Get("juggle_rpcs_unauthenticated_total", {{"rpc", "Register"}}), 2);
  EXPECT_EQ(m.Get("juggle_rpcs_unauthenticated_total", {{"rpc", "Heartbeat"}}), 1);
  EXPECT_EQ(m.Get("juggle_rpcs_unauthenticated_total", {{"rpc", "GetPolicy"}}), 1);
  EXPECT_EQ(m.Get("juggle_rpcs_unauthenticated_total", {{"rpc", "StreamTrajectories"}}), 1);

  // Plaintext to the TLS port does not get through, token or not.
  auto plain = grpc::CreateChannel(learner.address(), grpc::InsecureChannelCredentials());
  EXPECT_EQ(Register(plain, kToken).error_code(), grpc::StatusCode::UNAVAILABLE);
  EXPECT_EQ(m.Get("juggle_workers_connected") <= 1, true);
}

TEST(SecureServiceTest, HealthProbeAnswersServingOnlyOverTheLearnersTransport) {
  const Certificates& c = Certificates::Get();
  ASSERT_TRUE(c.ok);
  SecureLearner learner(LearnerSecurity(c, /*mutual=*/false));
  ASSERT_NE(learner.server(), nullptr);
  TransportSecurity tls;
  tls.ca_file = c.Path("ca.pem");
  // The health service needs TLS but no token (probes hold no secrets beyond the CA).
  EXPECT_TRUE(ProbeLearnerHealth(learner.address(), tls, 5).ok());
  tls.server_name = "localhost";
  EXPECT_TRUE(ProbeLearnerHealth(learner.address(), tls, 5).ok()) << "name override";

  EXPECT_FALSE(ProbeLearnerHealth(learner.address(), TransportSecurity{}, 5).ok())
      << "plaintext to the TLS port";
  TransportSecurity rogue;
  rogue.ca_file = c.Path("rogue_ca.pem");
  EXPECT_FALSE(ProbeLearnerHealth(learner.address(), rogue, 5).ok()) << "another CA";
  tls.server_name = "not-the-learner";
  EXPECT_FALSE(ProbeLearnerHealth(learner.address(), tls, 5).ok()) << "wrong name";

  const int closed_port = FreePort();
  const absl::Status nobody =
      ProbeLearnerHealth(absl::StrCat("127.0.0.1:", closed_port), TransportSecurity{}, 5);
  EXPECT_EQ(nobody.code(), absl::StatusCode::kUnavailable) << nobody;
  EXPECT_THAT(std::string(nobody.message()), HasSubstr(absl::StrCat(":", closed_port)));
}

TEST(SecureServiceTest, MutualTlsAdmitsOnlyClientsWithACertificateFromTheCa) {
  const Certificates& c = Certificates::Get();
  ASSERT_TRUE(c.ok);
  SecureLearner learner(LearnerSecurity(c, /*mutual=*/true));
  ASSERT_NE(learner.server(), nullptr);
  EXPECT_NE(Register(TlsChannel(learner.address(), c), kToken).error_code(), grpc::StatusCode::OK)
      << "no client certificate";
  EXPECT_NE(Register(TlsChannel(learner.address(), c, "rogue_worker"), kToken).error_code(),
            grpc::StatusCode::OK)
      << "a client certificate from another CA";
  EXPECT_TRUE(Register(TlsChannel(learner.address(), c, "worker"), kToken).ok());
}

TEST(SecureServiceTest, LearnerAndWorkerProcessesTrainOverMutualTlsWithAToken) {
  const Certificates& c = Certificates::Get();
  ASSERT_TRUE(c.ok);
  const std::string dir = MakeTempDir("juggle_secure_mp_");
  const int port = FreePort(), metrics_port = FreePort();
  ::unsetenv("JUGGLE_TOKEN");
  ChildProcess learner(
      {"learner", "--config=tests/data/tiny_right_foot.textproto", "--port=" + std::to_string(port),
       "--metrics_port=" + std::to_string(metrics_port), "--run_dir=" + dir + "/run",
       "--token_file=" + c.Path("token"), "--tls_cert=" + c.Path("learner.pem"),
       "--tls_key=" + c.Path("learner.key"), "--tls_ca=" + c.Path("ca.pem")},
      dir + "/learner.log");
  auto worker_args = [&](const std::string& token_file) {
    return std::vector<std::string>{
        "worker", "--learner=127.0.0.1:" + std::to_string(port), "--envs=2", "--threads=1",
        "--token_file=" + c.Path(token_file), "--tls_ca=" + c.Path("ca.pem"),
        "--tls_cert=" + c.Path("worker.pem"), "--tls_key=" + c.Path("worker.key")};
  };
  ChildProcess worker(worker_args("token"), dir + "/worker.log");
  EXPECT_TRUE(WaitFor(
      [&] { return ScrapeMetric(metrics_port, "juggle_policy_version").value_or(0) >= 3; }, 90))
      << ReadAll(dir + "/learner.log") << ReadAll(dir + "/worker.log");
  // gRPC listens on every interface (workers are elsewhere); HTTP only on loopback.
  EXPECT_THAT(ListeningAddresses(port),
              ::testing::Contains(::testing::AnyOf("00000000", std::string(32, '0'))));
  EXPECT_THAT(ListeningAddresses(metrics_port), ::testing::ElementsAre("0100007F"))
      << "/metrics must not be exposed by default";
  // A worker with the wrong token stops at once with the learner's reason.
  ChildProcess intruder(worker_args("wrong_token"), dir + "/intruder.log");
  EXPECT_EQ(intruder.Wait(30), 1) << ReadAll(dir + "/intruder.log");
  EXPECT_THAT(ReadAll(dir + "/intruder.log"), HasSubstr("wrong token"));
  EXPECT_THAT(ReadAll(dir + "/learner.log"), Not(HasSubstr("warning: no token")));
  worker.Kill(SIGTERM);
  EXPECT_EQ(worker.Wait(30), 0);
  learner.Kill(SIGTERM);
  EXPECT_EQ(learner.Wait(60), 0) << ReadAll(dir + "/learner.log");
  if (!::testing::Test::HasFailure()) std::system(("rm -rf " + dir).c_str());
}

}  // namespace
}  // namespace juggle
