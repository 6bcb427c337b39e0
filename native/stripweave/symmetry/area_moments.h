// AreaMoments: the area-weighted centroid and second moments of a triangle
// mesh's surface (not of the enclosed volume: open parts have none).
//
// area_moments(mesh) -> {area, centroid, axes (columns, unit), moments}
//   moments[i] is the area-weighted variance along axes.col(i), ascending.
//   Exact for the triangulated surface: a triangle's integral of x x^T is
//   A/12 (sum v_i v_i^T + (sum v_i)(sum v_i)^T), independent of how a planar
//   region is triangulated, so a symmetric part's centroid and axes are
//   symmetric whatever the mesh.
// Why: every global symmetry of a surface fixes its area centroid and maps
// its principal axes to principal axes; a reflection's normal and a rotation's
// axis are principal axes unless two moments are equal (paper §5.8's
// candidates; Mitra et al. 2013).
#pragma once

#include "stripweave/surface/triangle_mesh.h"

namespace stripweave {

struct AreaMoments {
  double area = 0;
  Vec3 centroid = Vec3::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  Vec3 moments = Vec3::Zero();
};

AreaMoments area_moments(const TriangleMesh& mesh);

}  // namespace stripweave
