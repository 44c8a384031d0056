#include "sweep/mesh_sweep.h"

#include <CGAL/Interval_nt.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
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

  // A pair that cannot meet, or only after the best contact's latest time, is not swept (the
  // brute force, the tests' reference, offers every pair unfiltered).
  void offer_if_possible(std::uint32_t f, std::uint32_t m) {
    const Triangle A = fixed.triangle(f), B = moving.triangle(m);
    if (sweep_pair_may_meet(A, B, v, result.hit ? result.t.hi : std::numeric_limits<double>::infinity()))
      offer(f, m, A, B);
  }

  void offer(std::uint32_t f, std::uint32_t m) { offer(f, m, fixed.triangle(f), moving.triangle(m)); }

  void offer(std::uint32_t f, std::uint32_t m, const Triangle& A, const Triangle& B) {
    ++result.triangle_sweeps;
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

// Lower bound of the first time the moving box (+ t v) meets the fixed one; +inf if never. On axis
// k they overlap when f.lo - m.hi <= t v_k <= f.hi - m.lo: an interval of t per axis (all of R, or
// none, when v_k = 0); they meet at the latest entry if it precedes the earliest exit. Only
// times >= from count (+inf when they meet only before). Must run under upward rounding: entries
// are rounded down and exits up, so a pair judged never to meet cannot meet.
double box_entry_lower_bound(const Aabb& f, const Aabb& m, const Vec3& v,
                             double from = -std::numeric_limits<double>::infinity()) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double entry = -kInf, exit = kInf;
  for (int k = 0; k < 3; ++k) {
    const double vk = v[k];
    if (vk == 0.0) {
      if (m.hi[k] < f.lo[k] || f.hi[k] < m.lo[k]) return kInf;
      continue;
    }
    const I a = (I(f.lo[k]) - m.hi[k]) / vk, b = (I(f.hi[k]) - m.lo[k]) / vk;
    entry = std::max(entry, vk > 0.0 ? a.inf() : b.inf());
    exit = std::min(exit, vk > 0.0 ? b.sup() : a.sup());
  }
  return entry <= exit && exit >= from ? std::max(entry, from) : kInf;
}

// (mesh_sweep.h) On axis L the boxes' projections are L.c_f +- R_f and L.c_m + t lv +- R_m
// (obb_radius, pads included; lv = L.v): they overlap when |p + t lv| <= R_f + R_m (p = L.(c_m -
// c_f), within the radii's slack of the exact), an interval of t when lv != 0. Axes nearly
// perpendicular to v (|lv| below 1e-6 |L|_1 |v|) are skipped, so lv carries a relative error below
// 1e-9 and the times a relative margin of 1e-8.
double obb_entry_lower_bound(const Obb& f, const Obb& m, const Vec3& v,
                             double from = -std::numeric_limits<double>::infinity()) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const Vec3 w = m.center - f.center;
  const double mag_f = obb_magnitude(f), mag_m = obb_magnitude(m);
  const double vmax = v.cwiseAbs().maxCoeff();
  double entry = -kInf, exit = kInf;
  const auto axis = [&](const Vec3& L) {
    const double l1 = L.cwiseAbs().sum();
    const double lv = L.dot(v);
    if (!(std::abs(lv) > 1e-6 * l1 * vmax)) return;
    const double R = obb_radius(f, L, l1, mag_f) + obb_radius(m, L, l1, mag_m);
    const double p = L.dot(w);
    double t0 = (-R - p) / lv, t1 = (R - p) / lv;
    if (lv < 0.0) std::swap(t0, t1);
    entry = std::max(entry, t0 - 1e-8 * std::abs(t0));
    exit = std::min(exit, t1 + 1e-8 * std::abs(t1));
  };
  for (int k = 0; k < 3; ++k) axis(f.axes.col(k));
  for (int k = 0; k < 3; ++k) axis(m.axes.col(k));
  for (int i = 0; i < 3 && entry <= exit; ++i)
    for (int j = 0; j < 3; ++j) axis(f.axes.col(i).cross(m.axes.col(j)));
  return entry <= exit && exit >= from ? std::max(entry, from) : kInf;
}

struct SweepPolicy {
  Best& best;
  const Vec3& v;
  I vx, vy, vz, vv;

