#include "envs/geom_extent.h"

#include <algorithm>
#include <cmath>

namespace juggle {

double GeomBounds::thinnest() const {
  return *std::min_element(half_extents.begin(), half_extents.end());
}

double GeomBounds::longest() const {
  return *std::max_element(half_extents.begin(), half_extents.end());
}

GeomBounds MeasureGeomBounds(const mjModel* m, int geom) {
  GeomBounds b;
  b.geom = geom;
  const double* s = m->geom_size + 3 * geom;
  switch (m->geom_type[geom]) {
    case mjGEOM_BOX:
    case mjGEOM_ELLIPSOID: b.half_extents = {s[0], s[1], s[2]}; break;
    case mjGEOM_SPHERE: b.half_extents = {s[0], s[0], s[0]}; break;
    case mjGEOM_CAPSULE: b.half_extents = {s[0], s[0], s[1] + s[0]}; break;
    case mjGEOM_CYLINDER: b.half_extents = {s[0], s[0], s[1]}; break;
    case mjGEOM_MESH: {
      b.mesh = true;
      const int mesh = m->geom_dataid[geom];
      const float* vert = m->mesh_vert + 3 * m->mesh_vertadr[mesh];
      double low[3] = {INFINITY, INFINITY, INFINITY}, high[3] = {-INFINITY, -INFINITY, -INFINITY};
      for (int v = 0; v < m->mesh_vertnum[mesh]; ++v) {
        const double in_geom[3] = {vert[3 * v], vert[3 * v + 1], vert[3 * v + 2]};
        double in_body[3];
        mju_rotVecQuat(in_body, in_geom, m->geom_quat + 4 * geom);  // MuJoCo's vertices: geom frame
        for (int k = 0; k < 3; ++k) {
          in_body[k] += m->geom_pos[3 * geom + k];
          low[k] = std::min(low[k], in_body[k]);
          high[k] = std::max(high[k], in_body[k]);
        }
      }
      for (int k = 0; k < 3; ++k) {
        b.centre_in_body[k] = (low[k] + high[k]) / 2;
        b.half_extents[k] = (high[k] - low[k]) / 2;
      }
      break;
    }
    default: break;
  }
  return b;
}

void GeomBoundsCentre(const GeomBounds& bounds, const mjModel* m, const mjData* d,
                      double centre[3]) {
  if (!bounds.mesh) {
    mju_copy3(centre, d->geom_xpos + 3 * bounds.geom);
    return;
  }
  const int body = m->geom_bodyid[bounds.geom];
  mju_rotVecMat(centre, bounds.centre_in_body.data(), d->xmat + 9 * body);
  mju_addTo3(centre, d->xpos + 3 * body);
}

}  // namespace juggle
