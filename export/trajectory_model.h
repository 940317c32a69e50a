// The compiled model a recording was made with, and what export/ needs to know about its
// bodies: which are balls, which form the character. Family-free: the config named in the
// recording's header — a run config, or an exported policy with its stored config — is loaded
// through the registry (LoadConfigOrPolicy -> CreateEnvSpec).
#ifndef JUGGLE_EXPORT_TRAJECTORY_MODEL_H_
#define JUGGLE_EXPORT_TRAJECTORY_MODEL_H_

#include <memory>
#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "absl/status/statusor.h"
#include "envs/env.h"
#include "record/trajectory.h"

namespace juggle {

// The spec of `trajectory`'s model: `config_path` (a run config or a .jglpolicy) if not
// empty, else the config the recording names. Errors (each naming `trajectory_path` and the config): the config cannot be
// loaded or compiled (its status code, e.g. NOT_FOUND), or it does not match the recording
// (FAILED_PRECONDITION: another family or another qpos size).
absl::StatusOr<std::shared_ptr<const EnvSpec>> LoadTrajectorySpec(
    const Trajectory& trajectory, const std::string& trajectory_path,
    const std::string& config_path = "");

// Bodies of the world whose name starts with "ball" (soccer: ball; toss: ball0..ball6), in
// body order. Their subtrees are props, not the character.
std::vector<int> BallBodies(const mjModel* model);

// True if `body` is a ball body or lies below one.
bool InBallSubtree(const mjModel* model, int body);

}  // namespace juggle

#endif  // JUGGLE_EXPORT_TRAJECTORY_MODEL_H_
