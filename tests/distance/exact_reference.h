#pragma once
// Independent references for the distance tests: exact rational distances (CGAL Epeck) and CGAL's
// own inside test (Side_of_triangle_mesh), neither of which shares code with lib/distance.
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <memory>

#include "core/interval.h"
#include "core/triangle_mesh.h"

namespace cdbench::testing {

using Epeck = CGAL::Exact_predicates_exact_constructions_kernel;
using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;

inline Epeck::Point_3 exact_point(const Vec3& v) { return Epeck::Point_3(v.x(), v.y(), v.z()); }

// Exact squared distance from p to triangle abc.
inline Epeck::FT exact_squared_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return CGAL::squared_distance(exact_point(p), Epeck::Triangle_3(exact_point(a), exact_point(b), exact_point(c)));
}

// The squared distance from p to triangle abc in doubles (CGAL's Epick): the filters below.
inline double approx_squared_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const auto P = [](const Vec3& v) { return Epick::Point_3(v.x(), v.y(), v.z()); };
  return CGAL::squared_distance(P(p), Epick::Triangle_3(P(a), P(b), P(c)));
}

// Exact squared distance from p to the mesh: candidates filtered in doubles with a wide margin
// (1e-6 relative), the minimum taken exactly among them.
inline Epeck::FT exact_squared_distance(const Vec3& p, const TriangleMesh& m) {
  std::vector<double> approx(m.faces.size());
  double best = HUGE_VAL;
  for (std::size_t i = 0; i < m.faces.size(); ++i) {
    const auto& f = m.faces[i];
    approx[i] = approx_squared_distance(p, m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]]);
    best = std::min(best, approx[i]);
  }
  bool first = true;
  Epeck::FT result = 0;
  for (std::size_t i = 0; i < m.faces.size(); ++i) {
    if (approx[i] > best * (1 + 1e-6) + 1e-300) continue;
    const auto& f = m.faces[i];
    const Epeck::FT d = exact_squared_distance(p, m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]]);
    if (first || d < result) result = d;
    first = false;
  }
  return result;
}

// Whether the exact distance from p to triangle abc is at most r. Decided in doubles where their
// squared distance is far from r^2 (a margin of 1e-6 relative plus 1e-12 (1 + |p|^2 + |a|^2),
// far above their rounding), exactly otherwise: exhaustive loops over a mesh stay fast (the
// sanitizer build runs them too).
inline bool exact_within(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double r) {
  const double approx = approx_squared_distance(p, a, b, c);
  const double r2 = r * r;
  const double margin = 1e-6 * (approx + r2) + 1e-12 * (1.0 + p.squaredNorm() + a.squaredNorm());
  if (approx < r2 - margin) return true;
  if (approx > r2 + margin) return false;
  return exact_squared_distance(p, a, b, c) <= Epeck::FT(r) * Epeck::FT(r);
}

// Whether the interval of a distance contains sqrt(exact_sq), decided exactly:
// lo <= sqrt(e) <= hi  <=>  (lo <= 0 or lo^2 <= e) and hi >= 0 and e <= hi^2.
inline bool contains_sqrt(const Interval& i, const Epeck::FT& exact_sq) {
  const Epeck::FT lo(i.lo), hi(i.hi);
  return (i.lo <= 0 || lo * lo <= exact_sq) && i.hi >= 0 && exact_sq <= hi * hi;
}

// CGAL's own inside test: -1 inside, 0 on the surface, +1 outside.
class CgalSide {
 public:
  explicit CgalSide(const TriangleMesh& m) {
    for (const Vec3& v : m.vertices) sm_.add_vertex(Epick::Point_3(v.x(), v.y(), v.z()));
    for (const Face& f : m.faces)
      sm_.add_face(Mesh::Vertex_index(f[0]), Mesh::Vertex_index(f[1]), Mesh::Vertex_index(f[2]));
    side_ = std::make_unique<CGAL::Side_of_triangle_mesh<Mesh, Epick>>(sm_);
  }
  int operator()(const Vec3& p) const {
    const auto s = (*side_)(Epick::Point_3(p.x(), p.y(), p.z()));
    return s == CGAL::ON_BOUNDED_SIDE ? -1 : s == CGAL::ON_BOUNDARY ? 0 : 1;
  }

 private:
  using Mesh = CGAL::Surface_mesh<Epick::Point_3>;
  Mesh sm_;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<Mesh, Epick>> side_;
};

}  // namespace cdbench::testing
