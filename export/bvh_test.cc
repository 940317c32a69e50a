// BVH export read back by an independent parser written here: frame count and time, the
// skeleton, and every joint angle equal to the recording's within 1e-4 rad — for the soccer
// humanoid (ball joints, hinges, a free root) and the toss arms (hinge chains) — the balls'
// CSV, and clear errors for what cannot be exported.
#include "export/bvh.h"

#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "export/trajectory_model.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;

// ---- An independent BVH reader.
struct ParsedJoint {
  std::string name;
  int parent = -1;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  std::vector<std::string> channels;
  int first_value = 0;  // index of its first channel in a frame's values
};
struct ParsedBvh {
  std::vector<ParsedJoint> joints;
  int frames = 0;
  double frame_time = 0;
  std::vector<std::vector<double>> values;  // [frame][channel]
  int Find(const std::string& name) const {
    for (size_t j = 0; j < joints.size(); ++j) {
      if (joints[j].name == name) return static_cast<int>(j);
    }
    return -1;
  }
  double Value(int frame, const std::string& joint, int channel) const {
    return values[frame][joints[Find(joint)].first_value + channel];
  }
};

bool ParseBvh(const std::string& text, ParsedBvh* out, std::string* error) {
  std::istringstream in(text);
  std::string token;
  std::vector<int> stack;  // open joints (-2 for an End Site)
  int channels = 0;
  in >> token;
  if (token != "HIERARCHY") return *error = "no HIERARCHY", false;
  while (in >> token) {
    if (token == "ROOT" || token == "JOINT") {
      ParsedJoint j;
      in >> j.name;
      for (auto it = stack.rbegin(); it != stack.rend(); ++it) {
        if (*it >= 0) { j.parent = *it; break; }
      }
      out->joints.push_back(j);
      stack.push_back(static_cast<int>(out->joints.size()) - 1);
      in >> token;
      if (token != "{") return *error = "no { after " + j.name, false;
    } else if (token == "End") {
      in >> token >> token;  // Site {
      stack.push_back(-2);
    } else if (token == "OFFSET") {
      Eigen::Vector3d v;
      in >> v.x() >> v.y() >> v.z();
      if (stack.back() >= 0) out->joints[stack.back()].offset = v;
    } else if (token == "CHANNELS") {
      int n = 0;
      in >> n;
      ParsedJoint& j = out->joints[stack.back()];
      j.first_value = channels;
      channels += n;
      for (int i = 0; i < n; ++i) {
        in >> token;
        j.channels.push_back(token);
      }
    } else if (token == "}") {
      stack.pop_back();
    } else if (token == "MOTION") {
      break;
    } else {
      return *error = "unexpected " + token, false;
    }
  }
  if (!stack.empty()) return *error = "unbalanced braces", false;
  in >> token >> out->frames;  // Frames: N
  if (token != "Frames:") return *error = "no Frames:", false;
  in >> token >> token >> out->frame_time;  // Frame Time: dt
  for (int f = 0; f < out->frames; ++f) {
    std::vector<double> row(channels);
    for (double& v : row) {
      if (!(in >> v)) return *error = "short motion data", false;
    }
    out->values.push_back(row);
  }
  if (in >> token) return *error = "extra data after the frames", false;
  return true;
}

// ---- Rotations, with Eigen (not the exporter's MuJoCo helpers).
constexpr double kRad = M_PI / 180;
Eigen::Matrix3d Rot(const std::string& channel, double degrees) {
  const Eigen::Vector3d axis = channel[0] == 'X'   ? Eigen::Vector3d::UnitX()
                               : channel[0] == 'Y' ? Eigen::Vector3d::UnitY()
                                                   : Eigen::Vector3d::UnitZ();
  return Eigen::AngleAxisd(degrees * kRad, axis).toRotationMatrix();
}
// The joint's local rotation at `frame`: the product of its rotation channels in order.
Eigen::Matrix3d LocalRotation(const ParsedBvh& bvh, int frame, int joint) {
  const ParsedJoint& j = bvh.joints[joint];
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  for (size_t c = 0; c < j.channels.size(); ++c) {
    if (j.channels[c].find("rotation") != std::string::npos) {
      r = r * Rot(j.channels[c], bvh.values[frame][j.first_value + c]);
    }
  }
  return r;
}
// MuJoCo axes (x, y, z) -> BVH (y, z, x), as documented in export/bvh.h.
Eigen::Matrix3d P() {
  Eigen::Matrix3d p;
  p << 0, 1, 0, 0, 0, 1, 1, 0, 0;
  return p;
}
Eigen::Quaterniond Quat(const double* wxyz) {
  return Eigen::Quaterniond(wxyz[0], wxyz[1], wxyz[2], wxyz[3]).normalized();
}
double AngleBetween(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

// Runs `config`'s env with zero actions for up to `steps` control steps, recording every state.
struct Recorded {
  std::shared_ptr<const EnvSpec> spec;
  Trajectory trajectory;
};
Recorded RecordZeroAction(const std::string& config, int steps) {
  Recorded r;
  absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(testing::RepoPath(config));
  EXPECT_TRUE(loaded.ok()) << loaded.status();
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*loaded);
  EXPECT_TRUE(spec.ok()) << spec.status();
  r.spec = *spec;
  const AdaptiveWalk walk(&r.spec->graph());
  std::unique_ptr<Env> env = r.spec->NewEnv(Rng::ForStream(7, 0, 0));
  env->Reset(walk);
  TrajectoryBuilder b(r.spec->family(), config, r.spec->control_dt(), r.spec->model()->nq,
                      r.spec->outcome_names(), {});
  b.Append(0, 0, 0, Outcome::kRunning, nullptr, env->data()->qpos);
  std::vector<float> action(r.spec->act_dim(), 0.0f);
  for (int s = 1; s <= steps; ++s) {
    const StepResult step = env->Step(action.data(), walk);
    b.Append(s * r.spec->control_dt(), 0, s * r.spec->control_dt(), step.outcome, nullptr,
             env->data()->qpos);
    if (step.outcome != Outcome::kRunning) break;
  }
  r.trajectory = b.Take();
  return r;
}