  SweepPolicy(Best& b, const Vec3& vel) : best(b), v(vel), vx(vel.x()), vy(vel.y()), vz(vel.z()) {
    vv = vx * vx + vy * vy + vz * vz;
  }

  // The latest of the sphere, box and oriented box entry times: each is a lower bound of the first
  // meeting (the oriented boxes, the dearest, only while the pair may still matter).
  double bound(const SweepVolume& f, const SweepVolume& m) {
    ++best.result.sphere_tests;
    const double s = entry_lower_bound(f.sphere, m.sphere, vx, vy, vz, vv);
    if (!(s < std::numeric_limits<double>::infinity())) return s;
    const double b = std::max(s, box_entry_lower_bound(f.box, m.box, v));
    if (!(b <= prune_bound()) || f.obb.half[0] < 0.0 || m.obb.half[0] < 0.0) return b;
    return std::max(b, obb_entry_lower_bound(f.obb, m.obb, v));
  }
  double prune_bound() const { return best.result.hit ? best.result.t.hi : std::numeric_limits<double>::infinity(); }
  bool split_first(const SweepVolume& f, const SweepVolume& m) const { return f.sphere.radius >= m.sphere.radius; }
  void leaf(std::uint32_t f, std::uint32_t m) { best.offer_if_possible(f, m); }
  bool done() const { return false; }
};

// The float twin of Best and SweepPolicy: the same traversal, sphere entry times and triangle
// sweeps in plain doubles (the paper's float placement).
struct FloatSweepPolicy {
  const SweepMesh& fixed;
  const SweepMesh& moving;
  const Vec3& v;
  double vv;
  FloatMeshContact result;

  Vec3 e1, e2;  // an orthonormal frame of the plane normal to v

  FloatSweepPolicy(const SweepMesh& f, const SweepMesh& m, const Vec3& vel)
      : fixed(f), moving(m), v(vel), vv(vel.squaredNorm()) {
    const Vec3 u = v / std::sqrt(vv);
    e1 = (std::abs(u.x()) < 0.6 ? Vec3(1, 0, 0) : Vec3(0, 1, 0)).cross(u).normalized();
    e2 = u.cross(e1);
  }

  // A necessary condition for a contact of the pair before the best one so far, cheaper than the
  // sweep: the two triangles' shadows on the plane normal to v must overlap (coordinate ranges in
  // e1 and e2), and a = b + t v needs t >= (min a.v - max b.v) / v.v. Ranges are widened by a
  // relative 1e-9 so that rounding never drops a contact the sweep would find.
  bool may_touch(const Triangle& A, const Triangle& B) const {
    const auto range = [](const Triangle& T, const Vec3& e, double* lo, double* hi) {
      const double a = T[0].dot(e), b = T[1].dot(e), c = T[2].dot(e);
      *lo = std::min(a, std::min(b, c));
      *hi = std::max(a, std::max(b, c));
    };
    double alo, ahi, blo, bhi;
    for (const Vec3* e : {&e1, &e2}) {
      range(A, *e, &alo, &ahi);
      range(B, *e, &blo, &bhi);
      const double slack = 1e-9 * (std::abs(alo) + std::abs(ahi) + std::abs(blo) + std::abs(bhi));
      if (ahi + slack < blo || bhi + slack < alo) return false;
    }
    if (!result.hit) return true;
    range(A, v, &alo, &ahi);
    range(B, v, &blo, &bhi);
    const double slack = 1e-9 * (std::abs(alo) + std::abs(bhi));
    return (alo - bhi - slack) / vv <= result.t;
  }

