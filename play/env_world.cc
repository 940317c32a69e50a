#include "play/env_world.h"

#include <algorithm>
#include <utility>

#include "absl/strings/str_cat.h"
#include "common/rng.h"
#include "export/trajectory_model.h"
#include "play/steering.h"

namespace juggle::play {

EnvWorld::EnvWorld(std::shared_ptr<const EnvSpec> spec, std::unique_ptr<Controller> controller,
                   planner::PlannerController* planner, uint64_t run_seed)
    : spec_(std::move(spec)),
      controller_(std::move(controller)),
      planner_(planner),
      run_seed_(run_seed),
      walk_(&spec_->graph()),
      obs_(spec_->obs_dim()),
      action_(spec_->act_dim()),
      balls_(BallBodies(spec_->model())) {
  if (planner_ != nullptr) {
    planner_->set_on_replan([this](int, const planner::ReplanReport& report) {
      ++replans_;
      last_replan_ = report;
      has_replan_ = true;
    });
  }
  Restart(0);
}

void EnvWorld::Restart(uint64_t seed) {
  seed_ = seed;
  // The evaluation's stream for episode `seed` (eval/episode_runner.h): play seed s starts as
  // `juggle eval --seed=RUN_SEED` episode s does.
  env_ = spec_->NewEnv(Rng::ForStream(run_seed_, 0, seed));
  env_->Reset(walk_);
  env_->Resteer(walk_);  // a skill chosen earlier holds from the start
  outcome_.clear();
}

bool EnvWorld::Step() {
  if (!outcome_.empty()) return false;
  env_->WriteObservation(obs_.data());
  const Env* envs[1] = {env_.get()};
  controller_->Act(envs, obs_.data(), 1, action_.data());
  const StepResult result = env_->Step(action_.data(), walk_);
  if (result.outcome == Outcome::kRunning) return true;
  const std::vector<std::string> names = spec_->outcome_names();
  const int o = static_cast<int>(result.outcome);
  outcome_ = o >= 0 && o < static_cast<int>(names.size()) ? names[o] : absl::StrCat(o);
  return false;
}

absl::Status EnvWorld::Poke(const std::array<double, 3>& impulse) {
  if (balls_.empty()) return absl::FailedPreconditionError("this world has no ball");
  const mjData* d = env_->data();
  int ball = balls_.front();
  for (int b : balls_) {
    if (d->xpos[3 * b + 2] > d->xpos[3 * ball + 2]) ball = b;
  }
  ApplyImpulse(spec_->model(), env_->data(), ball, impulse);
  return absl::OkStatus();
}

absl::Status EnvWorld::Choose(const std::string& name) {
  const ControlGraph& graph = spec_->graph();
  if (graph.num_nodes() == 0) {
    return absl::FailedPreconditionError(
        absl::StrCat("the ", spec_->family(), " family has no control graph to choose from"));
  }
  if (name == "walk") {
    absl::Status s = walk_.SetSteering({});
    if (s.ok()) chosen_.clear();
    return s;
  }
  absl::StatusOr<std::vector<int>> steering = SteerToward(graph, name, env_->node());
  if (!steering.ok()) return steering.status();
  if (absl::Status s = walk_.SetSteering(*std::move(steering)); !s.ok()) return s;
  env_->Resteer(walk_);
  chosen_ = name;
  return absl::OkStatus();
}

nlohmann::json EnvWorld::Options() const {
  const ControlGraph& graph = spec_->graph();
  nlohmann::json nodes = nlohmann::json::array(), edges = nlohmann::json::array(),
                 steerable = nlohmann::json::array();
  for (int n = 0; n < graph.num_nodes(); ++n) {
    nodes.push_back({{"name", graph.node(n).name},
                     {"stage", config::Stage_Name(graph.node(n).stage)},
                     {"initial", graph.node(n).initial}});
  }
  for (int e = 0; e < graph.num_edges(); ++e) {
    edges.push_back({graph.edge(e).from, graph.edge(e).to});
  }
  for (int n : SteerableNodes(graph)) steerable.push_back(graph.node(n).name);
  return {{"kind", "graph"},
          {"controller", controller_->name()},
          {"nodes", nodes},
          {"edges", edges},
          {"steerable", steerable},
          {"budget", budget_}};
}

void EnvWorld::AppendStatus(nlohmann::json* status) const {
  nlohmann::json& s = *status;
  s["seed"] = seed_;
  s["juggles"] = env_->juggles();
  s["completions"] = env_->completions();
  s["steps"] = env_->steps();
  const ControlGraph& graph = spec_->graph();
  if (graph.num_nodes() > 0) {
    s["node"] = graph.node(env_->node()).name;
    s["chosen"] = chosen_.empty() ? "walk" : chosen_;
  }
  if (!outcome_.empty()) s["outcome"] = outcome_;
  if (planner_ != nullptr && has_replan_) {
    s["planner"] = {{"replans", replans_},
                    {"rollouts", last_replan_.evaluations},
                    {"cost", last_replan_.best_cost},
                    {"rescued", last_replan_.rescued},
                    {"predicts_failure", last_replan_.predicts_failure}};
  }
}

void ApplyImpulse(const mjModel* m, mjData* d, int body, const std::array<double, 3>& impulse) {
  std::vector<mjtNum> jacp(3 * m->nv), force(m->nv), dv(m->nv);
  mj_jacBodyCom(m, d, jacp.data(), nullptr, body);
  for (int i = 0; i < m->nv; ++i) {
    force[i] = jacp[i] * impulse[0] + jacp[m->nv + i] * impulse[1] +
               jacp[2 * m->nv + i] * impulse[2];
  }
  mj_solveM(m, d, dv.data(), force.data(), 1);
  for (int i = 0; i < m->nv; ++i) d->qvel[i] += dv[i];
}

}  // namespace juggle::play
