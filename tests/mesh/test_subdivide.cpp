// Loop subdivision (the generator of larger meshes of the same shape): faces x 4 per step, still a
// valid closed solid of the same genus, close to the input's surface.
#include <gtest/gtest.h>

#include "distance/signed_distance.h"
#include "mesh/shapes.h"
#include "mesh/subdivide.h"
#include "mesh/validate_mesh.h"
#include "util/error.h"

namespace cdbench {
namespace {

TEST(Subdivide, TorusStaysAValidGenusOneSolidNearTheInput) {
  const TriangleMesh torus = make_torus(2.0, 0.5, 48, 24);
  for (int steps : {1, 2}) {
    const TriangleMesh fine = loop_subdivide(torus, steps);
    EXPECT_EQ(fine.faces.size(), torus.faces.size() << (2 * steps));
    const ValidatedMesh v = validate_mesh(fine);
    EXPECT_TRUE(v.report.valid());
    EXPECT_EQ(v.report.genus, 1);
    EXPECT_EQ(v.report.components, 1u);
    // Loop smoothing moves the surface by a fraction of an edge length (edges ~0.26 here).
    const SignedDistance coarse(torus);
    for (std::size_t i = 0; i < fine.vertices.size(); i += 97)
      EXPECT_LT(std::abs(coarse.signed_distance(fine.vertices[i]).hi), 0.05) << i;
  }
  EXPECT_EQ(loop_subdivide(torus, 0).faces.size(), torus.faces.size());
}

TEST(Subdivide, RejectsAnOpenSurface) {
  TriangleMesh open = make_icosphere(1.0, 1);
  open.faces.pop_back();
  EXPECT_THROW(loop_subdivide(open, 1), InputError);
}

}  // namespace
}  // namespace cdbench
