// The live page's HTTP side on a real session (soccer, zero action) over loopback: the page and
// scene are served; the stream starts with the viewer's id; commands are refused with the right
// status and a message (malformed JSON 400, too large 413, unknown command 400, no or unknown
// viewer 400/403, another viewer in control 403) and lose nothing; one viewer controls at a
// time until it releases or leaves; the viewer limit answers 503; a token is asked for when set
// (401 without it) and required beyond 127.0.0.1.
#include "play/play_server.h"

#include <atomic>
#include <chrono>
#include <thread>

#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "eval/controller.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "nlohmann/json.hpp"
#include "play/env_world.h"

namespace juggle::play {
namespace {

using ::testing::HasSubstr;

// A viewer: the stream read on its own thread until Leave(); its id from the hello message.
class Viewer {
 public:
  explicit Viewer(int port, const std::string& path = "/api/stream") {
    thread_ = std::thread([this, port, path] {
      status_ = HttpStream(port, path, [this](const std::string& data) {
        received_ += data;
        const size_t at = received_.find("\"viewer\":");
        if (id_ == 0 && at != std::string::npos) id_ = std::atoi(received_.c_str() + at + 9);
        return !leave_;
      });
      done_ = true;
    });
    for (int i = 0; i < 500 && id_ == 0 && !done_; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  ~Viewer() { Leave(); }
  void Leave() {
    leave_ = true;
    if (thread_.joinable()) thread_.join();
  }
  int64_t id() const { return id_; }
  bool done() const { return done_; }
  const absl::Status& status() const { return status_; }

 private:
  std::thread thread_;
  std::string received_;
  std::atomic<int64_t> id_{0};
  std::atomic<bool> leave_{false}, done_{false};
  absl::Status status_;
};

class PlayServerTest : public ::testing::Test {
 protected:
  void Start(PlayServerOptions options = {}, int max_viewers = 3) {
    absl::StatusOr<LoadedConfig> config = testing::LoadShippedConfig("foot_and_head_planner");
    ASSERT_TRUE(config.ok());
    absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
    ASSERT_TRUE(spec.ok()) << spec.status();
    hub_ = std::make_unique<FrameHub>(max_viewers, 8);
    session_ = std::make_unique<PlaySession>(
        std::make_unique<EnvWorld>(*spec, std::make_unique<ZeroController>((*spec)->act_dim()),
                                   nullptr, 1000),
        hub_.get(), SessionOptions{});
    options.port = 0;
    absl::StatusOr<std::unique_ptr<PlayServer>> server =
        PlayServer::Start(session_.get(), hub_.get(), "<html>the page</html>", options);
    ASSERT_TRUE(server.ok()) << server.status();
    server_ = *std::move(server);
    session_->Start();
  }
  void TearDown() override {
    if (server_) server_->Stop();
    if (session_) session_->Stop();
  }
  HttpResult Command(int64_t viewer, const std::string& body, const std::string& auth = "") {
    absl::StatusOr<HttpResult> r = HttpPost(
        server_->port(), "/api/command?viewer=" + std::to_string(viewer), body,
        "application/json", auth);
    EXPECT_TRUE(r.ok()) << r.status();
    return r.ok() ? *r : HttpResult{};
  }
  static std::string Error(const HttpResult& r) {
    const nlohmann::json j = nlohmann::json::parse(r.body, nullptr, false);
    return j.is_discarded() ? r.body : j.value("error", std::string("(no error)"));
  }

  std::unique_ptr<FrameHub> hub_;
  std::unique_ptr<PlaySession> session_;
  std::unique_ptr<PlayServer> server_;
};

TEST_F(PlayServerTest, ServesThePageTheSceneAndAStreamThatStartsWithTheViewersId) {
  Start();
  EXPECT_EQ(*HttpGet(server_->port(), "/"), "<html>the page</html>");
  const nlohmann::json scene = nlohmann::json::parse(*HttpGet(server_->port(), "/api/scene"));
  EXPECT_EQ(scene["family"], "soccer_juggle");
  EXPECT_EQ(scene["options"]["kind"], "graph");
  EXPECT_GT(scene["geoms"].size(), 10u);
  Viewer viewer(server_->port());
  EXPECT_GT(viewer.id(), 0);
  EXPECT_EQ(HttpFetch(server_->port(), "/nothing")->status, 404);
}

TEST_F(PlayServerTest, RefusesBadCommandsWithTheRightStatusAndAMessageAndKeepsRunning) {
  Start();
  Viewer viewer(server_->port());
  ASSERT_GT(viewer.id(), 0);
  HttpResult r = Command(viewer.id(), "{\"cmd\": ");
  EXPECT_EQ(r.status, 400);
  EXPECT_THAT(Error(r), HasSubstr("not valid JSON"));
  r = Command(viewer.id(), R"({"cmd":"launch"})");
  EXPECT_EQ(r.status, 400);
  EXPECT_THAT(Error(r), HasSubstr("unknown command \"launch\""));
  r = Command(viewer.id(), std::string(100000, ' ') + "{}");
  EXPECT_EQ(r.status, 413);
  EXPECT_THAT(Error(r), HasSubstr("at most 4096"));
  r = Command(viewer.id(), R"({"cmd":"skill","node":"left_knee_down"})");
  EXPECT_EQ(r.status, 400);
  EXPECT_THAT(Error(r), HasSubstr("no node \"left_knee_down\""));
  r = Command(viewer.id(), R"({"cmd":"poke","impulse":[5,0,0]})");
  EXPECT_EQ(r.status, 400);
  absl::StatusOr<HttpResult> no_viewer = HttpPost(server_->port(), "/api/command", "{}");
  EXPECT_EQ(no_viewer->status, 400);
  EXPECT_THAT(Error(*no_viewer), HasSubstr("?viewer=ID"));
  EXPECT_EQ(Command(999, R"({"cmd":"pause"})").status, 403);
  // After all that the session still takes a good command.
  r = Command(viewer.id(), R"({"cmd":"skill","node":"head_down"})");
  EXPECT_EQ(r.status, 200) << r.body;
  EXPECT_THAT(r.body, HasSubstr("next skill: head_down"));
  r = Command(viewer.id(), R"({"cmd":"poke","impulse":[0,0,0.2]})");
  EXPECT_EQ(r.status, 200) << r.body;
}

TEST_F(PlayServerTest, OneViewerControlsUntilItReleasesOrLeaves) {
  Start();
  auto first = std::make_unique<Viewer>(server_->port());
  Viewer second(server_->port());
  ASSERT_GT(first->id(), 0);
  ASSERT_GT(second.id(), 0);
  EXPECT_EQ(Command(first->id(), R"({"cmd":"claim"})").status, 200);
  EXPECT_EQ(server_->controller(), first->id());
  HttpResult r = Command(second.id(), R"({"cmd":"pause"})");
  EXPECT_EQ(r.status, 403);
  EXPECT_THAT(Error(r), HasSubstr("has control"));
  EXPECT_EQ(Command(first->id(), R"({"cmd":"release"})").status, 200);
  EXPECT_EQ(Command(second.id(), R"({"cmd":"pause"})").status, 200);  // takes control
  EXPECT_EQ(server_->controller(), second.id());
  EXPECT_EQ(Command(first->id(), R"({"cmd":"resume"})").status, 403);
  // The controller's stream ends: control is free again.
  Viewer third(server_->port());
  second.Leave();
  for (int i = 0; i < 300 && server_->controller() != 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(server_->controller(), 0);
  EXPECT_EQ(Command(third.id(), R"({"cmd":"resume"})").status, 200);
}

TEST_F(PlayServerTest, AViewerBeyondTheLimitGets503AndALeavingViewerFreesItsPlace) {
  Start({}, /*max_viewers=*/1);
  auto first = std::make_unique<Viewer>(server_->port());
  ASSERT_GT(first->id(), 0);
  Viewer refused(server_->port());
  EXPECT_TRUE(refused.done());
  EXPECT_THAT(refused.status().message(), HasSubstr("HTTP 503"));
  first.reset();
  bool joined = false;
  for (int i = 0; i < 100 && !joined; ++i) {
    Viewer again(server_->port());
    joined = again.id() > 0;
    if (!joined) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_TRUE(joined);
}

TEST_F(PlayServerTest, WithATokenEveryRequestMustCarryIt) {
  PlayServerOptions options;
  options.token = "s3cret";
  Start(options);
  EXPECT_EQ(HttpFetch(server_->port(), "/")->status, 401);
  EXPECT_EQ(HttpFetch(server_->port(), "/api/scene?token=wrong")->status, 401);
  EXPECT_EQ(HttpFetch(server_->port(), "/api/scene?token=s3cret")->status, 200);
  Viewer anonymous(server_->port());
  EXPECT_THAT(anonymous.status().message(), HasSubstr("HTTP 401"));
  Viewer viewer(server_->port(), "/api/stream?token=s3cret");
  ASSERT_GT(viewer.id(), 0);
  EXPECT_EQ(Command(viewer.id(), R"({"cmd":"pause"})").status, 401);
  EXPECT_EQ(Command(viewer.id(), R"({"cmd":"pause"})", "Bearer s3cret").status, 200);
}

TEST(PlayServerStartTest, RefusesEveryInterfaceWithoutAToken) {
  FrameHub hub(1, 1);
  PlayServerOptions options;
  options.all_interfaces = true;
  absl::StatusOr<std::unique_ptr<PlayServer>> server =
      PlayServer::Start(nullptr, &hub, "", options);
  EXPECT_EQ(server.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(server.status().message(), HasSubstr("needs a token"));
}

}  // namespace
}  // namespace juggle::play
