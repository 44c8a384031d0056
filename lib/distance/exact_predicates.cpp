#include "distance/exact_predicates.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

namespace cdbench {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
inline K::Point_3 P(const Vec3& v) { return K::Point_3(v.x(), v.y(), v.z()); }
}  // namespace

bool corners_collinear(const Vec3& a, const Vec3& b, const Vec3& c) { return CGAL::collinear(P(a), P(b), P(c)); }

bool vectors_coplanar(const Vec3& a, const Vec3& b, const Vec3& c) {
  return CGAL::orientation(K::Point_3(0.0, 0.0, 0.0), P(a), P(b), P(c)) == CGAL::COPLANAR;
}

int orientation_sign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // CGAL's orientation is the sign of det(b - a, c - a, d - a) = ((b - a) x (c - a)) . (d - a).
  return static_cast<int>(CGAL::orientation(P(a), P(b), P(c), P(d)));
}

bool point_on_triangle(const Vec3& pd, const Vec3& ad, const Vec3& bd, const Vec3& cd) {
  const K::Point_3 p = P(pd), a = P(ad), b = P(bd), c = P(cd);
  if (CGAL::collinear(a, b, c)) {
    return K::Segment_3(a, b).has_on(p) || K::Segment_3(b, c).has_on(p) || K::Segment_3(c, a).has_on(p);
  }
  return K::Triangle_3(a, b, c).has_on(p);
}

SegmentCrossing segment_crosses_triangle(const Vec3& pd, const Vec3& qd, const Vec3& ad, const Vec3& bd,
                                         const Vec3& cd) {
  const K::Point_3 p = P(pd), q = P(qd), a = P(ad), b = P(bd), c = P(cd);
  const CGAL::Orientation sp = CGAL::orientation(a, b, c, p);
  const CGAL::Orientation sq = CGAL::orientation(a, b, c, q);
  if (sp == sq && sp != CGAL::COPLANAR) return SegmentCrossing::None;
  if (sp == CGAL::COPLANAR && sq == CGAL::COPLANAR) {
    return CGAL::collinear(a, b, c) ? SegmentCrossing::None : SegmentCrossing::Degenerate;
  }
  if (sq == CGAL::COPLANAR) return SegmentCrossing::Degenerate;
  if (sp == CGAL::COPLANAR) return SegmentCrossing::None;  // meets the plane only at p, which is off the triangle
  const CGAL::Orientation o1 = CGAL::orientation(p, q, a, b);
  const CGAL::Orientation o2 = CGAL::orientation(p, q, b, c);
  const CGAL::Orientation o3 = CGAL::orientation(p, q, c, a);
  const bool pos = o1 == CGAL::POSITIVE || o2 == CGAL::POSITIVE || o3 == CGAL::POSITIVE;
  const bool neg = o1 == CGAL::NEGATIVE || o2 == CGAL::NEGATIVE || o3 == CGAL::NEGATIVE;
  if (pos && neg) return SegmentCrossing::None;
  if (o1 == CGAL::COPLANAR || o2 == CGAL::COPLANAR || o3 == CGAL::COPLANAR) return SegmentCrossing::Degenerate;
  return SegmentCrossing::Proper;
}

bool triangles_intersect(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& e, const Vec3& f) {
  const K::Triangle_3 t1(P(a), P(b), P(c)), t2(P(d), P(e), P(f));
  const bool dg1 = t1.is_degenerate(), dg2 = t2.is_degenerate();
  if (!dg1 && !dg2) return CGAL::do_intersect(t1, t2);
  // A degenerate triangle is the union of its edges (segments or points).
  const auto edges_hit = [](const K::Triangle_3& deg, const K::Triangle_3& other, bool other_degenerate) {
    for (int k = 0; k < 3; ++k) {
      const K::Point_3 p = deg.vertex(k), q = deg.vertex((k + 1) % 3);
      if (!other_degenerate) {
        if (p == q ? other.has_on(p) : CGAL::do_intersect(K::Segment_3(p, q), other)) return true;
      } else {
        for (int m = 0; m < 3; ++m) {
          const K::Point_3 r = other.vertex(m), s = other.vertex((m + 1) % 3);
          if (p == q && r == s) {
            if (p == r) return true;
          } else if (p == q) {
            if (K::Segment_3(r, s).has_on(p)) return true;
          } else if (r == s) {
            if (K::Segment_3(p, q).has_on(r)) return true;
          } else if (CGAL::do_intersect(K::Segment_3(p, q), K::Segment_3(r, s))) {
            return true;
          }
        }
      }
    }
    return false;
  };
  return dg1 ? edges_hit(t1, t2, dg2) : edges_hit(t2, t1, false);
}

}  // namespace cdbench