  double bound(const SweepVolume& fv, const SweepVolume& mv) {
    ++result.sphere_tests;
    const Sphere &f = fv.sphere, &m = mv.sphere;
    const Vec3 w = m.center - f.center;
    const double R = f.radius + m.radius;
    const double wv = w.dot(v);
    const double disc = wv * wv - vv * (w.squaredNorm() - R * R);
    if (disc < 0.0) return std::numeric_limits<double>::infinity();
    return (-wv - std::sqrt(disc)) / vv;
  }
  double prune_bound() const { return result.hit ? result.t : std::numeric_limits<double>::infinity(); }
  bool split_first(const SweepVolume& f, const SweepVolume& m) const { return f.sphere.radius >= m.sphere.radius; }
  void leaf(std::uint32_t f, std::uint32_t m) {
    const Triangle A = fixed.triangle(f), B = moving.triangle(m);
    if (!may_touch(A, B)) return;
    ++result.triangle_sweeps;
    const FloatLineContact lc = line_contact_float(A, B, v);
    if (!lc.hit) return;
    if (result.hit && (lc.t_in > result.t ||
                       (lc.t_in == result.t && std::tie(f, m) > std::tie(result.fixed_face, result.moving_face))))
      return;
    result.hit = true;
    result.t = lc.t_in;
    result.fixed_face = f;
    result.moving_face = m;
  }
  bool done() const { return false; }
};

}  // namespace

// (mesh_sweep.h) For e exactly perpendicular to v — (-v_y, v_x, 0), (0, -v_z, v_y) and
// (v_z, 0, -v_x): their dot products with v cancel exactly — a = b + t v gives a.e = b.e, so the
// two triangles' ranges on e must meet; and t = (a - b).v / v.v >= (min a.v - max b.v) / v.v.
// Interval arithmetic throughout: rounding can keep a pair that could be dropped, never the reverse.
bool sweep_pair_may_meet(const Triangle& A, const Triangle& B, const Vec3& v, double t_max) {
  CGAL::Protect_FPU_rounding<true> guard;
  const auto range = [](const Triangle& T, double x, double y, double z, double* lo, double* hi) {
    *lo = std::numeric_limits<double>::infinity();
    *hi = -*lo;
    for (const Vec3& p : T) {
      const I d = I(p.x()) * x + I(p.y()) * y + I(p.z()) * z;
      *lo = std::min(*lo, d.inf());
      *hi = std::max(*hi, d.sup());
    }
  };
  const double e[3][3] = {{-v.y(), v.x(), 0.0}, {0.0, -v.z(), v.y()}, {v.z(), 0.0, -v.x()}};
  double alo, ahi, blo, bhi;
  for (const auto& d : e) {
    range(A, d[0], d[1], d[2], &alo, &ahi);
    range(B, d[0], d[1], d[2], &blo, &bhi);
    if (ahi < blo || bhi < alo) return false;
  }
  if (!(t_max < std::numeric_limits<double>::infinity())) return true;
  range(A, v.x(), v.y(), v.z(), &alo, &ahi);
  range(B, v.x(), v.y(), v.z(), &blo, &bhi);
  const I vv = I(v.x()) * v.x() + I(v.y()) * v.y() + I(v.z()) * v.z();
  return !(((I(alo) - bhi) / vv).inf() > t_max);
}

FloatMeshContact first_contact_along_line_float(const SweepMesh& fixed, const SweepMesh& moving, const Vec3& v) {
  FloatSweepPolicy policy(fixed, moving, v);
  traverse_pairs_best_first(fixed.tree, moving.tree, policy);
  return policy.result;
}

double sphere_entry_time_lower_bound(const Sphere& fixed, const Sphere& moving, const Vec3& v) {
  CGAL::Protect_FPU_rounding<true> guard;
  const I vx(v.x()), vy(v.y()), vz(v.z());
  return entry_lower_bound(fixed, moving, vx, vy, vz, vx * vx + vy * vy + vz * vz);
}

double box_entry_time_lower_bound(const Aabb& fixed, const Aabb& moving, const Vec3& v) {
  CGAL::Protect_FPU_rounding<true> guard;
  return box_entry_lower_bound(fixed, moving, v);
}

double obb_entry_time_lower_bound(const Obb& fixed, const Obb& moving, const Vec3& v, double from) {
  return obb_entry_lower_bound(fixed, moving, v, from);
}

