#include "export/bvh.h"

#include <cmath>
#include <memory>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "envs/mujoco_model.h"
#include "export/trajectory_model.h"

namespace juggle {
namespace {

constexpr double kDegrees = 180.0 / M_PI;
// The rotation channel (in Zrotation Xrotation Yrotation order) of BVH axis X, Y, Z.
constexpr int kAxisChannel[3] = {1, 2, 0};

// MuJoCo world (x, y, z) -> BVH (X, Y, Z) = (y, z, x).
void ToBvh(const double* v, double* out) {
  const double x = v[0], y = v[1], z = v[2];
  out[0] = y;
  out[1] = z;
  out[2] = x;
}

// 3x3 row-major helpers.
void MulMatTransB(const double* a, const double* b, double* out) {
  mju_mulMatMatT(out, a, b, 3, 3, 3);
}
void MulMatTransA(const double* a, const double* b, double* out) {
  mju_mulMatTMat(out, a, b, 3, 3, 3);
}

// A rotation matrix in MuJoCo axes expressed in BVH axes: P·R·Pᵀ.
void RotationToBvh(const double* r, double* out) {
  // P maps mj (x, y, z) to (y, z, x): row i of P picks mj component perm[i].
  const int perm[3] = {1, 2, 0};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) out[3 * i + j] = r[3 * perm[i] + perm[j]];
  }
}

// R = Rz(z)·Rx(x)·Ry(y): returns (z, x, y) in radians.
void EulerZxy(const double* r, double* zxy) {
  const double sx = std::max(-1.0, std::min(1.0, r[7]));
  zxy[1] = std::asin(sx);
  zxy[0] = std::atan2(-r[1], r[4]);
  zxy[2] = std::atan2(-r[6], r[8]);
}

// Where a body's joint rotates: its first joint's anchor, else its origin.
void Pivot(const mjModel* m, const mjData* d, int body, double* p) {
  if (m->body_jntnum[body] > 0) {
    mju_copy3(p, d->xanchor + 3 * m->body_jntadr[body]);
  } else {
    mju_copy3(p, d->xpos + 3 * body);
  }
}

std::string Fmt(double v) { return absl::StrFormat("%.6f", std::abs(v) < 5e-7 ? 0.0 : v); }

void AppendJoint(const BvhSkeleton& s, int j, int depth, std::string* out) {
  const BvhJoint& joint = s.joints[j];
  const std::string indent(2 * depth, ' ');
  absl::StrAppend(out, indent, j == 0 ? "ROOT " : "JOINT ", joint.name, "\n", indent, "{\n");
  absl::StrAppend(out, indent, "  OFFSET ", Fmt(joint.offset[0]), " ", Fmt(joint.offset[1]), " ",
                  Fmt(joint.offset[2]), "\n", indent, "  CHANNELS ", joint.channels.size());
  for (const std::string& c : joint.channels) absl::StrAppend(out, " ", c);
  absl::StrAppend(out, "\n");
  for (size_t c = j + 1; c < s.joints.size(); ++c) {
    if (s.joints[c].parent == j) AppendJoint(s, static_cast<int>(c), depth + 1, out);
  }
  if (joint.end_site) {
    absl::StrAppend(out, indent, "  End Site\n", indent, "  {\n", indent, "    OFFSET ",
                    Fmt(joint.end_offset[0]), " ", Fmt(joint.end_offset[1]), " ",
                    Fmt(joint.end_offset[2]), "\n", indent, "  }\n");
  }
  absl::StrAppend(out, indent, "}\n");
}

}  // namespace

