#include "stripweave/symmetry/area_moments.h"

#include <Eigen/Eigenvalues>

namespace stripweave {

AreaMoments area_moments(const TriangleMesh& mesh) {
  AreaMoments out;
  Vec3 first = Vec3::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (const Tri& t : mesh.triangles) {
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const double area = 0.5 * (b - a).cross(c - a).norm();
    const Vec3 sum = a + b + c;
    out.area += area;
    first += area / 3.0 * sum;
    second += area / 12.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
  }
  if (out.area <= 0) return out;
  out.centroid = first / out.area;
  const Eigen::Matrix3d covariance = second / out.area - out.centroid * out.centroid.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(covariance);
  out.axes = eigen.eigenvectors();
  out.moments = eigen.eigenvalues();
  return out;
}

}  // namespace stripweave
