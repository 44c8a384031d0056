#include "mesh/repair.h"

#include <algorithm>
#include <map>
#include <utility>

#include "mesh/weld.h"
#include "util/timer.h"
#include "util/union_find.h"

namespace cdbench {
namespace {

// The polygons of each group as a soup of their own (points renumbered in first-use order).
std::vector<PolygonSoup> split_by(const PolygonSoup& soup, UnionFind& faces) {
  std::map<std::size_t, std::size_t> group_of_root;
  std::vector<PolygonSoup> groups;
  std::vector<std::map<std::size_t, std::size_t>> index;
  for (std::size_t f = 0; f < soup.polygons.size(); ++f) {
    const auto [it, fresh] = group_of_root.emplace(faces.find(f), groups.size());
    if (fresh) {
      groups.emplace_back();
      index.emplace_back();
    }
    PolygonSoup& g = groups[it->second];
    std::vector<std::size_t> poly;
    for (std::size_t v : soup.polygons[f]) {
      const auto [jt, added] = index[it->second].emplace(v, g.points.size());
      if (added) g.points.push_back(soup.points[v]);
      poly.push_back(jt->second);
    }
    g.polygons.push_back(std::move(poly));
  }
  return groups;
}

// Faces sharing a vertex index are one part.
std::vector<PolygonSoup> parts_by_indices(const PolygonSoup& soup) {
  UnionFind vertices(soup.points.size()), faces(soup.polygons.size());
  std::vector<std::size_t> face_of_vertex(soup.points.size(), SIZE_MAX);
  for (std::size_t f = 0; f < soup.polygons.size(); ++f)
    for (std::size_t v : soup.polygons[f]) {
      if (face_of_vertex[v] == SIZE_MAX)
        face_of_vertex[v] = f;
      else
        faces.unite(face_of_vertex[v], f);
    }
  return split_by(soup, faces);
}

// Faces joined across edges that exactly two faces use.
std::vector<PolygonSoup> parts_by_manifold_edges(const PolygonSoup& soup) {
  std::map<std::pair<std::size_t, std::size_t>, std::vector<std::size_t>> edges;
  for (std::size_t f = 0; f < soup.polygons.size(); ++f) {
    const auto& p = soup.polygons[f];
    for (std::size_t k = 0; k < p.size(); ++k) {
      const std::size_t a = p[k], b = p[(k + 1) % p.size()];
      edges[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
  }
  UnionFind faces(soup.polygons.size());
  for (const auto& [e, fs] : edges)
    if (fs.size() == 2) faces.unite(fs[0], fs[1]);
  return split_by(soup, faces);
}

// Validated closed parts, or a reason why not.
bool closed_parts(const std::vector<PolygonSoup>& soups, std::vector<TriangleMesh>& parts, std::string& reason) {
  parts.clear();
  if (soups.size() < 2) {
    reason = "the input is one connected piece";
    return false;
  }
  for (std::size_t i = 0; i < soups.size(); ++i) {
    const ValidatedMesh v = validate_mesh(soups[i]);
    if (!v.report.valid()) {
      reason = "part " + std::to_string(i) + " of " + std::to_string(soups.size()) + " is not a closed solid: " +
               v.report.errors.front().message;
      return false;
    }
    parts.push_back(v.mesh);
  }
  return true;
}

}  // namespace

const char* to_string(RepairMethod m) {
  switch (m) {
    case RepairMethod::Unchanged: return "unchanged";
    case RepairMethod::ExactUnion: return "exact-union";
    case RepairMethod::AlphaWrap: return "alpha-wrap";
  }
  return "?";
}

TriangleMesh fan_triangulation(const PolygonSoup& soup) {
  TriangleMesh m;
  m.vertices = soup.points;
  for (const auto& p : soup.polygons)
    for (std::size_t k = 1; k + 1 < p.size(); ++k)
      m.faces.push_back({static_cast<std::uint32_t>(p[0]), static_cast<std::uint32_t>(p[k]),
                         static_cast<std::uint32_t>(p[k + 1])});
  return m;
}

RepairResult repair_mesh(const PolygonSoup& input, const RepairOptions& options) {
  Timer timer;
  RepairResult r;
  ValidateOptions vo;
  vo.weld_tolerance = options.weld_tolerance;
  r.input_report = validate_mesh(input, vo).report;
  if (r.input_report.has("coordinate-range")) {  // nothing can be computed at that scale
    r.method = RepairMethod::Unchanged;
    r.result.report = r.input_report;
    r.exact_note = "the coordinates are outside the supported range";
    r.seconds = timer.seconds();
    return r;
  }
  PolygonSoup soup = input;
  weld_vertices(soup, options.weld_tolerance);
  if (r.input_report.valid()) {
    r.method = RepairMethod::Unchanged;
    r.result = validate_mesh(soup);
    r.seconds = timer.seconds();
    return r;
  }
  // Parts by the file's own indices (each welded on its own by validation), else by manifold edges.
  std::vector<TriangleMesh> parts;
  std::string why_indices, why_edges;
  PolygonSoup unwelded = input;
  if (options.weld_tolerance > 0.0) unwelded = soup;
  bool ok = closed_parts(parts_by_indices(unwelded), parts, why_indices);
  if (!ok) ok = closed_parts(parts_by_manifold_edges(soup), parts, why_edges);
  if (ok) {
    TriangleMesh united;
    if (exact_union(parts, united, r.exact_note)) {
      r.result = validate_mesh(united);
      if (r.result.report.valid()) {
        r.method = RepairMethod::ExactUnion;
        r.parts = parts.size();
        r.seconds = timer.seconds();
        return r;
      }
      r.exact_note = "the exact union of " + std::to_string(parts.size()) +
                     " parts is not valid once rounded to doubles: " + r.result.report.errors.front().message;
    }
  } else {
    r.exact_note = "not a union of closed parts (split by vertex indices: " + why_indices +
                   "; split by manifold edges: " + why_edges + ")";
  }
  if (!options.allow_wrap) {
    r.method = RepairMethod::Unchanged;
    r.result = validate_mesh(soup);
    r.seconds = timer.seconds();
    return r;
  }
  const AlphaWrapResult w = alpha_wrap(soup, options.wrap);
  r.method = RepairMethod::AlphaWrap;
  r.alpha = w.alpha;
  r.offset = w.offset;
  r.result = validate_mesh(w.mesh);
  r.seconds = timer.seconds();
  return r;
}

}  // namespace cdbench