absl::StatusOr<BvhSkeleton> BuildBvhSkeleton(const mjModel* m) {
  // The character: the world's one child outside the balls.
  int root = -1;
  for (int b = 1; b < m->nbody; ++b) {
    if (m->body_parentid[b] != 0 || InBallSubtree(m, b)) continue;
    if (root >= 0) {
      return absl::InvalidArgumentError(absl::StrCat(
          "the model has several character bodies below the world (",
          mj_id2name(m, mjOBJ_BODY, root), ", ", mj_id2name(m, mjOBJ_BODY, b),
          "); BVH needs one root"));
    }
    root = b;
  }
  if (root < 0) return absl::InvalidArgumentError("the model has no character body to export");
  for (int j = 0; j < m->njnt; ++j) {
    const int b = m->jnt_bodyid[j];
    if (m->body_rootid[b] != root) continue;
    if (m->jnt_type[j] == mjJNT_SLIDE) {
      return absl::InvalidArgumentError(absl::StrCat(
          "body ", mj_id2name(m, mjOBJ_BODY, b), " has a slide joint, which BVH cannot express"));
    }
    if (m->jnt_type[j] == mjJNT_FREE && b != root) {
      return absl::InvalidArgumentError(absl::StrCat(
          "body ", mj_id2name(m, mjOBJ_BODY, b), " has a free joint below the root"));
    }
  }

  // Rest pose: qpos0.
  MjDataPtr d(mj_makeData(m));
  mju_copy(d->qpos, m->qpos0, m->nq);
  mj_kinematics(m, d.get());

  BvhSkeleton s;
  std::vector<int> joint_of(m->nbody, -1);
  std::vector<int> children(m->nbody, 0);
  for (int b = 1; b < m->nbody; ++b) ++children[m->body_parentid[b]];
  // Bodies are numbered depth-first in MJCF order, parents first.
  for (int b = root; b < m->nbody; ++b) {
    if (m->body_rootid[b] != root) continue;
    const bool leaf = children[b] == 0;
    if (b != root && leaf && m->body_jntnum[b] == 0) {
      // A fixed leaf: its parent's End Site.
      BvhJoint& parent = s.joints[joint_of[m->body_parentid[b]]];
      if (!parent.end_site) {
        double pivot[3], parent_pivot[3], delta[3];
        Pivot(m, d.get(), b, pivot);
        Pivot(m, d.get(), parent.body, parent_pivot);
        mju_sub3(delta, pivot, parent_pivot);
        ToBvh(delta, parent.end_offset);
        parent.end_site = true;
      }
      continue;
    }
    BvhJoint j;
    j.name = mj_id2name(m, mjOBJ_BODY, b) ? mj_id2name(m, mjOBJ_BODY, b) : absl::StrCat("body", b);
    j.body = b;
    if (b == root) {
      j.channels = {"Xposition", "Yposition", "Zposition", "Zrotation", "Xrotation", "Yrotation"};
    } else {
      j.parent = joint_of[m->body_parentid[b]];
      double pivot[3], parent_pivot[3], delta[3];
      Pivot(m, d.get(), b, pivot);
      Pivot(m, d.get(), s.joints[j.parent].body, parent_pivot);
      mju_sub3(delta, pivot, parent_pivot);
      ToBvh(delta, j.offset);
      j.channels = {"Zrotation", "Xrotation", "Yrotation"};
      const int jnt = m->body_jntadr[b];
      if (m->body_jntnum[b] == 1 && m->jnt_type[jnt] == mjJNT_HINGE) {
        double axis[3];
        ToBvh(d->xaxis + 3 * jnt, axis);
        for (int k = 0; k < 3; ++k) {
          if (std::abs(std::abs(axis[k]) - 1) < 1e-9) {
            j.hinge_qpos = m->jnt_qposadr[jnt];
            j.hinge_channel = kAxisChannel[k];
            j.hinge_sign = axis[k] > 0 ? 1 : -1;
            break;
          }
        }
      }
    }
    if (leaf) {
      j.end_site = true;
      if (m->body_geomnum[b] > 0) {
        double pivot[3], delta[3];
        Pivot(m, d.get(), b, pivot);
        mju_sub3(delta, d->geom_xpos + 3 * m->body_geomadr[b], pivot);
        ToBvh(delta, j.end_offset);
      }
    }
    joint_of[b] = static_cast<int>(s.joints.size());
    s.joints.push_back(j);
  }
  return s;
}

