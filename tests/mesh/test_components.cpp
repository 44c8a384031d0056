#include <gtest/gtest.h>

#include "mesh/components.h"
#include "mesh/shapes.h"

namespace cdbench {
namespace {

TEST(FaceComponents, NumberedLikeTheRepresentatives) {
  const TriangleMesh a = make_icosphere(1.0, 1), b = make_box(Vec3(3, 0, 0), Vec3(4, 1, 1));
  const TriangleMesh m = merge_meshes(b, a);
  std::size_t count = 0;
  const std::vector<std::uint32_t> comp = face_components(m, &count);
  ASSERT_EQ(count, 2u);
  ASSERT_EQ(comp.size(), m.faces.size());
  const std::vector<std::uint32_t> reps = component_representatives(m);
  ASSERT_EQ(reps.size(), 2u);
  for (std::size_t i = 0; i < m.faces.size(); ++i) EXPECT_EQ(comp[i], i < b.faces.size() ? 0u : 1u) << i;
  // The component of a face holding a representative vertex has that representative's number.
  for (std::size_t i = 0; i < m.faces.size(); ++i)
    for (std::uint32_t v : m.faces[i])
      for (std::size_t k = 0; k < reps.size(); ++k)
        if (v == reps[k]) {
          EXPECT_EQ(comp[i], k);
        }
}

}  // namespace
}  // namespace cdbench
