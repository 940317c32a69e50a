#include "envs/soccer_juggle/family.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "common/status_macros.h"
#include "envs/soccer_juggle/spec.h"

namespace juggle::soccer_juggle {
namespace {

absl::Status ValidateEnv(const config::EnvConfig& env, const SourceLocator& where) {
  auto fail = [&](const char* field, const char* rule) {
    return absl::InvalidArgumentError(absl::StrCat(where.Where({{field}}), ": ", rule));
  };
  if (!(env.sim_dt() > 0)) return fail("sim_dt", "must be > 0");
  if (env.substeps() < 1) return fail("substeps", "must be >= 1");
  if (env.max_episode_steps() < 1) return fail("max_episode_steps", "must be >= 1");
  if (!(env.gravity() > 0)) return fail("gravity", "must be > 0");
  return absl::OkStatus();
}

// Reads graph_file (if set) into the config's graph and validates the graph.
absl::Status PrepareGraph(LoadedConfig* loaded, const SourceLocator& where) {
  config::SoccerJuggleConfig* section = loaded->run.mutable_soccer_juggle();
  const bool inline_graph = section->has_graph();
  const bool file_graph = section->has_graph_file();
  if (inline_graph == file_graph) {
    return absl::InvalidArgumentError(
        absl::StrCat(where.Where({{inline_graph ? "graph_file" : "graph"}}),
                     ": exactly one of 'graph' (inline) or 'graph_file' must be set"));
  }
  if (file_graph) {
    const std::string graph_path = ResolvePath(loaded->config_dir, section->graph_file());
    absl::StatusOr<std::string> graph_text = ReadFile(graph_path);
    if (!graph_text.ok()) {
      return absl::NotFoundError(
          absl::StrCat(where.Where({{"graph_file"}}), ": ", graph_text.status().message()));
    }
    ASSIGN_OR_RETURN(loaded->graph_locator,
                     ParseTextMessage(*graph_text, graph_path, section->mutable_graph()));
    section->clear_graph_file();  // workers receive the graph inline
  } else {
    loaded->graph_locator = where.Nested({{"graph"}});
  }
  ASSIGN_OR_RETURN(ControlGraph graph, ControlGraph::Build(section->graph(), loaded->graph_locator));
  loaded->graph = std::make_shared<const ControlGraph>(std::move(graph));
  return absl::OkStatus();
}

class SoccerJuggleFamily final : public EnvFamily {
 public:
  std::string_view name() const override { return "soccer_juggle"; }
  config::RunConfig::FamilyCase config_case() const override {
    return config::RunConfig::kSoccerJuggle;
  }
  absl::Status Prepare(LoadedConfig* loaded) const override {
    loaded->family_locator = loaded->root.Nested({{"soccer_juggle"}});
    RETURN_IF_ERROR(ValidateEnv(loaded->run.soccer_juggle().env(),
                                loaded->family_locator.Nested({{"env"}})));
    return PrepareGraph(loaded, loaded->family_locator);
  }
  absl::StatusOr<std::shared_ptr<const EnvSpec>> CreateSpec(
      const LoadedConfig& config, const std::string& model_mjb) const override {
    absl::StatusOr<std::shared_ptr<const JuggleSpec>> spec =
        model_mjb.empty() ? JuggleSpec::Create(config)
                          : JuggleSpec::CreateFromCompiled(config, model_mjb);
    if (!spec.ok()) return spec.status();
    return std::shared_ptr<const EnvSpec>(*std::move(spec));
  }
  void ConfigureForEvaluation(double max_seconds, config::RunConfig* run) const override {
    config::EnvConfig* env = run->mutable_soccer_juggle()->mutable_env();
    const double control_dt = env->sim_dt() * env->substeps();
    if (max_seconds > 0) {
      env->set_max_episode_steps(static_cast<int>(std::ceil(max_seconds / control_dt - 1e-9)));
    }
    env->mutable_start()->set_random_phase_fraction(0);
  }
  absl::Status SetConstantBallForce(const double force[3], config::RunConfig* run) const override {
    config::Vec3* f = run->mutable_soccer_juggle()->mutable_env()->mutable_ball_force();
    f->set_x(force[0]);
    f->set_y(force[1]);
    f->set_z(force[2]);
    return absl::OkStatus();
  }
};

}  // namespace

const EnvFamily& Family() {
  static const SoccerJuggleFamily family;
  return family;
}

}  // namespace juggle::soccer_juggle
