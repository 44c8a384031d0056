// The self-intersection test against CGAL's PMP::self_intersections (the reference it replaced):
// the same pairs on meshes with every kind of contact (folds across an edge, faces meeting beside
// a shared corner, disjoint faces crossing, coplanar overlaps), long faces beside fine ones (the
// grid's coarsening and crowded cells), and on CGAL's data (label slow).
#include <gtest/gtest.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <sstream>

#include "mesh/read_mesh.h"
#include "mesh/self_intersections.h"
#include "mesh/shapes.h"
#include "mesh/validate_mesh.h"

namespace cdbench {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Pairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

// CGAL's answer, face indices as in `mesh` (polygon_soup_to_polygon_mesh adds the faces in order).
Pairs cgal_pairs(const TriangleMesh& mesh) {
  std::vector<K::Point_3> points;
  for (const Vec3& v : mesh.vertices) points.emplace_back(v.x(), v.y(), v.z());
  std::vector<std::array<std::size_t, 3>> polygons;
  for (const Face& f : mesh.faces) polygons.push_back({f[0], f[1], f[2]});
  CGAL::Surface_mesh<K::Point_3> sm;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, polygons, sm);
  EXPECT_EQ(sm.number_of_faces(), mesh.faces.size());
  std::vector<std::pair<CGAL::Surface_mesh<K::Point_3>::Face_index, CGAL::Surface_mesh<K::Point_3>::Face_index>> out;
  CGAL::Polygon_mesh_processing::self_intersections(sm, std::back_inserter(out));
  Pairs pairs;
  for (const auto& [a, b] : out)
    pairs.emplace_back(std::min<std::uint32_t>(a, b), std::max<std::uint32_t>(a, b));
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

bool has_degenerate_face(const TriangleMesh& m) {
  for (const Face& f : m.faces) {
    const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &c = m.vertices[f[2]];
    if (CGAL::collinear(K::Point_3(a.x(), a.y(), a.z()), K::Point_3(b.x(), b.y(), b.z()), K::Point_3(c.x(), c.y(), c.z())))
      return true;
  }
  return false;
}

// The vertices moved by up to `amount` in each coordinate, then (quantum > 0) rounded to multiples
// of it: rounding makes faces coplanar with their neighbours, so folds and coplanar overlaps occur.
TriangleMesh jiggled(TriangleMesh m, double amount, double quantum, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amount, amount);
  for (Vec3& v : m.vertices) {
    for (int k = 0; k < 3; ++k) {
      v[k] += u(rng);
      if (quantum > 0.0) v[k] = quantum * std::round(v[k] / quantum);
    }
  }
  return m;
}

void expect_same_as_cgal(const TriangleMesh& m, const std::string& what) {
  const Pairs ours = self_intersecting_faces(m);
  const Pairs theirs = cgal_pairs(m);
  EXPECT_EQ(ours, theirs) << what << ": " << ours.size() << " pairs, CGAL " << theirs.size();
}

TEST(SelfIntersections, NoneOnValidSolids) {
  EXPECT_TRUE(self_intersecting_faces(make_icosphere(1.0, 4)).empty());
  EXPECT_TRUE(self_intersecting_faces(make_torus(2.0, 0.5, 64, 32)).empty());
  EXPECT_TRUE(self_intersecting_faces(make_tube(0.98, 1.0, 20.0, 200)).empty());  // long thin faces
  EXPECT_TRUE(self_intersecting_faces(make_box(Vec3(0, 0, 0), Vec3(1, 1, 1))).empty());
}

TEST(SelfIntersections, EachKindOfContact) {
  TriangleMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0.5, 0.5, 0), Vec3(0.5, -1, 0), Vec3(0.2, 0.2, -1),
                Vec3(0.2, 0.2, 1), Vec3(0.3, 0.3, 0), Vec3(5, 5, 5), Vec3(6, 5, 5), Vec3(5, 6, 5)};
  m.faces = {{0, 1, 2},    // 0
             {0, 3, 1},    // 1: shares edge 0-1 with 0, folded onto it (coplanar, same side)
             {0, 1, 4},    // 2: shares edge 0-1 with 0, coplanar on the other side: touch only
             {0, 5, 6},    // 3: shares corner 0 with 0 and pierces it at (0.2, 0.2, 0)
             {2, 5, 7},    // 4: shares corner 2 with 0, its opposite edge touches 0 at (0.3, 0.3, 0)
             {8, 9, 10}};  // 5: far from the rest
  EXPECT_TRUE(faces_intersect(m, 0, 1));
  EXPECT_FALSE(faces_intersect(m, 0, 2));
  EXPECT_TRUE(faces_intersect(m, 0, 3));
  EXPECT_TRUE(faces_intersect(m, 0, 4));
  EXPECT_FALSE(faces_intersect(m, 0, 5));
  const Pairs pairs = self_intersecting_faces(m);
  for (const auto& [f, g] : pairs) EXPECT_LT(f, g);
  EXPECT_TRUE(std::is_sorted(pairs.begin(), pairs.end()));
  EXPECT_TRUE(std::find(pairs.begin(), pairs.end(), std::make_pair(0u, 1u)) != pairs.end());
  EXPECT_TRUE(std::find(pairs.begin(), pairs.end(), std::make_pair(0u, 2u)) == pairs.end());
  EXPECT_TRUE(std::find(pairs.begin(), pairs.end(), std::make_pair(0u, 3u)) != pairs.end());
  for (const auto& [f, g] : pairs) EXPECT_NE(g, 5u);
}

