#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
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

// What reading `text` as file `name` throws ("no error" if nothing).
std::string reading_error(const std::string& text, const std::string& name) {
  try {
    read_polygon_soup_from_bytes(text, name);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
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

TEST(ReadMesh, OffVariantsCommentsAndLayout) {
  // COFF colours, comments, blank lines, counts on their own line, CRLF, a UTF-8 byte-order mark,
  // a face with colours after its indices, a quad, numbers with '+' and exponents.
  const std::string text =
      "\xEF\xBB\xBF"
      "COFF # coloured\r\n"
      "\n"
      "# counts next\n"
      "5 2 0\r\n"
      "0 0 0 255 0 0 255\n"
      "+1e0 0 0  0 255 0 255\n"
      "1 1 0 0 0 255 255\r\n"
      "0 1 0 1 1 1 1\n"
      "0.5 0.5 -2.5e-1 # apex\n"
      "4 0 1 2 3 0.5 0.5 0.5\n"
      "3\t0 4 1\n";
  const PolygonSoup soup = read_polygon_soup_from_bytes(text, "variants.off");
  ASSERT_EQ(soup.points.size(), 5u);
  EXPECT_EQ(soup.points[1], Vec3(1, 0, 0));
  EXPECT_EQ(soup.points[4], Vec3(0.5, 0.5, -0.25));
  ASSERT_EQ(soup.polygons.size(), 2u);
  EXPECT_EQ(soup.polygons[0], (std::vector<std::size_t>{0, 1, 2, 3}));
  EXPECT_EQ(soup.polygons[1], (std::vector<std::size_t>{0, 4, 1}));
  // Counts on the header line; "ST" prefixes are 3-D OFF too.
  const PolygonSoup st = read_polygon_soup_from_bytes("STOFF 3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n", "st.off");
  EXPECT_EQ(st.points.size(), 3u);
  EXPECT_EQ(st.polygons.size(), 1u);
}

TEST(ReadMesh, OffErrorsNameTheLine) {
  const auto message = [](const std::string& text) { return reading_error(text, "m.off"); };
  EXPECT_NE(message("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 x\n3 0 1 2\n").find("line 5: vertex 2 needs three finite"),
            std::string::npos);
  EXPECT_NE(message("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n").find("line 6: face 0 refers to vertex '3'"),
            std::string::npos);
  EXPECT_NE(message("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n").find("announces '4' corners"), std::string::npos);
  EXPECT_NE(message("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").find("the file ends after 1"), std::string::npos);
  EXPECT_NE(message("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 1e999\n3 0 1 2\n").find("vertex 2 needs three finite"),
            std::string::npos);
  EXPECT_NE(message("OFF BINARY\n").find("binary OFF is not supported"), std::string::npos);
  EXPECT_NE(message("4OFF\n").find("non-3D OFF"), std::string::npos);
  EXPECT_NE(message("OFF\n-3 1 0\n").find("non-negative integers"), std::string::npos);
  EXPECT_NE(message("OFF\n99999999 1 0\n0 0 0\n").find("more than a file of"), std::string::npos);
}

// Files above 256 KB are parsed in chunks of lines on all threads: the first bad record is still
// the one reported, with its line, whichever chunk holds it and whatever later chunks hold.
TEST(ReadMesh, OffErrorsNameTheLineInALargeFile) {
  const int nv = 60000, nf = 20000;
  std::vector<std::string> lines{"OFF", "# a large file", std::to_string(nv) + " " + std::to_string(nf) + " 0"};
  for (int v = 0; v < nv; ++v) {
    lines.push_back(std::to_string(v) + ".25 " + std::to_string(v % 7) + " -1e-3");
    if (v % 9000 == 0) lines.push_back("   # a comment line, then a blank one");
    if (v % 9000 == 0) lines.push_back("");
  }
  for (int f = 0; f < nf; ++f) lines.push_back("3 " + std::to_string(f) + " " + std::to_string(f + 1) + " " + std::to_string(f + 2));
  const auto text_of = [](const std::vector<std::string>& l) {
    std::string t;
    for (const std::string& s : l) t += s + "\n";
    return t;
  };
  const auto message = [](const std::string& text) { return reading_error(text, "big.off"); };
  const std::string good = text_of(lines);
  ASSERT_GT(good.size(), 4u * 262144u);  // several chunks
  const PolygonSoup soup = read_polygon_soup_from_bytes(good, "big.off");
  ASSERT_EQ(soup.points.size(), std::size_t(nv));
  EXPECT_EQ(soup.points[54321], Vec3(54321.25, 54321 % 7, -1e-3));
  ASSERT_EQ(soup.polygons.size(), std::size_t(nf));
  EXPECT_EQ(soup.polygons[nf - 1], (std::vector<std::size_t>{std::size_t(nf) - 1, std::size_t(nf), std::size_t(nf) + 1}));
  // The line of face 15000 and of vertex 50000 (counting from 1, as the message does).
  const auto line_of = [&](const std::string& prefix) {
    return std::find_if(lines.begin(), lines.end(), [&](const std::string& l) { return l.rfind(prefix, 0) == 0; }) -
           lines.begin() + 1;
  };
  std::vector<std::string> bad = lines;
  const auto face_line = line_of("3 15000 ");
  bad[face_line - 1] = "3 15000 15001 70000";
  EXPECT_NE(message(text_of(bad)).find("line " + std::to_string(face_line) + ": face 15000 refers to vertex '70000'"),
            std::string::npos)
      << message(text_of(bad));
  const auto vertex_line = line_of("50000.25 ");
  bad[vertex_line - 1] = "50000.25 x 0";  // an earlier record: reported instead of the face
  EXPECT_NE(message(text_of(bad)).find("line " + std::to_string(vertex_line) + ": vertex 50000 needs three finite"),
            std::string::npos)
      << message(text_of(bad));
  std::vector<std::string> short_file(lines.begin(), lines.end() - 5);
  EXPECT_NE(message(text_of(short_file)).find("announces 20000 faces, the file ends after 19995"), std::string::npos)
      << message(text_of(short_file));
}

// A NUL byte in a large file (searched in 4 MB chunks on all threads) is reported at its first
// position, also when a later chunk holds another, and a file without one is read.
TEST(ReadMesh, FirstNulByteOfALargeFileIsNamed) {
  std::string text = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  text.resize(40u << 20, ' ');  // trailing blanks: still a good file
  EXPECT_EQ(read_polygon_soup_from_bytes(text, "big.off").polygons.size(), 1u);
  for (std::size_t first : {std::size_t(9) << 20, (std::size_t(13) << 20) + 17, (std::size_t(40) << 20) - 1}) {
    std::string bad = text;
    bad[first] = '\0';
    if (first + (5u << 20) < bad.size()) bad[first + (5u << 20)] = '\0';  // another, chunks later
    bad[bad.size() - 1] = '\0';
    const std::string m = reading_error(bad, "big.off");
    EXPECT_NE(m.find("byte " + std::to_string(first) + " is a NUL byte"), std::string::npos) << m;
  }
}

// Our OFF reader against an independent parse (a stream read token by token, the way CGAL's
// reader reads) on every OFF file of CGAL's data: the same coordinates bit for bit, the same faces.
TEST(ReadMesh, OffReaderAgreesWithAStreamParseOnCgalData) {
  const std::string dir = std::string(CDBENCH_DATA_DIR) + "/cgal/meshes";
  if (!std::filesystem::is_directory(dir)) GTEST_SKIP() << "CGAL data not extracted: " << dir;
  std::vector<std::string> paths;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".off" && e.file_size() < 4'000'000) paths.push_back(e.path().string());
  std::sort(paths.begin(), paths.end());
  ASSERT_GE(paths.size(), 20u);
  std::size_t compared = 0;
  for (const std::string& path : paths) {
    PolygonSoup ours;
    try {
      ours = read_polygon_soup(path);
    } catch (const InputError&) {
      continue;  // files our reader refuses are covered by the bad-input table
    }
    // The independent parse: whole lines without comments, then tokens from a stream.
    std::ifstream in(path);
    std::string line, body;
    while (std::getline(in, line)) body += line.substr(0, line.find('#')) + "\n";
    std::istringstream is(body);
    std::string key;
    is >> key;
    if (key.rfind("\xEF\xBB\xBF", 0) == 0) key = key.substr(3);
    std::size_t nv = 0, nf = 0, ne = 0;
    ASSERT_TRUE(static_cast<bool>(is >> nv >> nf >> ne)) << path;
    ASSERT_EQ(ours.points.size(), nv) << path;
    ASSERT_EQ(ours.polygons.size(), nf) << path;
    std::getline(is, line);
    for (std::size_t v = 0; v < nv; ++v) {
      do std::getline(is, line);
      while (line.find_first_not_of(" \t\r") == std::string::npos);
      std::istringstream ls(line);
      double x, y, z;
      ls >> x >> y >> z;
      ASSERT_EQ(ours.points[v], Vec3(x, y, z)) << path << " vertex " << v;
    }
    for (std::size_t f = 0; f < nf; ++f) {
      do std::getline(is, line);
      while (line.find_first_not_of(" \t\r") == std::string::npos);
      std::istringstream ls(line);
      std::size_t k = 0;
      ls >> k;
      std::vector<std::size_t> poly(k);
      for (std::size_t& id : poly) ls >> id;
      ASSERT_EQ(ours.polygons[f], poly) << path << " face " << f;
    }
    ++compared;
  }
  EXPECT_GE(compared, 20u);
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
