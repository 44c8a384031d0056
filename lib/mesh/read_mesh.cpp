// CGAL's readers live in this translation unit only.
#include "mesh/read_mesh.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/PLY.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>

#include "mesh/file_structure.h"
#include "mesh/text_readers.h"
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

namespace {

// PLY through CGAL, after the structural pre-check.
PolygonSoup read_ply_with_cgal(std::string_view view, const std::string& name) {
  const std::string bytes(view);  // CGAL reads from a stream
  check_mesh_file_structure(bytes, MeshFormat::Ply, name);
  std::vector<Kernel::Point_3> points;
  std::vector<std::vector<std::size_t>> polygons;
  bool ok = false;
  try {
    std::istringstream is(bytes, std::ios::in | std::ios::binary);
    // CGAL's readers print diagnostics on std::cerr when verbose; keep them quiet and report ourselves.
    ok = CGAL::IO::read_PLY(is, points, polygons, CGAL::parameters::verbose(false));
  } catch (const std::bad_alloc&) {
    throw InputError(name + ": out of memory while parsing (the file announces more data than fits)");
  } catch (const std::exception& e) {
    throw InputError(name + ": cannot parse: " + e.what());
  }
  if (!ok && points.empty() && polygons.empty())
    throw InputError(name + ": cannot parse as " + lower(name.substr(name.find_last_of('.') + 1)) +
                     " (malformed content or no faces)");
  if (!ok)
    throw InputError(name + ": cannot parse: malformed content after " + std::to_string(points.size()) +
                     " vertices and " + std::to_string(polygons.size()) + " faces");
  PolygonSoup soup;
  soup.points.reserve(points.size());
  for (const auto& p : points) soup.points.emplace_back(p.x(), p.y(), p.z());
  soup.polygons = std::move(polygons);
  return soup;
}

}  // namespace

PolygonSoup read_polygon_soup_from_bytes(std::string_view bytes, const std::string& name) {
  const MeshFormat format = mesh_format_from_path(name);
  if (bytes.empty()) throw InputError(name + ": the file is empty");
  PolygonSoup soup;
  switch (format) {
    case MeshFormat::Obj: soup = read_obj(bytes, name); break;
    case MeshFormat::Stl: soup = read_stl(bytes, name); break;
    case MeshFormat::Off: soup = read_off(bytes, name); break;
    case MeshFormat::Ply: {
      // The header is text, the body may be binary: only the header's encoding is checked.
      const std::size_t header = std::min(bytes.find("end_header"), bytes.size());
      std::size_t bom = 0;
      const bool utf16_pattern = bytes.size() >= 2 && (bytes[0] == '\0' || bytes[1] == '\0');
      const unsigned char first = static_cast<unsigned char>(bytes[0]);
      if (bytes.compare(0, 3, "ply") != 0 && (utf16_pattern || first == 0xEF || first == 0xFE || first == 0xFF))
        bom = check_text_encoding(bytes.substr(0, std::min<std::size_t>(header, 4096)), name);
      soup = read_ply_with_cgal(bom ? bytes.substr(bom) : bytes, name);
      break;
    }
  }
  // Diagnose what was parsed, whatever the reader: the message names the vertex or face.
  for (std::size_t i = 0; i < soup.points.size(); ++i)
    if (!soup.points[i].allFinite())
      throw InputError(name + ": vertex " + std::to_string(i) + " has a non-finite coordinate " +
                       describe_point(soup.points[i]));
  for (std::size_t f = 0; f < soup.polygons.size(); ++f) {
    if (soup.polygons[f].size() < 3)
      throw InputError(name + ": face " + std::to_string(f) + " has " + std::to_string(soup.polygons[f].size()) +
                       " corners; a face needs at least 3");
    for (std::size_t id : soup.polygons[f])
      if (id >= soup.points.size())
        throw InputError(name + ": face " + std::to_string(f) + " refers to vertex " + std::to_string(id) +
                         " (counting from 0), but the file has only " + std::to_string(soup.points.size()) +
                         " vertices");
  }
  if (soup.points.empty()) throw InputError(name + ": empty mesh (no vertices)");
  if (soup.polygons.empty())
    throw InputError(name + ": empty mesh (" + std::to_string(soup.points.size()) + " vertices, no faces)");
  return soup;
}

PolygonSoup read_polygon_soup(const std::string& path) {
  mesh_format_from_path(path);  // an unknown format is reported before the file is touched
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path + ": no such file");
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": not a regular file");
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw InputError(path + ": cannot open the file (missing or unreadable)");
  struct stat st {};
  if (::fstat(fd, &st) != 0 || st.st_size < 0) {
    ::close(fd);
    throw InputError(path + ": cannot determine the file's size");
  }
  // Read whole into an uninitialised buffer, in chunks on all threads: the copies and the pages'
  // first touch (a 42 MB file: 0.18 s on one thread, half of it clearing a string first) are shared.
  const std::size_t size = static_cast<std::size_t>(st.st_size);
  std::unique_ptr<char[]> buffer(new char[std::max<std::size_t>(size, 1)]);
  constexpr std::size_t kChunk = std::size_t(4) << 20;
  std::atomic<bool> short_read{false};
  tbb::parallel_for(std::size_t{0}, (size + kChunk - 1) / kChunk, [&](std::size_t c) {
    std::size_t at = c * kChunk;
    const std::size_t end = std::min(size, at + kChunk);
    while (at < end && !short_read.load(std::memory_order_relaxed)) {
      const ssize_t got = ::pread(fd, buffer.get() + at, end - at, static_cast<off_t>(at));
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) short_read = true;  // an error, or the file shrank
      else at += static_cast<std::size_t>(got);
    }
  });
  char extra;
  const bool grew = !short_read && ::pread(fd, &extra, 1, static_cast<off_t>(size)) > 0;
  ::close(fd);
  if (short_read || grew)
    throw InputError(path + ": read error (the file changed or could not be read whole)");
  const std::string_view bytes(buffer.get(), size);
  return read_polygon_soup_from_bytes(bytes, path);
}

TriangleMesh read_triangle_mesh(const std::string& path) {
  const PolygonSoup soup = read_polygon_soup(path);
  TriangleMesh m;
  m.vertices = soup.points;
  m.faces.reserve(soup.polygons.size());
  for (const auto& p : soup.polygons) {
    if (p.size() != 3) throw InputError(path + ": a face is not a triangle");
    m.faces.push_back({static_cast<std::uint32_t>(p[0]), static_cast<std::uint32_t>(p[1]), static_cast<std::uint32_t>(p[2])});
  }
  return m;
}

}  // namespace cdbench