TEST(SelfIntersections, SameAsCgalOnJiggledSurfaces) {
  int cases = 0, with_pairs = 0;
  const TriangleMesh shapes[] = {make_icosphere(1.0, 3), make_torus(2.0, 0.5, 40, 20), make_tube(0.9, 1.0, 4.0, 48)};
  for (std::size_t s = 0; s < std::size(shapes); ++s)
    for (double amount : {0.0, 0.02, 0.1, 0.4})
      for (double quantum : {0.0, 0.1, 0.25})
        for (unsigned seed = 1; seed <= 4; ++seed) {
          const TriangleMesh m = jiggled(shapes[s], amount, quantum, seed + 17 * static_cast<unsigned>(s));
          if (has_degenerate_face(m)) continue;  // the precondition (validation rejects these first)
          ++cases;
          if (!cgal_pairs(m).empty()) ++with_pairs;
          std::ostringstream what;
          what << "shape " << s << " amount " << amount << " quantum " << quantum << " seed " << seed;
          expect_same_as_cgal(m, what.str());
        }
  std::printf("%d jiggled surfaces, %d with intersecting faces\n", cases, with_pairs);
  EXPECT_GE(cases, 60);
  EXPECT_GE(with_pairs, 25);
}

TEST(SelfIntersections, SameAsCgalWithLongFacesBesideFineOnes) {
  // A box of 12 faces crossed by a sphere of 20,480 faces: the box's faces span the grid (it is
  // coarsened) and its cells are crowded with the sphere's (swept along x).
  const TriangleMesh box = make_box(Vec3(-3, -3, -3), Vec3(3, 3, 0.95));
  for (const Vec3& c : {Vec3(0.3, -0.2, 0.0), Vec3(2.5, 2.9, 1.2)}) {
    const TriangleMesh m = merge_meshes(box, make_icosphere(1.0, 5, c));
    const Pairs pairs = self_intersecting_faces(m);
    EXPECT_FALSE(pairs.empty());
    expect_same_as_cgal(m, "box and sphere");
  }
}

TEST(SelfIntersections, SameForOneThreadAndAll) {
  const TriangleMesh m = jiggled(make_icosphere(1.0, 4), 0.05, 0.0, 3);
  const Pairs all = self_intersecting_faces(m);
  Pairs one;
  tbb::task_arena(1).execute([&] { one = self_intersecting_faces(m); });
  EXPECT_FALSE(all.empty());
  EXPECT_EQ(all, one);
}

// Every closed or open manifold mesh of CGAL's data up to 60,000 faces (label slow).
TEST(SelfIntersectionsSlow, SameAsCgalOnCgalData) {
  const std::filesystem::path dir = std::filesystem::path(CDBENCH_DATA_DIR) / "cgal" / "meshes";
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << "no CGAL data (scripts/fetch-cgal-data.sh)";
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  int compared = 0, with_pairs = 0;
  for (const auto& path : files) {
    ValidatedMesh v;
    try {
      ValidateOptions o;
      o.check_self_intersections = false;
      v = validate_mesh(read_polygon_soup(path.string()), o);
    } catch (const std::exception&) {
      continue;  // not a mesh this reader takes
    }
    if (v.mesh.faces.size() > 60000 || v.mesh.faces.empty() || v.report.has("degenerate-face") ||
        v.report.has("non-manifold-edge") || v.report.has("non-manifold-vertex") || v.report.has("non-orientable") ||
        has_degenerate_face(v.mesh))
      continue;
    ++compared;
    const Pairs ours = self_intersecting_faces(v.mesh);
    if (!ours.empty()) ++with_pairs;
    EXPECT_EQ(ours, cgal_pairs(v.mesh)) << path;
  }
  std::printf("%d meshes of CGAL's data compared, %d with intersecting faces\n", compared, with_pairs);
  EXPECT_GE(compared, 60);
  EXPECT_GE(with_pairs, 1);
}

}  // namespace
}  // namespace cdbench
