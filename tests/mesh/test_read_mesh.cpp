#include <gtest/gtest.h>

#include <cstring>
#include <sstream>

#include "mesh/read_mesh.h"
#include "mesh/shapes.h"
#include "mesh/validate_mesh.h"
#include "mesh/write_mesh.h"
#include "util/error.h"

namespace cdbench {
namespace {

const TriangleMesh kCube = make_box(Vec3(0, 0, 0), Vec3(1, 2, 3));

void expect_unit_cube_volume(const PolygonSoup& soup) {
  const ValidatedMesh v = validate_mesh(soup);
  ASSERT_TRUE(v.report.valid()) << (v.report.errors.empty() ? "" : v.report.errors[0].message);
  EXPECT_EQ(v.mesh.faces.size(), 12u);
  EXPECT_EQ(v.mesh.vertices.size(), 8u);
  EXPECT_LE(v.report.volume_lo, 6.0);
  EXPECT_GE(v.report.volume_hi, 6.0);
  EXPECT_EQ(v.report.genus, 0);
}

TEST(ReadMesh, OffRoundTripIsExact) {
  const TriangleMesh sphere = make_icosphere(1.3, 2);
  std::ostringstream os;
  write_off(sphere, os);
  const PolygonSoup soup = read_polygon_soup_from_bytes(os.str(), "sphere.off");
  ASSERT_EQ(soup.points.size(), sphere.vertices.size());
  for (std::size_t i = 0; i < soup.points.size(); ++i) EXPECT_EQ(soup.points[i], sphere.vertices[i]);
  ASSERT_EQ(soup.polygons.size(), sphere.faces.size());
}

TEST(ReadMesh, AsciiStl) {
  std::ostringstream os;
  os << "solid cube\n";
  for (const Face& f : kCube.faces) {
    os << " facet normal 0 0 0\n  outer loop\n";
    for (auto v : f) os << "   vertex " << kCube.vertices[v].x() << " " << kCube.vertices[v].y() << " " << kCube.vertices[v].z() << "\n";
    os << "  endloop\n endfacet\n";
  }
  os << "endsolid cube\n";
  expect_unit_cube_volume(read_polygon_soup_from_bytes(os.str(), "cube.stl"));
}

TEST(ReadMesh, BinaryStl) {
  std::string bytes(80, ' ');
  const std::uint32_t n = static_cast<std::uint32_t>(kCube.faces.size());
  bytes.append(reinterpret_cast<const char*>(&n), 4);
  for (const Face& f : kCube.faces) {
    float data[12] = {0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) data[3 + 3 * k + c] = static_cast<float>(kCube.vertices[f[k]][c]);
    bytes.append(reinterpret_cast<const char*>(data), sizeof data);
    bytes.append(2, '\0');
  }
  expect_unit_cube_volume(read_polygon_soup_from_bytes(bytes, "cube.STL"));
}

std::string ply_header(const std::string& format) {
  return "ply\nformat " + format +
         " 1.0\ncomment cube\nelement vertex 8\nproperty double x\nproperty double y\nproperty double z\n"
         "element face 12\nproperty list uchar int vertex_indices\nend_header\n";
}

TEST(ReadMesh, AsciiPly) {
  std::ostringstream os;
  os << ply_header("ascii");
  for (const Vec3& v : kCube.vertices) os << v.x() << " " << v.y() << " " << v.z() << "\n";
  for (const Face& f : kCube.faces) os << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
  expect_unit_cube_volume(read_polygon_soup_from_bytes(os.str(), "cube.ply"));
}

TEST(ReadMesh, BinaryLittleEndianPly) {
  std::string bytes = ply_header("binary_little_endian");
  for (const Vec3& v : kCube.vertices) bytes.append(reinterpret_cast<const char*>(v.data()), 24);
  for (const Face& f : kCube.faces) {
    bytes.push_back(3);
    for (auto id : f) {
      const std::int32_t i = static_cast<std::int32_t>(id);
      bytes.append(reinterpret_cast<const char*>(&i), 4);
    }
  }
  expect_unit_cube_volume(read_polygon_soup_from_bytes(bytes, "cube.ply"));
}

TEST(ReadMesh, ObjWithQuadsIsTriangulated) {
  // The box's six sides as quads (1-based indices, some with texture/normal references).
  std::ostringstream os;
  for (const Vec3& v : kCube.vertices) os << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
  os << "vn 0 0 1\n"
     << "f 1 3 4 2\nf 5 6 8 7\nf 1//1 2//1 6//1 5//1\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
  const PolygonSoup soup = read_polygon_soup_from_bytes(os.str(), "cube.obj");
  EXPECT_EQ(soup.polygons.size(), 6u);
  const ValidatedMesh v = validate_mesh(soup);
  ASSERT_TRUE(v.report.valid()) << v.report.errors[0].message;
  EXPECT_EQ(v.mesh.faces.size(), 12u);
  EXPECT_LE(v.report.volume_lo, 6.0);
  EXPECT_GE(v.report.volume_hi, 6.0);
}

TEST(ReadMesh, FormatFromExtension) {
  EXPECT_EQ(mesh_format_from_path("a/b.OFF"), MeshFormat::Off);
  EXPECT_EQ(mesh_format_from_path("x.Stl"), MeshFormat::Stl);
  EXPECT_THROW(mesh_format_from_path("dir.off/file"), InputError);
  EXPECT_THROW(mesh_format_from_path("mesh.vtk"), InputError);
}

TEST(ReadMesh, MissingFileNamesThePath) {
  try {
    read_polygon_soup("/nonexistent/mesh.off");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/mesh.off"), std::string::npos);
  }
}

}  // namespace
}  // namespace cdbench