absl::StatusOr<BvhExport> ExportBvh(const mjModel* m, const Trajectory& t, int episode) {
  if (t.num_samples() == 0) {
    return absl::InvalidArgumentError("the recording has no samples: nothing to export");
  }
  if (t.nq != m->nq) {
    return absl::InvalidArgumentError(
        absl::StrCat("the recording has nq ", t.nq, " but the model ", m->nq));
  }
  std::vector<int> samples;
  for (int i = 0; i < t.num_samples(); ++i) {
    if (t.episode(i) == episode) samples.push_back(i);
  }
  if (samples.empty()) {
    return absl::InvalidArgumentError(absl::StrCat("the recording has no episode ", episode,
                                                   " (episodes 0..", t.episode(t.num_samples() - 1),
                                                   ")"));
  }
  absl::StatusOr<BvhSkeleton> skeleton = BuildBvhSkeleton(m);
  if (!skeleton.ok()) return skeleton.status();
  const std::vector<BvhJoint>& joints = skeleton->joints;

  BvhExport out;
  out.frames = static_cast<int>(samples.size());
  out.frame_time = t.control_dt;
  out.joints = static_cast<int>(joints.size());
  for (const BvhJoint& j : joints) out.channels += static_cast<int>(j.channels.size());

  MjDataPtr d(mj_makeData(m));
  mju_copy(d->qpos, m->qpos0, m->nq);
  mj_kinematics(m, d.get());
  std::vector<double> rest(9 * m->nbody);  // rest world rotations
  mju_copy(rest.data(), d->xmat, 9 * m->nbody);

  out.bvh = "HIERARCHY\n";
  AppendJoint(*skeleton, 0, 0, &out.bvh);
  absl::StrAppend(&out.bvh, "MOTION\nFrames: ", out.frames, "\nFrame Time: ",
                  absl::StrFormat("%.6f", t.control_dt), "\n");

  const std::vector<int> balls = BallBodies(m);
  if (!balls.empty()) {
    out.balls_csv = "frame,time";
    for (int b : balls) {
      const char* name = mj_id2name(m, mjOBJ_BODY, b);
      absl::StrAppend(&out.balls_csv, ",", name, "_x,", name, "_y,", name, "_z");
    }
    out.balls_csv += "\n";
  }

  std::vector<double> world(9 * joints.size());  // W_j = R_j(t)·R_j0ᵀ, MuJoCo axes
  for (int f = 0; f < out.frames; ++f) {
    const int s = samples[f];
    mju_copy(d->qpos, t.qpos_at(s), m->nq);
    mj_kinematics(m, d.get());
    std::string line;
    for (size_t j = 0; j < joints.size(); ++j) {
      const BvhJoint& joint = joints[j];
      const int b = joint.body;
      double* w = &world[9 * j];
      MulMatTransB(d->xmat + 9 * b, &rest[9 * b], w);
      if (joint.hinge_qpos >= 0) {
        const double angle = d->qpos[joint.hinge_qpos] - m->qpos0[joint.hinge_qpos];
        double zxy[3] = {0, 0, 0};
        zxy[joint.hinge_channel] = joint.hinge_sign * angle * kDegrees;
        absl::StrAppend(&line, " ", Fmt(zxy[0]), " ", Fmt(zxy[1]), " ", Fmt(zxy[2]));
        continue;
      }
      double local[9], local_bvh[9], zxy[3];
      if (joint.parent < 0) {
        mju_copy(local, w, 9);
        double p[3], pb[3];
        Pivot(m, d.get(), b, p);
        ToBvh(p, pb);
        absl::StrAppend(&line, Fmt(pb[0]), " ", Fmt(pb[1]), " ", Fmt(pb[2]), " ");
      } else {
        MulMatTransA(&world[9 * joint.parent], w, local);
      }
      RotationToBvh(local, local_bvh);
      EulerZxy(local_bvh, zxy);
      absl::StrAppend(&line, j ? " " : "", Fmt(zxy[0] * kDegrees), " ", Fmt(zxy[1] * kDegrees),
                      " ", Fmt(zxy[2] * kDegrees));
    }
    absl::StrAppend(&out.bvh, line, "\n");
    if (!balls.empty()) {
      absl::StrAppend(&out.balls_csv, f, ",",
                      absl::StrFormat("%.6f", t.time[s] - t.time[samples[0]]));
      for (int b : balls) {
        double p[3];
        ToBvh(d->xpos + 3 * b, p);
        absl::StrAppend(&out.balls_csv, ",", Fmt(p[0]), ",", Fmt(p[1]), ",", Fmt(p[2]));
      }
      out.balls_csv += "\n";
    }
  }
  return out;
}

}  // namespace juggle
