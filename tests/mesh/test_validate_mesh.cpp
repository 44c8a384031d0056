#include <gtest/gtest.h>

#include <algorithm>
#include <tbb/task_arena.h>

#include "mesh/alpha_wrap.h"
#include "mesh/self_intersections.h"
#include "mesh/shapes.h"
#include "mesh/validate_mesh.h"

namespace cdbench {
namespace {

TEST(Validate, SphereIsAValidGenusZeroSolid) {
  const ValidatedMesh v = validate_mesh(make_icosphere(2.0, 3));
  EXPECT_TRUE(v.report.valid());
  EXPECT_TRUE(v.report.closed);
  EXPECT_TRUE(v.report.self_intersections_checked);
  EXPECT_EQ(v.report.components, 1u);
  EXPECT_EQ(v.report.genus, 0);
  const double ball = 4.0 / 3.0 * M_PI * 8.0;
  EXPECT_LT(v.report.volume_hi, ball);  // inscribed polyhedron
  EXPECT_GT(v.report.volume_lo, 0.95 * ball);
  EXPECT_TRUE(v.report.notices.empty());
}

TEST(Validate, TorusHasGenusOne) {
  const ValidatedMesh v = validate_mesh(make_torus(2.0, 0.5, 48, 24));
  EXPECT_TRUE(v.report.valid());
  EXPECT_EQ(v.report.genus, 1);
}

TEST(Validate, TwoComponentsAreAllowedAndReported) {
  const TriangleMesh m = merge_meshes(make_icosphere(1.0, 2), make_icosphere(1.0, 2, Vec3(5, 0, 0)));
  const ValidatedMesh v = validate_mesh(m);
  EXPECT_TRUE(v.report.valid());
  EXPECT_EQ(v.report.components, 2u);
  EXPECT_EQ(v.report.genus, 0);
  ASSERT_FALSE(v.report.notices.empty());
  EXPECT_NE(v.report.notices[0].find("2 connected components"), std::string::npos);
  // The genus sums over the components (each counted on its own Euler characteristic): a torus and
  // two tori beside a sphere.
  const TriangleMesh torus = make_torus(2.0, 0.5, 48, 24);
  EXPECT_EQ(validate_mesh(merge_meshes(make_icosphere(1.0, 2, Vec3(9, 0, 0)), torus)).report.genus, 1);
  TriangleMesh moved = torus;
  for (Vec3& p : moved.vertices) p += Vec3(0, 0, 4);
  EXPECT_EQ(validate_mesh(merge_meshes(merge_meshes(make_icosphere(1.0, 2, Vec3(9, 0, 0)), torus), moved)).report.genus, 2);
}

TEST(Validate, InwardMeshIsReversedWithANotice) {
  TriangleMesh m = make_icosphere(1.0, 2);
  for (Face& f : m.faces) std::swap(f[1], f[2]);
  const ValidatedMesh v = validate_mesh(m);
  EXPECT_TRUE(v.report.valid());
  EXPECT_GT(v.report.volume_lo, 0.0);
  bool noticed = false;
  for (const auto& n : v.report.notices) noticed |= n.find("inward-oriented") != std::string::npos;
  EXPECT_TRUE(noticed);
}

TEST(Validate, OneThreadAndAllGiveTheSameMeshAndBits) {
  // 20,480 faces: several blocks of the volume's sum and of the parallel passes. Inward, so that
  // the one-shell orientation (by the volume's sign) reverses every face.
  TriangleMesh m = make_icosphere(1.0, 5);
  for (Face& f : m.faces) std::swap(f[1], f[2]);
  ValidatedMesh one;
  tbb::task_arena(1).execute([&] { one = validate_mesh(m); });
  const ValidatedMesh all = validate_mesh(m);
  ASSERT_TRUE(all.report.valid());
  EXPECT_EQ(one.report.volume_lo, all.report.volume_lo);
  EXPECT_EQ(one.report.volume_hi, all.report.volume_hi);
  EXPECT_EQ(one.mesh.faces, all.mesh.faces);
  EXPECT_GT(all.report.volume_lo, 0.0);
  const double ball = 4.0 / 3.0 * M_PI;
  EXPECT_LT(all.report.volume_hi, ball);
  EXPECT_GT(all.report.volume_lo, 0.99 * ball);
  for (std::size_t i = 0; i < m.faces.size(); ++i)
    ASSERT_EQ(all.mesh.faces[i], (Face{m.faces[i][0], m.faces[i][2], m.faces[i][1]})) << i;
}

TEST(Validate, InconsistentFacesAreFlippedToAgree) {
  // Every third face reversed: the breadth-first flip must make them agree with their
  // neighbours (then the volume's sign keeps the whole shell outward): the original faces.
  const TriangleMesh m = make_icosphere(1.0, 3);
  TriangleMesh mixed = m;
  for (std::size_t i = 0; i < mixed.faces.size(); i += 3) std::swap(mixed.faces[i][1], mixed.faces[i][2]);
  const ValidatedMesh v = validate_mesh(mixed);
  ASSERT_TRUE(v.report.valid());
  EXPECT_EQ(v.mesh.faces, m.faces);
  bool noticed = false;  // the count is of the faces that disagreed with face 0
  for (const auto& n : v.report.notices) noticed |= n.find("faces were flipped to make the orientation consistent") != std::string::npos;
  EXPECT_TRUE(noticed);
}

TEST(Validate, HollowBallKeepsTheInnerShellInward) {
  // An outer sphere and a smaller inner sphere: the solid between them. Whatever the input
  // orientation, the inner shell must face the cavity (volume = outer - inner).
  const TriangleMesh outer = make_icosphere(2.0, 2), inner = make_icosphere(1.0, 2);
  const ValidatedMesh v = validate_mesh(merge_meshes(outer, inner));
  ASSERT_TRUE(v.report.valid());
  const double vo = validate_mesh(outer).report.volume_lo, vi = validate_mesh(inner).report.volume_lo;
  EXPECT_NEAR(v.report.volume_lo, vo - vi, 1e-9 * vo);
}

TEST(Validate, NestedSphereWithoutSelfIntersectionIsDetectedAsSelfIntersectingWhenTheyCross) {
  const TriangleMesh m = merge_meshes(make_icosphere(1.0, 2), make_icosphere(1.0, 2, Vec3(1.0, 0, 0)));
  const ValidatedMesh v = validate_mesh(m);
  EXPECT_FALSE(v.report.valid());
  EXPECT_TRUE(v.report.has("self-intersection"));
  // The pairs themselves (the offset repair mends folds with them): one of each sphere, sorted, the
  // same count as the message's.
  const auto& pairs = v.report.intersecting_faces;
  ASSERT_FALSE(pairs.empty());
  EXPECT_TRUE(std::is_sorted(pairs.begin(), pairs.end()));
  const std::size_t first = make_icosphere(1.0, 2).faces.size();
  for (const auto& [a, b] : pairs) EXPECT_TRUE(a < first && b >= first) << a << " " << b;
  for (const auto& e : v.report.errors) {
    if (e.kind == "self-intersection") {
      EXPECT_EQ(e.count, pairs.size());
    }
  }
  EXPECT_TRUE(validate_mesh(make_icosphere(1.0, 2)).report.intersecting_faces.empty());
}

// The self-intersection test runs beside the edge, fan and orientation steps (validate_mesh): with
// every third face of two crossing spheres reversed (the orientation step flips them back while the
// test runs), the pairs are those of the test on the validated mesh, on one thread and on all.
// A mesh whose edges are not manifold reports no self-intersection (it is not checked there),
// although its faces cross.
TEST(Validate, SelfIntersectionsBesideTheOtherStepsAreThoseOfTheFinalMesh) {
  TriangleMesh m = merge_meshes(make_icosphere(1.0, 3), make_icosphere(1.0, 3, Vec3(0.7, 0.2, 0.1)));
  for (std::size_t i = 0; i < m.faces.size(); i += 3) std::swap(m.faces[i][1], m.faces[i][2]);
  ValidatedMesh one;
  tbb::task_arena(1).execute([&] { one = validate_mesh(m); });
  const ValidatedMesh all = validate_mesh(m);
  ASSERT_TRUE(all.report.self_intersections_checked);
  ASSERT_FALSE(all.report.intersecting_faces.empty());
  const auto expected = self_intersecting_faces(all.mesh);
  ASSERT_EQ(all.report.intersecting_faces.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(all.report.intersecting_faces[i].first, expected[i].first);
    EXPECT_EQ(all.report.intersecting_faces[i].second, expected[i].second);
  }
  EXPECT_EQ(one.report.intersecting_faces, all.report.intersecting_faces);
  EXPECT_EQ(one.mesh.faces, all.mesh.faces);

  TriangleMesh pinched = merge_meshes(make_icosphere(1.0, 2), make_icosphere(1.0, 2, Vec3(0.7, 0, 0)));
  pinched.faces.push_back(pinched.faces.front());  // an edge of three faces (and a repeated face)
  const ValidatedMesh p = validate_mesh(pinched);
  EXPECT_TRUE(p.report.has("non-manifold-edge"));
  EXPECT_FALSE(p.report.self_intersections_checked);
  EXPECT_FALSE(p.report.has("self-intersection"));
  EXPECT_TRUE(p.report.intersecting_faces.empty());
}

TEST(AlphaWrap, OpenSurfaceBecomesAValidSolid) {
  TriangleMesh box = make_box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  box.faces.resize(10);  // open: two triangles missing
  ASSERT_FALSE(validate_mesh(box).report.valid());
  PolygonSoup soup;
  soup.points = box.vertices;
  for (const Face& f : box.faces) soup.polygons.push_back({f[0], f[1], f[2]});
  AlphaWrapOptions opt;
  opt.alpha = 2.0;  // wider than the 1 x 1 hole: the wrap closes it instead of entering
  opt.offset = 0.01;
  const AlphaWrapResult w = alpha_wrap(soup, opt);
  const ValidatedMesh v = validate_mesh(w.mesh);
  EXPECT_TRUE(v.report.valid()) << (v.report.errors.empty() ? "" : v.report.errors[0].message);
  EXPECT_EQ(v.report.genus, 0);
  EXPECT_GT(v.report.volume_lo, 1.0);  // encloses the input
  EXPECT_LT(v.report.volume_hi, 1.2);
}

}  // namespace
}  // namespace cdbench

namespace cdbench {
namespace {

TEST(Validate, CoordinatesOutsideTheSupportedScaleAreNamed) {
  const auto scaled = [](double s) {
    TriangleMesh box = make_box(Vec3(0, 0, 0), Vec3(1, 1, 1));
    for (Vec3& v : box.vertices) v *= s;
    return validate_mesh(box);
  };
  for (double s : {1e150, 1e200, 1e-150, 1e-45}) {
    const ValidatedMesh v = scaled(s);
    ASSERT_TRUE(v.report.has("coordinate-range")) << s;
    EXPECT_NE(v.report.errors[0].message.find(s > 1 ? "scale the mesh down" : "scale the mesh up"), std::string::npos);
  }
  for (double s : {1e39, 1e-39, 1.0}) {
    const ValidatedMesh v = scaled(s);
    EXPECT_TRUE(v.report.valid()) << s;
    EXPECT_LE(v.report.volume_lo, s * s * s);
    EXPECT_GE(v.report.volume_hi, s * s * s);
  }
}

}  // namespace
}  // namespace cdbench