// (mesh_sweep.h) On axis L the projections are L.c_a +- R_a and L.c_b +- R_b (obb_radius, pads
// included, their slack covering p = L.(c_b - c_a)): a gap |p| - R_a - R_b > 0 proves every pair of
// points at least gap / |L| apart. |L|^2 is rounded up by the factor, the quotient down by the
// final one.
double obb_squared_distance_lower_bound(const Obb& a, const Obb& b) {
  const Vec3 w = b.center - a.center;
  const double mag_a = obb_magnitude(a), mag_b = obb_magnitude(b);
  double best = 0.0;
  const auto axis = [&](const Vec3& L) {
    const double l1 = L.cwiseAbs().sum();
    const double gap = std::abs(L.dot(w)) - obb_radius(a, L, l1, mag_a) - obb_radius(b, L, l1, mag_b);
    if (!(gap > 0.0)) return;
    const double n2 = L.squaredNorm() * (1.0 + 1e-14);
    if (!(n2 > 0.0)) return;
    best = std::max(best, gap * gap / n2);
  };
  for (int k = 0; k < 3; ++k) axis(a.axes.col(k));
  for (int k = 0; k < 3; ++k) axis(b.axes.col(k));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) axis(a.axes.col(i).cross(b.axes.col(j)));
  return best * (1.0 - 1e-13);
}

double box_entry_time_lower_bound_upward(const Aabb& fixed, const Aabb& moving, const Vec3& v, double from) {
  return box_entry_lower_bound(fixed, moving, v, from);
}

SweepMesh make_sweep_mesh(std::vector<Vec3> vertices, std::vector<Face> faces, const BvhBuildOptions& options,
                          bool oriented) {
  SweepMesh m;
  m.vertices = std::move(vertices);
  m.faces = std::move(faces);
  m.tree = build_triangle_bvh<SweepVolume>(
      m.vertices, m.faces,
      [oriented](int n, const auto& p) {
        const Aabb box = bounding_box(n, p);
        return SweepVolume{bounding_sphere_in_box(box, n, p), box, oriented ? fit_obb(n, p) : Obb{}};
      },
      options);
  return m;
}

namespace {

// An upper bound of the spectral norm of R: sqrt of a Gershgorin bound on R^T R, whose computed
// entries are within 1e-15 of (|R|^T |R|)_ij of the exact ones (three products and two sums).
double spectral_norm_upper(const Eigen::Matrix3d& R) {
  const Eigen::Matrix3d M = R.transpose() * R;
  const Eigen::Matrix3d A = R.cwiseAbs().transpose() * R.cwiseAbs();
  double worst = 0.0;
  for (int i = 0; i < 3; ++i) {
    double row = 0.0;
    for (int j = 0; j < 3; ++j) row += std::abs(M(i, j)) + 1e-15 * A(i, j);
    worst = std::max(worst, row);
  }
  return std::sqrt(worst) * (1.0 + 1e-15);
}

// |fl(fl(R x) + t) - (R x + t)| (Euclidean) bounded, as MoverOrientation::transform_error: gamma_4
// (< 4.5e-16) times |R| |x| + |t| per coordinate; the sum over coordinates bounds the norm.
double place_error(const Eigen::Matrix3d& absR, const Vec3& x, const Vec3& t) {
  return 1e-15 * ((absR * x.cwiseAbs()).sum() + t.cwiseAbs().sum()) + 1e-300;
}

// fl(fl(R x) + t) in some order of evaluation: within place_error of R x + t.
Vec3 carry(const Eigen::Matrix3d& R, const Vec3& t, const Vec3& x) {
  const Vec3 y = R * x;
  return Vec3(y[0] + t[0], y[1] + t[1], y[2] + t[2]);
}

}  // namespace

