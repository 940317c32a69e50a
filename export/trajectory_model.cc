#include "export/trajectory_model.h"

#include <cstring>

#include "absl/strings/str_cat.h"
#include "envs/policy_config.h"
#include "envs/registry.h"

namespace juggle {

absl::StatusOr<std::shared_ptr<const EnvSpec>> LoadTrajectorySpec(
    const Trajectory& trajectory, const std::string& trajectory_path,
    const std::string& config_path) {
  const std::string path = config_path.empty() ? trajectory.config_path : config_path;
  auto wrap = [&](const absl::Status& s) {
    return absl::Status(s.code(), absl::StrCat(trajectory_path, ": the recording's config ", path,
                                               " cannot be loaded (run from the folder it was "
                                               "recorded in, or pass --config): ",
                                               s.message()));
  };
  absl::StatusOr<LoadedConfig> config = LoadConfigOrPolicy(path, nullptr);
  if (!config.ok()) return wrap(config.status());
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  if (!spec.ok()) return wrap(spec.status());
  if ((*spec)->family() != trajectory.family || (*spec)->model()->nq != trajectory.nq) {
    return absl::FailedPreconditionError(absl::StrCat(
        trajectory_path, ": recorded with family ", trajectory.family, " and nq ", trajectory.nq,
        ", but config ", path, " has family ", (*spec)->family(), " and nq ",
        (*spec)->model()->nq));
  }
  return spec;
}

std::vector<int> BallBodies(const mjModel* m) {
  std::vector<int> balls;
  for (int b = 1; b < m->nbody; ++b) {
    const char* name = mj_id2name(m, mjOBJ_BODY, b);
    if (m->body_parentid[b] == 0 && name != nullptr && std::strncmp(name, "ball", 4) == 0) {
      balls.push_back(b);
    }
  }
  return balls;
}

bool InBallSubtree(const mjModel* m, int body) {
  if (body <= 0) return false;
  const int top = m->body_rootid[body];
  const char* name = mj_id2name(m, mjOBJ_BODY, top);
  return name != nullptr && std::strncmp(name, "ball", 4) == 0;
}

}  // namespace juggle
