#include <gtest/gtest.h>

#include "mesh/shapes.h"
#include "mesh/validate_mesh.h"
#include "mesh/weld.h"
#include "util/error.h"

namespace cdbench {
namespace {

PolygonSoup soup_of(const TriangleMesh& m) {
  PolygonSoup s;
  s.points = m.vertices;
  for (const Face& f : m.faces) s.polygons.push_back({f[0], f[1], f[2]});
  return s;
}

// Every corner its own vertex, as STL and textured exports write them.
PolygonSoup split_corners(const TriangleMesh& m) {
  PolygonSoup s;
  for (const Face& f : m.faces) {
    s.polygons.push_back({s.points.size(), s.points.size() + 1, s.points.size() + 2});
    for (std::uint32_t v : f) s.points.push_back(m.vertices[v]);
  }
  return s;
}

TEST(Weld, AMeshWithoutDuplicatesIsUnchanged) {
  const TriangleMesh sphere = make_icosphere(1.0, 2);
  PolygonSoup s = soup_of(sphere);
  const WeldResult w = weld_vertices(s);
  EXPECT_EQ(w.merged(), 0u);
  EXPECT_EQ(s.points, sphere.vertices);
  ASSERT_EQ(s.polygons.size(), sphere.faces.size());
  for (std::size_t i = 0; i < s.polygons.size(); ++i)
    EXPECT_EQ(s.polygons[i], (std::vector<std::size_t>{sphere.faces[i][0], sphere.faces[i][1], sphere.faces[i][2]}));
}

TEST(Weld, SplitCornersBecomeTheOriginalMeshInFirstOccurrenceOrder) {
  const TriangleMesh sphere = make_icosphere(1.0, 2);
  PolygonSoup s = split_corners(sphere);
  const WeldResult w = weld_vertices(s);
  EXPECT_EQ(w.vertices_after, sphere.vertices.size());
  EXPECT_EQ(w.merged(), 3 * sphere.faces.size() - sphere.vertices.size());
  EXPECT_EQ(w.max_displacement, 0.0);
  // Corners reference points with the original coordinates.
  for (std::size_t f = 0; f < s.polygons.size(); ++f)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(s.points[s.polygons[f][k]], sphere.vertices[sphere.faces[f][k]]);
  const ValidatedMesh v = validate_mesh(split_corners(sphere));
  EXPECT_TRUE(v.report.valid());
  ASSERT_FALSE(v.report.notices.empty());
  EXPECT_NE(v.report.notices[0].find("welded " + std::to_string(w.merged()) + " vertices"), std::string::npos);
}

TEST(Weld, SignedZerosAreOnePointAndNearbyPointsAreNotMergedExactly) {
  PolygonSoup s;
  s.points = {Vec3(0, 0, 0), Vec3(-0.0, 0, 0), Vec3(1e-300, 0, 0), Vec3(std::nextafter(1.0, 2.0), 0, 0), Vec3(1, 0, 0)};
  s.polygons = {{0, 2, 3}, {1, 4, 3}};
  const WeldResult w = weld_vertices(s);
  EXPECT_EQ(w.merged(), 1u);
  EXPECT_EQ(s.points.size(), 4u);
  EXPECT_EQ(s.polygons[1][0], 0u);
}

TEST(Weld, ToleranceMergesClustersDropsCollapsedFacesAndReportsTheMove) {
  PolygonSoup s;
  s.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1e-7, 0, 0), Vec3(0, 0, 1)};
  s.polygons = {{0, 1, 2}, {3, 2, 4}, {0, 3, 4}};  // the last collapses to a segment
  const WeldResult w = weld_vertices(s, 1e-6);
  EXPECT_EQ(w.merged(), 1u);
  EXPECT_EQ(w.polygons_dropped, 1u);
  EXPECT_DOUBLE_EQ(w.max_displacement, 1e-7);
  ASSERT_EQ(s.polygons.size(), 2u);
  EXPECT_EQ(s.polygons[1], (std::vector<std::size_t>{0, 2, 3}));
  EXPECT_EQ(s.points[0], Vec3(0, 0, 0));  // the cluster moves onto its first vertex
}

TEST(Weld, BadTolerancesAreInputErrors) {
  PolygonSoup s = soup_of(make_icosphere(1.0, 0));
  EXPECT_THROW(weld_vertices(s, -1.0), InputError);
  EXPECT_THROW(weld_vertices(s, std::nan("")), InputError);
  s.points[0] = Vec3(1e300, 0, 0);
  EXPECT_THROW(weld_vertices(s, 1e-300), InputError);
}

}  // namespace
}  // namespace cdbench
