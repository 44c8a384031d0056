#pragma once
// The plain indexed triangle mesh every module works on (no CGAL types in interfaces).
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/aabb.h"

namespace cdbench {

using Vec3 = Eigen::Vector3d;
using Face = std::array<std::uint32_t, 3>;

struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<Face> faces;  // counter-clockwise seen from outside once validated

  Aabb bbox() const {
    Aabb b;
    for (const Vec3& v : vertices) b.extend(v);
    return b;
  }
};

// A polygon soup as read from a file: polygons may have any number of corners.
struct PolygonSoup {
  std::vector<Vec3> points;
  std::vector<std::vector<std::size_t>> polygons;
  std::vector<std::string> notices;  // what the reader skipped or fixed (validate_mesh reports them)
};

}  // namespace cdbench
