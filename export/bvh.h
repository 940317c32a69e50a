// BVH export of a recording (`juggle export-bvh`): the character's skeleton from the MJCF body
// tree and its motion per control step, for animation tools (Blender, MotionBuilder, ...).
//
// Conventions (docs/replay_and_export.md, "BVH export"):
// - Axes: BVH Y up. MuJoCo's world (x, y, z) maps to BVH (X, Y, Z) = (y, z, x), a rotation,
//   so handedness is kept: the soccer character, facing MuJoCo +x, faces BVH +Z. Metres.
// - Joints: every body of the character (the subtree of the world's one child that is not a
//   ball) except leaves without joints, which become their parent's End Site; leaves with
//   joints get an End Site at their first geom's centre. A joint sits at its body's (first)
//   joint anchor; OFFSETs are the rest pose's (the model's qpos0) anchor differences.
// - Channels: the root has Xposition Yposition Zposition Zrotation Xrotation Yrotation
//   (absolute world position of its anchor, OFFSET 0); every other joint has Zrotation
//   Xrotation Yrotation (three rotation channels everywhere: Blender's importer, among others,
//   needs them), R = Rz·Rx·Ry of its rotation relative to its parent's, measured from the rest
//   pose. A body with one hinge whose rest axis is a BVH axis writes ±(qpos − qpos0) in that
//   axis's channel and 0 in the other two, the sign making it a right-handed rotation about +X,
//   +Y or +Z (exact for any angle, where an Euler decomposition would fold angles past 90°).
//   Angles in degrees.
// - Frames: the samples of one episode, Frame Time = the recording's control_dt.
// - Balls (world bodies named ball*) are not in the BVH: their centres go to a CSV beside it,
//   in the BVH's axes and units: frame,time,<ball>_x,<ball>_y,<ball>_z,...
// Slide joints in the character cannot be expressed and are an error. Pure functions.
#ifndef JUGGLE_EXPORT_BVH_H_
#define JUGGLE_EXPORT_BVH_H_

#include <string>
#include <vector>

#include <mujoco/mujoco.h>

#include "absl/status/statusor.h"
#include "record/trajectory.h"

namespace juggle {

struct BvhJoint {
  std::string name;            // the body's name
  int body = 0;                // model body id
  int parent = -1;             // index into BvhSkeleton::joints; -1 for the root
  double offset[3] = {0, 0, 0};  // BVH axes, m
  std::vector<std::string> channels;
  int hinge_qpos = -1;         // a hinge about a BVH axis: its qpos address, ...
  int hinge_channel = 0;       // ... the rotation channel (0 Z, 1 X, 2 Y) holding its angle ...
  double hinge_sign = 1;       // ... and the sign of the channel relative to the angle
  bool end_site = false;       // a leaf: End Site at end_offset
  double end_offset[3] = {0, 0, 0};
};

struct BvhSkeleton {
  std::vector<BvhJoint> joints;  // depth-first, parents before children
};

// The skeleton of `model`'s character. INVALID_ARGUMENT when the model has no character body,
// more than one (world children that are not balls), or a slide joint in the character.
absl::StatusOr<BvhSkeleton> BuildBvhSkeleton(const mjModel* model);

struct BvhExport {
  std::string bvh;        // the BVH file's text
  std::string balls_csv;  // the balls' path ("" when the model has no ball)
  int frames = 0;
  double frame_time = 0;
  int joints = 0;
  int channels = 0;
};

// Exports episode `episode` of `trajectory` (recorded with `model`). INVALID_ARGUMENT for an
// empty recording, a missing episode, an nq mismatch or a skeleton BuildBvhSkeleton refuses.
absl::StatusOr<BvhExport> ExportBvh(const mjModel* model, const Trajectory& trajectory,
                                    int episode = 0);

}  // namespace juggle

#endif  // JUGGLE_EXPORT_BVH_H_
