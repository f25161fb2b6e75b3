// A bounding-volume hierarchy over the triangles of a mesh, for queries that would otherwise
// visit every triangle: the first triangle a ray crosses, whether any triangle lies within a
// distance, the nearest triangle, and the generalised winding number. Built in O(n log n) (median split of the
// triangle centroids along the longest axis); a query visits O(log n) nodes on ordinary meshes.
//
// Written here rather than taken from a Debian package: the ones that would fit (libembree's
// BVH, CGAL's AABB_tree) bring a large dependency for three small queries, and none of them
// offers the winding number; this one keeps the exact per-triangle tests of the brute-force
// code (Utilities/TriangleMesh.h), so its answers match it.
//
// The winding number sums the exact solid angles of nearby triangles and replaces every far
// cluster by a truncated expansion about its area-weighted centroid (after
//   G. Barill, N. Dickson, R. Schmidt, D. Levin, A. Jacobson: Fast Winding Numbers for Soups and
//   Clouds. ACM Trans. Graph. 37(4), 2018, Sec. 3.2: the dipole and the first moment of the
//   triangles' area-weighted normals): within 0.02 of the exact sum (unit test), exact in the
//   near field; ample for the inside/outside tests (winding number > 0.5) that use it.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "Utilities/Types.h"
#include "Utilities/TriangleMesh.h"

namespace consph {

class TriangleBvh {
 public:
  static constexpr std::size_t kNoTriangle = std::numeric_limits<std::size_t>::max();

  // Copies the triangles' corners: the hierarchy does not refer to the mesh after building.
  explicit TriangleBvh(const TriangleMesh& mesh);

  std::size_t triangleCount() const { return corners_.size(); }

  // Distance t > 1e-9 along o + t dir to the nearest triangle other than `skip` (an index into
  // the mesh's triangles); infinity when none is crossed. The same answer as testing every
  // triangle with rayTriangleDistance, wherever that answer is at most `within` (beyond it: the
  // true distance or infinity; a caller that needs only near hits saves walking the whole ray).
  Real firstHitDistance(const Vector3r& o, const Vector3r& dir, std::size_t skip = kNoTriangle,
                        Real within = std::numeric_limits<Real>::infinity()) const;

  // Whether some triangle has a point closer than `distance` to p.
  bool anyTriangleCloserThan(const Vector3r& p, Real distance) const;

  // The triangle nearest to p among those closer than `within`: its index in the mesh, the
  // closest point on it, the distance and whether that point is inside the face (not on an edge
  // or a vertex). Ties go to the lowest mesh index, so the answer is the brute force's (the first
  // triangle in mesh order with the least closestPointOnTriangle distance). `triangle` is
  // kNoTriangle when none is that close.
  struct Nearest {
    std::size_t triangle = kNoTriangle;
    Real distance = 0;
    Vector3r point = Vector3r::Zero();
    bool onFace = false;
  };
  Nearest nearestTriangle(const Vector3r& p, Real within) const;

  // Generalised winding number around p: 1 inside a closed mesh with outward normals, 0 outside
  // (within 0.02 of the exact sum: the side of 0.5 is the brute force's off the surface).
  Real windingNumber(const Vector3r& p) const;

 private:
  // A node covers triangles [first, first + count) of corners_ when it is a leaf (count > 0);
  // otherwise its children are the next node and `right`.
  struct Node {
    Vector3r lo, hi;             // bounding box of its triangles, padded (see build)
    Eigen::Vector3d areaNormal;  // sum of the triangles' area-weighted normals (dipole moment)
    Eigen::Vector3d centre;      // area-weighted centroid (dipole position)
    Eigen::Matrix3d moment;      // sum of area-weighted normal (x) (centroid - centre), the next order
    double radius = 0;           // farthest corner from the centre
    std::uint32_t first = 0, count = 0, right = 0;
  };
  std::uint32_t build(std::uint32_t first, std::uint32_t count, std::vector<Vector3r>& centroids);

  std::vector<std::array<Vector3r, 3>> corners_;  // triangles in tree order
  std::vector<std::size_t> meshIndex_;            // tree order -> index in the mesh
  std::vector<Node> nodes_;                       // nodes_[0] is the root
};

}  // namespace consph
