// The certified Hausdorff distance against closed forms, dense sampling, and CGAL's
// bounded-error Hausdorff distance (an independent implementation, in doubles).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <random>

#include "distance/hausdorff.h"
#include "mesh/shapes.h"
#include "test_scale.h"

namespace cdbench {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalMesh = CGAL::Surface_mesh<Kernel::Point_3>;

CgalMesh to_cgal(const TriangleMesh& m) {
  CgalMesh out;
  std::vector<CgalMesh::Vertex_index> v;
  for (const Vec3& p : m.vertices) v.push_back(out.add_vertex(Kernel::Point_3(p.x(), p.y(), p.z())));
  for (const Face& f : m.faces) out.add_face(v[f[0]], v[f[1]], v[f[2]]);
  return out;
}

// Largest certified distance lower end over random points of A's triangles (a lower bound of h).
double sampled_lower(const TriangleMesh& a, const SignedDistance& b, int per_face) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double best = 0.0;
  for (const Face& f : a.faces)
    for (int k = 0; k < per_face; ++k) {
      double s = u(rng), t = u(rng);
      if (s + t > 1.0) s = 1.0 - s, t = 1.0 - t;
      const Vec3 p = a.vertices[f[0]] + s * (a.vertices[f[1]] - a.vertices[f[0]]) + t * (a.vertices[f[2]] - a.vertices[f[0]]);
      best = std::max(best, b.unsigned_distance(p).lo);
    }
  return best;
}

TEST(Hausdorff, NestedCubesHaveTheirClosedForms) {
  const TriangleMesh inner = make_box(Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5));
  const TriangleMesh outer = make_box(Vec3(-1, -1, -1), Vec3(1, 1, 1));
  HausdorffOptions tight;
  tight.relative_tolerance = 1e-3;
  const SurfaceDeviation d = two_sided_hausdorff(inner, outer, tight);
  // Every point of the inner cube is 0.5 from the outer faces at most, attained on its faces.
  EXPECT_TRUE(d.first_to_second.distance.contains(0.5));
  EXPECT_LE(d.first_to_second.distance.width(), 1e-3 * 0.5);
  // The outer corners are farthest from the inner cube: sqrt(3)/2.
  EXPECT_TRUE(d.second_to_first.distance.contains(std::sqrt(3.0) / 2));
  EXPECT_LE(d.second_to_first.distance.width(), 1e-3);
  EXPECT_TRUE(d.first_to_second.converged && d.second_to_first.converged);
}

TEST(Hausdorff, IdenticalSurfacesAreAtDistanceZero) {
  const TriangleMesh torus = make_torus(2.0, 0.5, 32, 16);
  const SurfaceDeviation d = two_sided_hausdorff(torus, torus);
  EXPECT_EQ(d.first_to_second.distance.lo, 0.0);
  EXPECT_LE(d.first_to_second.distance.hi, 1e-8);
  EXPECT_LE(d.second_to_first.distance.hi, 1e-8);
}

TEST(Hausdorff, SpheresOfDifferentResolutionAgreeWithSamplingAndCgal) {
  // The coarse sphere is inscribed in the fine one: faces of the coarse one lie inside.
  const TriangleMesh coarse = make_icosphere(1.0, 1, Vec3(0.01, -0.02, 0.03));
  const TriangleMesh fine = make_icosphere(1.05, 4);
  HausdorffOptions opt;
  opt.relative_tolerance = 1e-4;
  for (int dir = 0; dir < 2; ++dir) {
    const TriangleMesh& a = dir == 0 ? coarse : fine;
    const TriangleMesh& b = dir == 0 ? fine : coarse;
    const SignedDistance to_b(b);
    const HausdorffResult h = one_sided_hausdorff(a, to_b, opt);
    SCOPED_TRACE(dir);
    EXPECT_TRUE(h.converged);
    EXPECT_LE(h.distance.width(), 1e-4 * h.distance.lo + 1e-12);
    EXPECT_LE(sampled_lower(a, to_b, 200), h.distance.hi);
    EXPECT_GE(to_b.unsigned_distance(h.witness).hi, h.distance.lo);
    const double cgal = CGAL::Polygon_mesh_processing::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(
        to_cgal(a), to_cgal(b), 1e-6);
    EXPECT_GE(cgal, h.distance.lo - 2e-6);
    EXPECT_LE(cgal, h.distance.hi + 2e-6);
  }
}

TEST(Hausdorff, TheMaximumInsideATriangleIsFoundNotOnlyAtItsCorners) {
  // A large flat triangle over a finely curved target: the bound must not be taken at the corners
  // only (the distance of a point to a curved surface is not convex).
  TriangleMesh tri;
  tri.vertices = {Vec3(-0.9, -0.9, 0.0), Vec3(0.9, -0.9, 0.0), Vec3(0.0, 0.9, 0.0)};
  tri.faces = {{0, 1, 2}};
  const SignedDistance sphere(make_icosphere(1.0, 4));
  const HausdorffResult h = one_sided_hausdorff(tri, sphere);
  for (const Vec3& v : tri.vertices) EXPECT_LT(sphere.unsigned_distance(v).hi, 0.3);  // corners alone would say 0.3
  const double sampled = sampled_lower(tri, sphere, 20000);
  EXPECT_LE(sampled, h.distance.hi);
  EXPECT_GE(sampled, h.distance.lo - 1e-3);
  EXPECT_NEAR(h.distance.lo, 1.0, 2e-2);  // the centre of the sphere lies on the triangle
}

TEST(Hausdorff, AConstantDistanceToAFinelyTriangulatedSheetConverges) {
  // Every point of a square is exactly h from a parallel sheet of 2 x 60 x 60 irregular triangles
  // (the shape of a wrap's distance to its input): cells straddling the sheet's edges and vertices
  // must be bounded by their pieces, or the search runs into its work limit.
  const double h = 1e-3;
  TriangleMesh square;
  square.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  square.faces = {{0, 1, 2}, {0, 2, 3}};
  TriangleMesh sheet;
  const int n = test_scale::pick(60, 30);  // a quarter of the triangles under the sanitizers
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> jitter(-0.3 / n, 0.3 / n);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const bool inner = i > 0 && i < n && j > 0 && j < n;  // keep the border straight: the sheet covers the square
      sheet.vertices.push_back(Vec3{double(i) / n + (inner ? jitter(rng) : 0.0), double(j) / n + (inner ? jitter(rng) : 0.0), h});
    }
  const auto at = [&](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      sheet.faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      sheet.faces.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  HausdorffOptions tight;
  tight.relative_tolerance = 1e-3;
  const HausdorffResult r = one_sided_hausdorff(square, SignedDistance(sheet), tight);
  EXPECT_TRUE(r.converged) << r.cells << " cells";
  EXPECT_TRUE(r.distance.contains(h)) << r.distance.lo << " " << r.distance.hi;
  EXPECT_LE(r.distance.width(), 1e-3 * h);
}

}  // namespace
}  // namespace cdbench