TEST(BvhTest, SoccerJointAnglesReadBackEqualTheRecording) {
  Recorded rec = RecordZeroAction("configs/right_foot.textproto", 30);
  const mjModel* m = rec.spec->model();
  const Trajectory& t = rec.trajectory;
  absl::StatusOr<BvhExport> e = ExportBvh(m, t);
  ASSERT_TRUE(e.ok()) << e.status();
  ParsedBvh bvh;
  std::string error;
  ASSERT_TRUE(ParseBvh(e->bvh, &bvh, &error)) << error;
  ASSERT_EQ(bvh.frames, t.num_samples());
  EXPECT_NEAR(bvh.frame_time, 0.02, 1e-9);
  // Every body with a joint; the wrists (fixed leaves) are End Sites.
  ASSERT_EQ(bvh.joints.size(), 13u);
  EXPECT_EQ(bvh.joints[0].name, "root");
  EXPECT_EQ(bvh.Find("right_wrist"), -1);
  // Three rotation channels on every joint (Blender's importer needs them).
  const std::vector<std::string> kZxy = {"Zrotation", "Xrotation", "Yrotation"};
  EXPECT_EQ(bvh.joints[bvh.Find("right_knee")].channels, kZxy);
  EXPECT_NEAR(bvh.joints[bvh.Find("right_knee")].offset.norm(), 0.421546, 1e-6);
  EXPECT_EQ(bvh.joints[bvh.Find("right_knee")].parent, bvh.Find("right_hip"));

  // The character's rest orientation (its root's qpos0 quaternion) R0: every body has it at
  // rest, so a ball joint's BVH rotation is R0·q·R0ᵀ in BVH axes, and a hinge about the
  // body's z (DeepMimic's convention) turns about R0·z = −y (MuJoCo) = −X (BVH).
  const Eigen::Matrix3d r0 = Quat(m->qpos0 + 3).toRotationMatrix();
  double worst = 0;
  for (int f = 0; f < bvh.frames; ++f) {
    const double* q = t.qpos_at(f);
    // Root: position and world rotation R(t)·R0ᵀ.
    const Eigen::Vector3d root_bvh = P() * Eigen::Vector3d(q[0], q[1], q[2]);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(bvh.Value(f, "root", k), root_bvh[k], 1e-5);
    const Eigen::Matrix3d root_expected = P() * Quat(q + 3).toRotationMatrix() * r0.transpose() *
                                          P().transpose();
    worst = std::max(worst, AngleBetween(root_expected, LocalRotation(bvh, f, 0)));
    for (int jnt = 1; jnt < m->njnt; ++jnt) {
      const std::string name = mj_id2name(m, mjOBJ_JOINT, jnt);
      if (name == "ball") continue;
      const int joint = bvh.Find(name);  // bodies are named after their joints
      ASSERT_GE(joint, 0) << name;
      const double* jq = q + m->jnt_qposadr[jnt];
      if (m->jnt_type[jnt] == mjJNT_HINGE) {
        // About BVH −X: the X channel holds −angle, Z and Y stay 0.
        const double angle = -bvh.Value(f, name, 1) * kRad;
        worst = std::max(worst, std::abs(angle - jq[0]));
        EXPECT_EQ(bvh.Value(f, name, 0), 0.0);
        EXPECT_EQ(bvh.Value(f, name, 2), 0.0);
      } else {
        const Eigen::Matrix3d expected =
            P() * r0 * Quat(jq).toRotationMatrix() * r0.transpose() * P().transpose();
        worst = std::max(worst, AngleBetween(expected, LocalRotation(bvh, f, joint)));
      }
    }
  }
  EXPECT_LT(worst, 1e-4);

  // The ball's centre per frame, in BVH axes.
  std::istringstream csv(e->balls_csv);
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "frame,time,ball_x,ball_y,ball_z");
  const int ball_q = m->jnt_qposadr[mj_name2id(m, mjOBJ_JOINT, "ball")];
  for (int f = 0; std::getline(csv, line); ++f) {
    int frame = 0;
    double time = 0, x = 0, y = 0, z = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%d,%lf,%lf,%lf,%lf", &frame, &time, &x, &y, &z), 5);
    EXPECT_EQ(frame, f);
    const double* b = t.qpos_at(f) + ball_q;
    EXPECT_NEAR(x, b[1], 1e-6);
    EXPECT_NEAR(y, b[2], 1e-6);
    EXPECT_NEAR(z, b[0], 1e-6);
  }
}

