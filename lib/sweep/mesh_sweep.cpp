#include "sweep/mesh_sweep.h"

#include <CGAL/Interval_nt.h>

#include <limits>
#include <tuple>

namespace cdbench {
namespace {

using I = CGAL::Interval_nt<false>;

// Keeps the earliest contact; among equal times, the smallest (fixed, moving) face pair, so that
// the reported pair does not depend on the visiting order.
struct Best {
  const SweepMesh& fixed;
  const SweepMesh& moving;
  const Vec3& v;
  MeshContact result;
  LineContact best_lc;

  void offer(std::uint32_t f, std::uint32_t m) {
    ++result.triangle_sweeps;
    const Triangle A = fixed.triangle(f), B = moving.triangle(m);
    const LineContact lc = line_contact(A, B, v);
    if (!lc.hit) return;
    result.exact_fallbacks += lc.exact_path;
    if (result.hit) {
      const int c = compare_entry_times(lc, A, B, v, best_lc, fixed.triangle(result.fixed_face),
                                        moving.triangle(result.moving_face), v);
      if (c > 0 || (c == 0 && std::tie(f, m) > std::tie(result.fixed_face, result.moving_face))) return;
    }
    result.hit = true;
    result.t = lc.t_in;
    result.fixed_face = f;
    result.moving_face = m;
    result.candidate = lc.in;
    best_lc = lc;
  }
};

// Lower bound of the first time the moving sphere (centre + t v) meets the fixed one; +inf if never.
// Must run under upward rounding, as CGAL's intervals require.
double entry_lower_bound(const Sphere& f, const Sphere& m, const I& vx, const I& vy, const I& vz, const I& vv) {
  const I wx = I(m.center.x()) - f.center.x(), wy = I(m.center.y()) - f.center.y(), wz = I(m.center.z()) - f.center.z();
  const I R = I(f.radius) + m.radius;
  const I wv = wx * vx + wy * vy + wz * vz;
  const I ww = wx * wx + wy * wy + wz * wz;
  const I disc = wv * wv - vv * (ww - R * R);
  if (disc.sup() < 0.0) return std::numeric_limits<double>::infinity();
  const I root = CGAL::sqrt(I(std::max(0.0, disc.inf()), disc.sup()));
  return ((-wv - root) / vv).inf();
}

struct SweepPolicy {
  Best& best;
  I vx, vy, vz, vv;

  SweepPolicy(Best& b, const Vec3& v) : best(b), vx(v.x()), vy(v.y()), vz(v.z()) { vv = vx * vx + vy * vy + vz * vz; }

  double bound(const Sphere& f, const Sphere& m) {
    ++best.result.sphere_tests;
    return entry_lower_bound(f, m, vx, vy, vz, vv);
  }
  double prune_bound() const { return best.result.hit ? best.result.t.hi : std::numeric_limits<double>::infinity(); }
  bool split_first(const Sphere& f, const Sphere& m) const { return f.radius >= m.radius; }
  void leaf(std::uint32_t f, std::uint32_t m) { best.offer(f, m); }
  bool done() const { return false; }
};

}  // namespace

double sphere_entry_time_lower_bound(const Sphere& fixed, const Sphere& moving, const Vec3& v) {
  CGAL::Protect_FPU_rounding<true> guard;
  const I vx(v.x()), vy(v.y()), vz(v.z());
  return entry_lower_bound(fixed, moving, vx, vy, vz, vx * vx + vy * vy + vz * vz);
}

SweepMesh make_sweep_mesh(std::vector<Vec3> vertices, std::vector<Face> faces) {
  SweepMesh m;
  m.vertices = std::move(vertices);
  m.faces = std::move(faces);
  m.tree = build_triangle_bvh<Sphere>(m.vertices, m.faces, [](int n, const auto& p) { return bounding_sphere(n, p); });
  return m;
}

MeshContact first_contact_along_line(const SweepMesh& fixed, const SweepMesh& moving, const Vec3& v) {
  Best best{fixed, moving, v, {}, {}};
  {
    CGAL::Protect_FPU_rounding<true> guard;  // the sphere bounds are interval computations
    SweepPolicy policy(best, v);
    traverse_pairs_nearest_first(fixed.tree, moving.tree, policy);
  }
  return best.result;
}

MeshContact first_contact_brute_force(const SweepMesh& fixed, const SweepMesh& moving, const Vec3& v) {
  Best best{fixed, moving, v, {}, {}};
  for (std::uint32_t f = 0; f < fixed.faces.size(); ++f)
    for (std::uint32_t m = 0; m < moving.faces.size(); ++m) best.offer(f, m);
  return best.result;
}

mpq_class exact_contact_time(const SweepMesh& fixed, const SweepMesh& moving, const Vec3& v, const MeshContact& c) {
  return exact_candidate_time(fixed.triangle(c.fixed_face), moving.triangle(c.moving_face), v, c.candidate);
}

}  // namespace cdbench
