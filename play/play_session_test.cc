// The live simulation on a real soccer env (foot and head graph, zero action): a poke's impulse
// lands on the ball alone as Δv = p/m (cross-checked against the impulse-momentum law, not
// M⁻¹Jᵀp); a skill choice steers the node after the coming one and is refused for unknown
// nodes; the session streams frames of every drawn body, pauses, restarts at a seed, paces
// simulated time by the speed asked for, and answers commands after Stop with UNAVAILABLE.
#include "play/play_session.h"

#include <chrono>
#include <cmath>
#include <thread>

#include "envs/soccer_juggle/env.h"
#include "envs/testing/test_configs.h"
#include "eval/controller.h"
#include "export/trajectory_model.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "nlohmann/json.hpp"
#include "play/env_world.h"

namespace juggle::play {
namespace {

using ::testing::HasSubstr;

std::unique_ptr<EnvWorld> MakeWorld() {
  absl::StatusOr<LoadedConfig> config = testing::LoadShippedConfig("foot_and_head_planner");
  if (!config.ok()) return nullptr;
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  if (!spec.ok()) return nullptr;
  return std::make_unique<EnvWorld>(*spec, std::make_unique<ZeroController>((*spec)->act_dim()),
                                    nullptr, /*run_seed=*/1000);
}

nlohmann::json FrameJson(const std::string& sse) {
  EXPECT_EQ(sse.rfind("data: ", 0), 0u);
  return nlohmann::json::parse(sse.substr(6));
}

TEST(EnvWorldTest, APokeChangesTheBallsVelocityByImpulseOverMassAndNothingElse) {
  std::unique_ptr<EnvWorld> world = MakeWorld();
  ASSERT_NE(world, nullptr);
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(world->Step());
  const mjModel* m = world->model();
  const int ball = BallBodies(m).front();
  const int dof = m->jnt_dofadr[m->body_jntadr[ball]];
  const mjData* d = world->data();
  std::vector<double> before(d->qvel, d->qvel + m->nv);
  ASSERT_TRUE(world->Poke({0.1, -0.2, 0.4}).ok());
  const double mass = m->body_mass[ball];
  EXPECT_NEAR(d->qvel[dof] - before[dof], 0.1 / mass, 1e-9);
  EXPECT_NEAR(d->qvel[dof + 1] - before[dof + 1], -0.2 / mass, 1e-9);
  EXPECT_NEAR(d->qvel[dof + 2] - before[dof + 2], 0.4 / mass, 1e-9);
  for (int i = 0; i < m->nv; ++i) {
    if (i >= dof && i < dof + 6) continue;
    EXPECT_EQ(d->qvel[i], before[i]) << "dof " << i;
  }
  // The ball's angular velocity: an impulse through the centre adds no spin.
  for (int k = 3; k < 6; ++k) EXPECT_NEAR(d->qvel[dof + k], before[dof + k], 1e-9);
}

TEST(EnvWorldTest, ASkillChoiceSteersTheNodeAfterTheComingOneAndUnknownNodesAreRefused) {
  std::unique_ptr<EnvWorld> world = MakeWorld();
  ASSERT_NE(world, nullptr);
  const auto* env = dynamic_cast<const soccer_juggle::JuggleEnv*>(&world->env());
  ASSERT_NE(env, nullptr);
  const ControlGraph& g = env->spec().graph();
  ASSERT_TRUE(world->Choose("head_down").ok());
  EXPECT_EQ(world->chosen(), "head_down");
  if (g.node(env->cursor().current).name == "right_foot_down") {
    EXPECT_EQ(g.node(env->cursor().next_next).name, "head_down");
  }
  nlohmann::json status;
  world->AppendStatus(&status);
  EXPECT_EQ(status["chosen"], "head_down");
  absl::Status unknown = world->Choose("left_knee_down");
  EXPECT_EQ(unknown.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(unknown.message(), HasSubstr("no node \"left_knee_down\""));
  EXPECT_EQ(world->chosen(), "head_down");  // a refused choice changes nothing
  ASSERT_TRUE(world->Choose("walk").ok());
  EXPECT_EQ(world->chosen(), "");
  EXPECT_EQ(world->Options()["steerable"].size(), 4u);
}

TEST(PlaySessionTest, StreamsFramesOfEveryDrawnBodyAndAppliesCommandsBetweenSteps) {
  FrameHub hub(2, 64);
  const int64_t viewer = *hub.Join();
  SessionOptions options;
  options.speed = 1.0;
  PlaySession session(MakeWorld(), &hub, options);
  const size_t bodies = session.Scene()["bodies"].size();
  ASSERT_GT(bodies, 10u);
  EXPECT_GT(session.Scene()["ball_mass"].get<double>(), 0.1);
  session.Start();
  std::vector<nlohmann::json> frames;
  const auto start = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - start < std::chrono::milliseconds(600)) {
    std::optional<std::string> m = hub.Take(viewer, std::chrono::milliseconds(100));
    if (m.has_value()) frames.push_back(FrameJson(*m));
  }
  ASSERT_GT(frames.size(), 10u);
  for (const nlohmann::json& f : frames) {
    EXPECT_EQ(f["x"].size(), 3 * bodies);
    EXPECT_EQ(f["q"].size(), 4 * bodies);
  }
  EXPECT_GT(frames.back()["t"].get<double>(), frames.front()["t"].get<double>());

  PlayCommand pause;
  pause.kind = CommandKind::kPause;
  EXPECT_EQ(*session.Submit(pause), "paused");
  const double paused_at = session.times().sim_seconds;
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(session.times().sim_seconds, paused_at);

  PlayCommand restart;
  restart.kind = CommandKind::kRestart;
  restart.has_seed = true;
  restart.seed = 5;
  EXPECT_EQ(*session.Submit(restart), "new start: seed 5");
  PlayCommand bad_skill;
  bad_skill.kind = CommandKind::kSkill;
  bad_skill.name = "no_such_node";
  absl::StatusOr<std::string> refused = session.Submit(bad_skill);
  EXPECT_EQ(refused.status().code(), absl::StatusCode::kInvalidArgument);
  // The refusal reaches the page with the frame published after the command.
  for (int i = 0; i < 100 && session.LatestFrame().find("no_such_node") == std::string::npos;
       ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_THAT(session.LatestFrame(), HasSubstr("no node \\\"no_such_node\\\""));
  EXPECT_THAT(session.LatestFrame(), HasSubstr("\"seed\":5"));

  // Half speed: about half a simulated second per wall second (pacing, loosely bounded).
  PlayCommand half;
  half.kind = CommandKind::kSpeed;
  half.factor = 0.5;
  ASSERT_TRUE(session.Submit(half).ok());
  PlayCommand resume;
  resume.kind = CommandKind::kResume;
  ASSERT_TRUE(session.Submit(resume).ok());
  const double sim0 = session.times().sim_seconds;
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  const double simulated = session.times().sim_seconds - sim0;
  EXPECT_GT(simulated, 0.3);
  EXPECT_LT(simulated, 0.7);
  EXPECT_GT(session.times().steps, 0);
  session.Stop();
  EXPECT_EQ(session.Submit(pause).status().code(), absl::StatusCode::kUnavailable);
}

}  // namespace
}  // namespace juggle::play
