// A geom's bounds, for code that needs a part's size and place whatever its shape (the football
// foot's reach to the ball, a trapping part's surface and centre). Primitives: their own centre
// and half sizes (box: its half sizes; sphere: the radius thrice; capsule: the radius, the radius,
// the half-length plus the radius; cylinder: the radius, the radius, the half-length; ellipsoid:
// its semi-axes). A mesh: the box that bounds its vertices along its body's axes — for the
// football boot (configs/models/football_pitch.xml), the box foot it replaces with a higher top,
// while MuJoCo's centre for a mesh (its volume's) sits nearer the heel.
#ifndef JUGGLE_ENVS_GEOM_EXTENT_H_
#define JUGGLE_ENVS_GEOM_EXTENT_H_

#include <array>

#include <mujoco/mujoco.h>

namespace juggle {

struct GeomBounds {
  int geom = -1;
  bool mesh = false;
  std::array<double, 3> centre_in_body{};  // meshes only: the bounds' centre in the body frame
  // Primitives: along the geom's axes; meshes: along the body's. Planes, height fields: zeros.
  std::array<double, 3> half_extents{};
  double thinnest() const;
  double longest() const;
};
GeomBounds MeasureGeomBounds(const mjModel* m, int geom);

// The bounds' centre in world coordinates (after mj_kinematics): geom_xpos for primitives.
void GeomBoundsCentre(const GeomBounds& bounds, const mjModel* m, const mjData* d,
                      double centre[3]);

}  // namespace juggle

#endif  // JUGGLE_ENVS_GEOM_EXTENT_H_