SweepMesh placed_sweep_mesh(const SweepMesh& own, const Eigen::Matrix3d& R, const Vec3& t, std::vector<Vec3> placed,
                            double err) {
  if (placed.size() != own.vertices.size())
    throw std::invalid_argument("placed_sweep_mesh: the placed vertices do not match the mesh");
  SweepMesh r;
  r.vertices = std::move(placed);
  r.faces = own.faces;
  r.tree.order = own.tree.order;
  r.tree.nodes.resize(own.tree.nodes.size());
  const Eigen::Matrix3d absR = R.cwiseAbs();
  const double nR = spectral_norm_upper(R);
  const auto outward = [](double x) { return x * (1.0 + 1e-14) + 1e-300; };
  // Every node on its own (on all threads: an orientation's frame holds up the threads that wait
  // for it), leaves' boxes included; then the internal boxes, which need their children's.
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, own.tree.nodes.size(), 4096), [&](const auto& range) {
    for (std::size_t k = range.begin(); k != range.end(); ++k) {
      const auto& a = own.tree.nodes[k];
      auto& b = r.tree.nodes[k];
      b.first = a.first;
      b.count = a.count;
      const SweepVolume& u = a.bv;
      SweepVolume& w = b.bv;
      // A point x of the volume lands at y = R x + t + e (|e| <= err); the volume's centre c at
      // c' = fl(fl(R c) + t), within place_error of R c + t.
      if (u.sphere.radius >= 0.0) {  // |y - c'| <= |R| |x - c| + err + |c' - (R c + t)|
        w.sphere.center = carry(R, t, u.sphere.center);
        w.sphere.radius = outward(nR * u.sphere.radius + err + place_error(absR, u.sphere.center, t));
      }
      if (u.obb.half[0] >= 0.0) {
        // y = c' + fl(R A) a + (R A - fl(R A)) a + (R c + t - c') + e, |a_k| <= half_k: within the
        // pad of the carried box; fl(R A)'s columns are within 1e-15 |R| |A_k| <= 2e-15 of R A_k.
        w.obb.center = carry(R, t, u.obb.center);
        w.obb.axes = R * u.obb.axes;
        w.obb.half = u.obb.half;
        w.obb.pad = outward(nR * u.obb.pad + err + place_error(absR, u.obb.center, t) + 1e-14 * u.obb.half.sum());
      }
      // The boxes, tight: each leaf's from its triangles' placed vertices.
      if (b.count > 0) b.bv.box = leaf_triangles_box(b, r.tree.order, r.faces, r.vertices);
    }
  });
  unite_internal_boxes(r.tree.nodes, [](auto& node) -> Aabb& { return node.bv.box; });
  return r;
}

SweepMesh translated_sweep_mesh(const SweepMesh& m, const Vec3& t) {
  SweepMesh r;
  r.faces = m.faces;
  r.vertices.resize(m.vertices.size());
  for (std::size_t k = 0; k < m.vertices.size(); ++k)
    r.vertices[k] = Vec3(m.vertices[k][0] + t[0], m.vertices[k][1] + t[1], m.vertices[k][2] + t[2]);
  r.tree = m.tree;
  const double tn = t.norm();
  for (auto& node : r.tree.nodes) {
    // Rounding to nearest is monotone: fl(lo + t) <= fl(v + t) <= fl(hi + t) for lo <= v <= hi.
    Aabb& b = node.bv.box;
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = b.lo[k] + t[k];
      b.hi[k] = b.hi[k] + t[k];
    }
    // The oriented box: its centre moved as the points, both rounded once (each within u of
    // |c + t| and |x + t| <= |c + t| + the box's half diagonal); 1e-15 per axis covers it.
    Obb& o = node.bv.obb;
    if (o.half[0] >= 0.0) {
      const Vec3 c = o.center;
      o.center = Vec3(c[0] + t[0], c[1] + t[1], c[2] + t[2]);
      const double grow = 1e-15 * (2.0 * (c.cwiseAbs().sum() + t.cwiseAbs().sum()) + o.half.sum()) + 1e-300;
      o.half = (o.half.array() + grow).matrix();
    }
    Sphere& s = node.bv.sphere;
    if (s.radius < 0.0) continue;
    const Vec3 c = s.center;
    s.center = Vec3(c[0] + t[0], c[1] + t[1], c[2] + t[2]);
    // |v + t| <= |c| + r + |t|; 1e-15 > 4u covers the two roundings, the norms' own rounding and
    // this sum's; the tiny absolute term covers underflow.
    s.radius = s.radius * (1.0 + 1e-15) + 1e-15 * (2.0 * (c.norm() + tn) + s.radius) + 1e-300;
  }
  return r;
}

MeshContact first_contact_along_line(const SweepMesh& fixed, const SweepMesh& moving, const Vec3& v) {
  Best best{fixed, moving, v, {}, {}};
  {
    CGAL::Protect_FPU_rounding<true> guard;  // the sphere bounds are interval computations
    SweepPolicy policy(best, v);
    traverse_pairs_best_first(fixed.tree, moving.tree, policy);
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
