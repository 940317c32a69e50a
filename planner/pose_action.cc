#include "planner/pose_action.h"

namespace juggle::planner {

void AddPoseChangeAction(const humanoid::Joints& joints, const humanoid::CharacterPose& from,
                         const humanoid::CharacterPose& to, double action_torque, double* out) {
  for (const humanoid::ActuatedJoint& joint : joints) {
    if (!(joint.torque_scale > 0)) continue;  // actions do nothing there (and kp / 0)
    const int a = joint.dof_adr - 6;
    const double scale = joint.kp / (action_torque * joint.torque_scale);
    if (joint.dofs == 3) {
      double d[3];
      mju_subQuat(d, to.data() + joint.qpos_adr, from.data() + joint.qpos_adr);
      for (int k = 0; k < 3; ++k) out[a + k] += scale * d[k];
    } else {
      out[a] += scale * (to[joint.qpos_adr] - from[joint.qpos_adr]);
    }
  }
}

}  // namespace juggle::planner
