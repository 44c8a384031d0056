#include "distance/exact_predicates.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace cdbench {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
inline K::Point_3 P(const Vec3& v) { return K::Point_3(v.x(), v.y(), v.z()); }
}  // namespace

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

}  // namespace cdbench