TEST(BvhTest, TossArmsExportAsHingeChainsWithTheAngleInTheXChannel) {
  Recorded rec = RecordZeroAction("configs/toss_catch.textproto", 30);
  const mjModel* m = rec.spec->model();
  const Trajectory& t = rec.trajectory;
  ASSERT_GT(t.num_samples(), 5);
  absl::StatusOr<BvhExport> e = ExportBvh(m, t);
  ASSERT_TRUE(e.ok()) << e.status();
  ParsedBvh bvh;
  std::string error;
  ASSERT_TRUE(ParseBvh(e->bvh, &bvh, &error)) << error;
  EXPECT_EQ(bvh.frames, t.num_samples());
  EXPECT_NEAR(bvh.frame_time, 0.01, 1e-9);
  ASSERT_EQ(bvh.joints.size(), 8u);  // torso, head, 2 × (upper arm, forearm, hand)
  EXPECT_EQ(bvh.joints[0].name, "torso");
  EXPECT_EQ(bvh.joints[bvh.Find("right_forearm")].parent, bvh.Find("right_upper_arm"));
  // Hinges about MuJoCo y = BVH X, positive.
  double worst = 0;
  for (const char* joint : {"neck", "right_shoulder", "right_elbow", "right_wrist",
                            "left_shoulder", "left_elbow", "left_wrist"}) {
    const int jnt = mj_name2id(m, mjOBJ_JOINT, joint);
    const std::string body = mj_id2name(m, mjOBJ_BODY, m->jnt_bodyid[jnt]);
    ASSERT_EQ(bvh.joints[bvh.Find(body)].channels,
              (std::vector<std::string>{"Zrotation", "Xrotation", "Yrotation"}));
    for (int f = 0; f < bvh.frames; ++f) {
      worst = std::max(worst, std::abs(bvh.Value(f, body, 1) * kRad -
                                       t.qpos_at(f)[m->jnt_qposadr[jnt]]));
      // The local rotation the three channels compose is the hinge's, about +X.
      worst = std::max(worst, AngleBetween(LocalRotation(bvh, f, bvh.Find(body)),
                                           Rot("X", t.qpos_at(f)[m->jnt_qposadr[jnt]] / kRad)));
    }
  }
  EXPECT_LT(worst, 1e-4);
  EXPECT_THAT(e->balls_csv, HasSubstr("frame,time,ball0_x,ball0_y,ball0_z,ball1_x"));
}

TEST(BvhTest, RefusesAnEmptyRecordingAndAMissingEpisode) {
  Recorded rec = RecordZeroAction("configs/toss_catch.textproto", 3);
  Trajectory empty = rec.trajectory;
  empty.time.clear();
  empty.values.clear();
  empty.qpos.clear();
  EXPECT_THAT(ExportBvh(rec.spec->model(), empty).status().message(),
              HasSubstr("no samples: nothing to export"));
  EXPECT_THAT(ExportBvh(rec.spec->model(), rec.trajectory, 3).status().message(),
              HasSubstr("no episode 3"));
}

TEST(BvhTest, RefusesASlideJointInTheCharacter) {
  constexpr char kModel[] = R"(<mujoco><worldbody><body name="cart">
      <joint type="slide"/><geom size="0.1"/></body></worldbody></mujoco>)";
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  mj_makeEmptyFileVFS(&vfs, "m.xml", sizeof(kModel));
  std::memcpy(vfs.filedata[mj_findFileVFS(&vfs, "m.xml")], kModel, sizeof(kModel));
  char err[256] = "";
  mjModel* m = mj_loadXML("m.xml", &vfs, err, sizeof(err));
  mj_deleteVFS(&vfs);
  ASSERT_NE(m, nullptr) << err;
  EXPECT_THAT(BuildBvhSkeleton(m).status().message(),
              HasSubstr("body cart has a slide joint, which BVH cannot express"));
  mj_deleteModel(m);
}

TEST(BvhTest, ARecordingWhoseConfigCannotBeLoadedNamesTheConfig) {
  Recorded rec = RecordZeroAction("configs/toss_catch.textproto", 2);
  Trajectory t = rec.trajectory;
  t.config_path = "configs/no_such.textproto";
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = LoadTrajectorySpec(t, "x.traj");
  EXPECT_EQ(spec.status().code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(spec.status().message(),
              HasSubstr("x.traj: the recording's config configs/no_such.textproto cannot be loaded"));
  t.config_path = testing::RepoPath("configs/right_foot.textproto");
  spec = LoadTrajectorySpec(t, "x.traj");
  EXPECT_EQ(spec.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(spec.status().message(), HasSubstr("recorded with family toss and nq 21"));
}

}  // namespace
}  // namespace juggle
