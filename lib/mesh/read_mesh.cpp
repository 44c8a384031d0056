// CGAL's readers live in this translation unit only.
#include "mesh/read_mesh.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/OBJ.h>
#include <CGAL/IO/OFF.h>
#include <CGAL/IO/PLY.h>
#include <CGAL/IO/STL.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "mesh/file_structure.h"
#include "util/error.h"

namespace cdbench {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string describe_point(const Vec3& p) {
  std::ostringstream os;
  os.precision(17);
  os << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return os.str();
}

}  // namespace

MeshFormat mesh_format_from_path(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of('/');
  const std::string ext = (dot == std::string::npos || (slash != std::string::npos && dot < slash))
                              ? std::string()
                              : lower(path.substr(dot + 1));
  if (ext == "off") return MeshFormat::Off;
  if (ext == "obj") return MeshFormat::Obj;
  if (ext == "ply") return MeshFormat::Ply;
  if (ext == "stl") return MeshFormat::Stl;
  throw InputError(path + ": unknown mesh format '" + (ext.empty() ? std::string("(no extension)") : "." + ext) +
                   "'; supported: .off, .obj, .ply, .stl");
}

PolygonSoup read_polygon_soup_from_bytes(const std::string& bytes, const std::string& name) {
  const MeshFormat format = mesh_format_from_path(name);
  if (bytes.empty()) throw InputError(name + ": the file is empty");
  check_mesh_file_structure(bytes, format, name);

  std::vector<Kernel::Point_3> points;
  std::vector<std::vector<std::size_t>> polygons;
  bool ok = false;
  try {
    std::istringstream is(bytes, std::ios::in | std::ios::binary);
    // CGAL's readers print diagnostics on std::cerr when verbose; keep them quiet and report ourselves.
    switch (format) {
      case MeshFormat::Off: ok = CGAL::IO::read_OFF(is, points, polygons, CGAL::parameters::verbose(false)); break;
      case MeshFormat::Obj: ok = CGAL::IO::read_OBJ(is, points, polygons, CGAL::parameters::verbose(false)); break;
      case MeshFormat::Ply: ok = CGAL::IO::read_PLY(is, points, polygons, CGAL::parameters::verbose(false)); break;
      case MeshFormat::Stl: ok = CGAL::IO::read_STL(is, points, polygons, CGAL::parameters::verbose(false)); break;
    }
  } catch (const std::bad_alloc&) {
    throw InputError(name + ": out of memory while parsing (the file announces more data than fits)");
  } catch (const std::exception& e) {
    throw InputError(name + ": cannot parse: " + e.what());
  }
  // Diagnose what was parsed even when CGAL gave up: its OBJ reader, for one, rejects an index out
  // of range without saying so, and our message names the face.
  PolygonSoup soup;
  soup.points.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 p(points[i].x(), points[i].y(), points[i].z());
    if (!p.allFinite())
      throw InputError(name + ": vertex " + std::to_string(i) + " has a non-finite coordinate " + describe_point(p));
    soup.points.push_back(p);
  }
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    if (polygons[f].size() < 3)
      throw InputError(name + ": face " + std::to_string(f) + " has " + std::to_string(polygons[f].size()) +
                       " corners; a face needs at least 3");
    for (std::size_t id : polygons[f])
      if (id >= soup.points.size())
        throw InputError(name + ": face " + std::to_string(f) + " refers to vertex " + std::to_string(id) +
                         " (counting from 0), but the file has only " + std::to_string(soup.points.size()) +
                         " vertices");
  }
  if (!ok) {
    if (points.empty() && polygons.empty())
      throw InputError(name + ": cannot parse as " + lower(name.substr(name.find_last_of('.') + 1)) +
                       " (malformed content or no faces)");
    throw InputError(name + ": cannot parse: malformed content after " + std::to_string(points.size()) +
                     " vertices and " + std::to_string(polygons.size()) + " faces");
  }
  if (soup.points.empty()) throw InputError(name + ": empty mesh (no vertices)");
  if (polygons.empty()) throw InputError(name + ": empty mesh (" + std::to_string(points.size()) + " vertices, no faces)");
  soup.polygons = std::move(polygons);
  return soup;
}

PolygonSoup read_polygon_soup(const std::string& path) {
  mesh_format_from_path(path);  // an unknown format is reported before the file is touched
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path + ": no such file");
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the file (missing or unreadable)");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw InputError(path + ": read error");
  return read_polygon_soup_from_bytes(buffer.str(), path);
}

}  // namespace cdbench
