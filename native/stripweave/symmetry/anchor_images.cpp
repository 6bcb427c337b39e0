#include "stripweave/symmetry/anchor_images.h"

#include "stripweave/core/error.h"

namespace stripweave {

std::vector<Anchor> anchor_images(const Symmetry& symmetry, const Anchor& anchor, const TriangleMesh& mesh,
                                  const SurfaceLocator& locator) {
  std::vector<Anchor> out;
  for (int k = 1; k <= symmetry.images(); ++k) {
    Anchor image;
    const SurfacePoint3 at = locator.closest(symmetry.map_point(anchor.point, k));
    image.point = at.point;
    if (anchor.directional()) {
      const Tri& t = mesh.triangles[at.triangle];
      Vec3 n = (mesh.positions[t[1]] - mesh.positions[t[0]]).cross(mesh.positions[t[2]] - mesh.positions[t[0]]);
      const Vec3 d = symmetry.map_direction(anchor.direction, k);
      const Vec3 tangent = n.norm() > 0 ? Vec3(d - n.normalized() * d.dot(n.normalized())) : d;
      if (!(tangent.norm() > 1e-9 * d.norm()))
        throw InputError("a symmetric image of an anchor's direction is normal to the surface there");
      image.direction = tangent.normalized();
    }
    out.push_back(image);
  }
  return out;
}

}  // namespace stripweave
