// Exact translational triangle sweep against an independent formulation: the line t v against
// the Minkowski difference A - B built explicitly from its 9 points, as the union of the closed
// triangles of all their triples (every point of a convex hull lies in such a triangle), each
// intersected with the line by CGAL's exact (lazy, filtered) kernel.
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>
#include <limits>
#include <random>
#include <string>

#include "sweep/mesh_sweep.h"
#include "sweep/triangle_sweep.h"

namespace cdbench {
namespace {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;

// CGAL's exact number type (whichever GMP wrapper this CGAL uses) to mpq_class, via its text form.
mpq_class to_mpq(const EK::FT& x) {
  std::ostringstream os;
  os << CGAL::exact(x);
  mpq_class q(os.str());
  q.canonicalize();
  return q;
}

struct Range {
  bool hit = false;
  mpq_class lo, hi;
  void take(const mpq_class& t) {
    if (!hit) {
      hit = true;
      lo = hi = t;
    } else {
      if (t < lo) lo = t;
      if (t > hi) hi = t;
    }
  }
};

EK::Point_3 P(const Vec3& p) { return {p.x(), p.y(), p.z()}; }

// [t_in, t_out] of the line {t v} through the Minkowski difference, by brute force.
Range reference_line_contact(const Triangle& A, const Triangle& B, const Vec3& vd) {
  std::vector<EK::Point_3> pts;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      pts.push_back(EK::Point_3(0, 0, 0) + (P(A[i]) - P(B[j])));
  const EK::Vector_3 v(vd.x(), vd.y(), vd.z());
  const EK::Point_3 O(0, 0, 0);
  const EK::Line_3 line(O, v);
  const EK::FT vv = v.squared_length();
  Range r;
  const auto param = [&](const EK::Point_3& p) { return to_mpq(((p - O) * v) / vv); };
  const auto with_segment = [&](const EK::Point_3& p, const EK::Point_3& q) {
    if (p == q) {
      if (line.has_on(p)) r.take(param(p));
      return;
    }
    const EK::Segment_3 seg(p, q);
    if (!CGAL::do_intersect(line, seg)) return;
    const auto x = CGAL::intersection(line, seg);
    if (!x) return;
    if (const auto* pt = boost::get<EK::Point_3>(&*x)) r.take(param(*pt));
    else if (const auto* s = boost::get<EK::Segment_3>(&*x)) {
      r.take(param(s->source()));
      r.take(param(s->target()));
    }
  };
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (std::size_t j = i + 1; j < pts.size(); ++j)
      for (std::size_t k = j + 1; k < pts.size(); ++k) {
        if (CGAL::collinear(pts[i], pts[j], pts[k])) {
          with_segment(pts[i], pts[j]);
          with_segment(pts[j], pts[k]);
          with_segment(pts[i], pts[k]);
          continue;
        }
        const EK::Triangle_3 tri(pts[i], pts[j], pts[k]);
        if (!CGAL::do_intersect(line, tri)) continue;
        const auto x = CGAL::intersection(line, tri);
        if (!x) continue;
        if (const auto* pt = boost::get<EK::Point_3>(&*x)) r.take(param(*pt));
        else if (const auto* s = boost::get<EK::Segment_3>(&*x)) {
          r.take(param(s->source()));
          r.take(param(s->target()));
        }
      }
  return r;
}

std::optional<mpq_class> reference_first_contact(const Triangle& A, const Triangle& B, const Vec3& v) {
  if (v == Vec3::Zero()) {
    const Range r = reference_line_contact(A, B, Vec3(1, 0, 0));
    if (r.hit && r.lo <= 0 && r.hi >= 0) return mpq_class(0);
    return std::nullopt;
  }
  const Range r = reference_line_contact(A, B, v);
  if (!r.hit || r.hi < 0) return std::nullopt;
  if (r.lo >= 0) return r.lo;
  return mpq_class(0);
}

std::string describe(const Triangle& A, const Triangle& B, const Vec3& v) {
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "A={{%.17g,%.17g,%.17g},{%.17g,%.17g,%.17g},{%.17g,%.17g,%.17g}} "
                "B={{%.17g,%.17g,%.17g},{%.17g,%.17g,%.17g},{%.17g,%.17g,%.17g}} v={%.17g,%.17g,%.17g}",
                A[0].x(), A[0].y(), A[0].z(), A[1].x(), A[1].y(), A[1].z(), A[2].x(), A[2].y(), A[2].z(), B[0].x(),
                B[0].y(), B[0].z(), B[1].x(), B[1].y(), B[1].z(), B[2].x(), B[2].y(), B[2].z(), v.x(), v.y(), v.z());
  return buf;
}

std::string str(const std::optional<mpq_class>& t) { return t ? t->get_str() : std::string("none"); }

// Checks line_contact and first_contact_time against the reference on one case.
void check_case(const Triangle& A, const Triangle& B, const Vec3& v) {
  const auto got = first_contact_time(A, B, v);
  const auto want = reference_first_contact(A, B, v);
  ASSERT_EQ(str(got), str(want)) << describe(A, B, v);
  if (v == Vec3::Zero()) return;
  const LineContact lc = line_contact(A, B, v);
  const Range r = reference_line_contact(A, B, v);
  ASSERT_EQ(lc.hit, r.hit) << describe(A, B, v);
  if (!r.hit) return;
  const mpq_class tin = exact_candidate_time(A, B, v, lc.in), tout = exact_candidate_time(A, B, v, lc.out);
  ASSERT_EQ(tin, r.lo) << describe(A, B, v);
  ASSERT_EQ(tout, r.hi) << describe(A, B, v);
  ASSERT_LE(mpq_class(lc.t_in.lo), tin);
  ASSERT_GE(mpq_class(lc.t_in.hi), tin);
  ASSERT_LE(mpq_class(lc.t_out.lo), tout);
  ASSERT_GE(mpq_class(lc.t_out.hi), tout);
}

const Triangle A0{Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)};

struct HandCase {
  const char* what;
  Triangle A, B;
  Vec3 v;
  const char* expected;  // rational or "none"
};

// Hand-built degenerate and boundary cases, with the answer worked out by hand.
std::vector<HandCase> hand_cases() {
  const auto T = [](Vec3 a, Vec3 b, Vec3 c) { return Triangle{a, b, c}; };
  return {
      {"vertex onto face interior", A0, T({1, 1, 2}, {2, 1, 3}, {1, 2, 3}), {0, 0, -1}, "2"},
      {"same, twice the speed", A0, T({1, 1, 2}, {2, 1, 3}, {1, 2, 3}), {0, 0, -2}, "1"},
      {"moving away", A0, T({1, 1, 2}, {2, 1, 3}, {1, 2, 3}), {0, 0, 1}, "none"},
      {"coplanar sliding, vertex meets vertex", A0, T({6, 0, 0}, {8, 0, 0}, {6, 2, 0}), {-1, 0, 0}, "2"},
      {"coplanar sliding, vertex meets hypotenuse", A0, T({5, 1, 0}, {7, 1, 0}, {5, 3, 0}), {-1, 0, 0}, "2"},
      {"coplanar sliding, other shape", A0, T({5, 1, 0}, {7, 1, 0}, {7, 3, 0}), {-1, 0, 0}, "2"},
      {"coplanar sliding, passes above", A0, T({5, 5, 0}, {7, 5, 0}, {5, 7, 0}), {-1, 0, 0}, "none"},
      {"coplanar sliding along the top vertex line", A0, T({5, 4, 0}, {7, 4, 0}, {5, 6, 0}), {-1, 0, 0}, "5"},
      {"parallel edges meet along a segment", A0, T({1, -2, 0}, {3, -2, 0}, {2, -2, 2}), {0, 1, 0}, "2"},
      {"apex onto an edge, oblique", A0, T({1, -2, 0}, {3, -2, 0}, {2, -2, 2}), {0, 1, -1}, "2"},
      {"touching at t = 0, moving away", A0, T({1, 1, 0}, {2, 1, 1}, {1, 2, 1}), {0, 0, 1}, "0"},
      {"intersecting at t = 0, moving away", A0, T({1, 1, -1}, {2, 1, 1}, {1, 2, 1}), {0, 0, 1}, "0"},
      {"intersecting at t = 0, moving in", A0, T({1, 1, -1}, {2, 1, 1}, {1, 2, 1}), {0, 0, -1}, "0"},
      {"zero motion, intersecting", A0, T({1, 1, -1}, {2, 1, 1}, {1, 2, 1}), {0, 0, 0}, "0"},
      {"zero motion, disjoint", A0, T({1, 1, 2}, {2, 1, 3}, {1, 2, 3}), {0, 0, 0}, "none"},
      {"zero motion, touching at a vertex", A0, T({1, 1, 0}, {2, 1, 1}, {1, 2, 1}), {0, 0, 0}, "0"},
      {"zero motion, coplanar nested", A0, T({1, 1, 0}, {2, 1, 0}, {1, 2, 0}), {0, 0, 0}, "0"},
      {"zero motion, coplanar disjoint", A0, T({6, 0, 0}, {8, 0, 0}, {6, 2, 0}), {0, 0, 0}, "none"},
      {"zero motion, coplanar sharing a vertex", A0, T({4, 0, 0}, {8, 0, 0}, {6, 2, 0}), {0, 0, 0}, "0"},
      {"parallel faces, same shape", A0, T({0, 0, 3}, {4, 0, 3}, {0, 4, 3}), {0, 0, -1}, "3"},
      {"parallel faces, shifted", A0, T({1, 1, 3}, {5, 1, 3}, {1, 5, 3}), {0, 0, -1}, "3"},
      {"parallel faces, no overlap", A0, T({5, 5, 3}, {9, 5, 3}, {5, 9, 3}), {0, 0, -1}, "none"},
      {"edge onto face, segment contact", A0, T({2, -1, 1}, {2, 1, 1}, {2, 0, 3}), {0, 0, -1}, "1"},
      {"vertex onto vertex from above", A0, T({4, 0, 2}, {5, 0, 3}, {4, 1, 3}), {0, 0, -1}, "2"},
      {"coplanar vertex onto vertex", A0, T({6, 0, 0}, {7, 1, 0}, {6, -1, 0}), {-1, 0, 0}, "2"},
      {"motion along an edge line", A0, T({6, 0, 0}, {7, 0, 1}, {7, 0, -1}), {-1, 0, 0}, "2"},
      {"grazing miss beside the face", A0, T({1, 5, 1}, {2, 5, 1}, {1, 5, 2}), {0, 0, -1}, "none"},
      {"vertex onto the top vertex", A0, T({0, 4, 1}, {-1, 5, 1}, {0, 5, 2}), {0, 0, -1}, "1"},
      {"contact only at negative time", A0, T({1, 1, -2}, {2, 1, -3}, {1, 2, -3}), {0, 0, -1}, "none"},
      {"motion parallel to the plane, above it", A0, T({1, 1, 1}, {2, 1, 1}, {1, 2, 2}), {1, 0, 0}, "none"},
      {"edge in the plane hits the hypotenuse", A0, T({6, 1, 0}, {6, 2, 0}, {7, 1, 3}), {-1, 0, 0}, "3"},
      {"diagonal in-plane motion, vertex meets vertex", A0, T({6, 1, 0}, {6, 2, 0}, {7, 1, 3}), {-1, -1, 0}, "2"},
      {"non-unit speed, rational time", A0, T({1, 1, 2}, {2, 1, 3}, {1, 2, 3}), {0, 0, -3}, "2/3"},
      {"edge crosses edge, skew", A0, T({2, -1, 1}, {3, 1, 1}, {2, 0, 5}), {0, 1, -1}, "1"},
      {"collinear motion, edges overlap", A0, T({5, 0, 0}, {7, 0, 0}, {6, 0, 2}), {-1, 0, 0}, "1"},
      {"vertex slides along the hypotenuse line onto a vertex", A0, T({5, -1, 0}, {6, -1, 1}, {6, -1, -1}), {-1, 1, 0}, "1"},
      {"same from farther", A0, T({6, -2, 0}, {7, -2, 1}, {7, -2, -1}), {-1, 1, 0}, "2"},
      {"degenerate B (a segment) onto the face", A0, T({1, 1, 2}, {2, 2, 2}, {3, 3, 2}), {0, 0, -1}, "2"},
      {"degenerate B (a point) onto an edge", A0, T({2, -3, 0}, {2, -3, 0}, {2, -3, 0}), {0, 1, 0}, "3"},
      {"degenerate A (a segment), B crosses it", T({0, 0, 0}, {4, 0, 0}, {2, 0, 0}), T({1, -1, 3}, {3, -1, 3}, {2, 1, 3}),
       {0, 0, -1}, "3"},
      {"both degenerate, segments cross", T({0, 0, 0}, {4, 0, 0}, {2, 0, 0}), T({2, -1, 3}, {2, 1, 3}, {2, 0, 3}),
       {0, 0, -1}, "3"},
      {"both degenerate, parallel collinear segments", T({0, 0, 0}, {4, 0, 0}, {2, 0, 0}),
       T({6, 0, 0}, {8, 0, 0}, {7, 0, 0}), {-1, 0, 0}, "2"},
      {"both points", T({1, 2, 3}, {1, 2, 3}, {1, 2, 3}), T({3, 6, 9}, {3, 6, 9}, {3, 6, 9}), {-1, -2, -3}, "2"},
      {"both points, missing", T({1, 2, 3}, {1, 2, 3}, {1, 2, 3}), T({3, 6, 9}, {3, 6, 9}, {3, 6, 9}), {-1, -2, -2}, "none"},
      {"tiny gap, exact rational", A0, T({1, 1, 0x1p-40}, {2, 1, 1}, {1, 2, 1}), {0, 0, -3}, "1/3298534883328"},
      {"huge coordinates", T({0, 0, 0}, {0x1p60, 0, 0}, {0, 0x1p60, 0}),
       T({0x1p58, 0x1p58, 0x1p59}, {0x1p59, 0x1p58, 0x1p60}, {0x1p58, 0x1p59, 0x1p60}), {0, 0, -1}, "576460752303423488"},
      {"edge parallel to the motion, its vertex first", A0, T({4, 4, 0}, {5, 5, 0}, {4, 5, 1}), {-1, -1, 0}, "2"},
      {"B surrounds A's plane crossing, moving sideways", A0, T({-10, -10, -12}, {30, -10, -12}, {-10, 30, 28}),
       {1, 0, 0}, "0"},
      {"coplanar, B contains A, moving", A0, T({-10, -10, 0}, {30, -10, 0}, {-10, 30, 0}), {1, 1, 0}, "0"},
      {"coplanar, approach along the hypotenuse normal", A0, T({4, 4, 0}, {6, 4, 0}, {4, 6, 0}), {-1, -1, 0}, "2"},
  };
}

TEST(TriangleSweep, HandBuiltDegenerateCases) {
  const auto cases = hand_cases();
  EXPECT_GE(cases.size(), 50u);
  for (const HandCase& c : cases) {
    SCOPED_TRACE(c.what);
    const auto got = first_contact_time(c.A, c.B, c.v);
    EXPECT_EQ(str(got), c.expected) << describe(c.A, c.B, c.v);
    check_case(c.A, c.B, c.v);
    // Symmetry: B fixed and A moving with -v touch at the same times.
    EXPECT_EQ(str(first_contact_time(c.B, c.A, -c.v)), c.expected) << describe(c.B, c.A, -c.v);
    // Vertex order does not matter.
    EXPECT_EQ(str(first_contact_time(Triangle{c.A[2], c.A[0], c.A[1]}, Triangle{c.B[1], c.B[0], c.B[2]}, c.v)),
              c.expected);
  }
}

// compare_entry_times decides one event seen from two triangle pairs (a vertex or an edge shared by
// neighbouring faces, corners in any order) without rationals; every answer must equal the exact
// comparison. Cases: a mover vertex shared by two faces reaching a fixed face (kind 0), a mover
// edge shared by two faces crossing a fixed ridge (kind 2, edges reversed in the neighbours), and
// near-ties of different events (a second vertex one ulp higher: overlapping enclosures, unequal
// times) that must not be merged.
TEST(TriangleSweep, CompareEntryTimesTiesAgreeWithRationals) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const auto jitter = [&](double x) { return x + 0.01 * U(rng); };
  int ties = 0, near = 0, compared = 0;
  const auto check = [&](const Triangle& A1, const Triangle& B1, const Triangle& A2, const Triangle& B2, const Vec3& v) {
    const LineContact c1 = line_contact(A1, B1, v), c2 = line_contact(A2, B2, v);
    if (!c1.hit || !c2.hit) return;
    ++compared;
    const int exact = cmp(exact_candidate_time(A1, B1, v, c1.in), exact_candidate_time(A2, B2, v, c2.in));
    const int got = compare_entry_times(c1, A1, B1, v, c2, A2, B2, v);
    EXPECT_EQ(got, exact) << describe(A1, B1, v) << "\nagainst\n" << describe(A2, B2, v);
    ties += exact == 0;
  };
  for (int k = 0; k < 400; ++k) {
    const Vec3 v{0.05 * U(rng), 0.05 * U(rng), -1.0 - 0.1 * std::abs(U(rng))};
    // A vertex b below its two faces, over a fixed face; the neighbour's corners in another order.
    const Triangle A{Vec3{jitter(-10), jitter(-10), jitter(0)}, Vec3{jitter(10), jitter(-10), jitter(0)},
                     Vec3{jitter(0), jitter(10), jitter(0)}};
    const Vec3 b{U(rng), U(rng), 5.0 + U(rng)};
    const Triangle B1{b, b + Vec3{jitter(1), jitter(0), jitter(1)}, b + Vec3{jitter(0), jitter(1), jitter(2)}};
    const Triangle B2{b + Vec3{jitter(-1), jitter(0.5), jitter(3)}, b + Vec3{jitter(0.3), jitter(-1), jitter(1)}, b};
    const Triangle Ar{A[2], A[1], A[0]};
    check(A, B1, A, B2, v);
    check(A, B1, Ar, B2, v);
    // Another vertex beside b parallel to A's plane, then one ulp higher: a different event whose
    // time differs from b's by about an ulp (the enclosures overlap; the exact times differ or not).
    const Vec3 n = (A[1] - A[0]).cross(A[2] - A[0]);
    Vec3 c = b + 0.25 * n.cross(Vec3(1, 0, 0)).normalized();
    c[2] = std::nextafter(c[2], 100.0);
    const Triangle C{c, c + Vec3{jitter(1), jitter(0), jitter(1)}, c + Vec3{jitter(0), jitter(1), jitter(2)}};
    const LineContact lb = line_contact(A, B1, v), lc = line_contact(A, C, v);
    near += lb.hit && lc.hit && !(lb.t_in.hi < lc.t_in.lo) && !(lc.t_in.hi < lb.t_in.lo);
    check(A, B1, A, C, v);
    check(A, C, A, B1, v);
    // A mover ridge su over a fixed ridge pq, each shared by two faces (reversed in the second).
    const double h = 3.0 + U(rng);
    const Vec3 p{jitter(-5), jitter(0), jitter(0)}, q{jitter(5), jitter(0), jitter(0)};
    const Vec3 s{jitter(0.3), jitter(-5), h}, u{jitter(0.2), jitter(5), h + 0.1 * U(rng)};
    const Triangle F1{p, q, Vec3{jitter(0), jitter(3), jitter(-2)}}, F2{q, p, Vec3{jitter(0), jitter(-3), jitter(-2)}};
    const Triangle M1{s, u, Vec3{jitter(3), jitter(0), h + 2}}, M2{u, s, Vec3{jitter(-3), jitter(0), h + 2}};
    check(F1, M1, F2, M2, v);
    check(F1, M2, F2, M1, v);
    check(F2, M1, F1, M1, v);
  }
  EXPECT_GT(compared, 2000);
  EXPECT_GT(ties, 1500);  // most comparisons are true ties of one event (2,000 of 2,800)
  EXPECT_GT(near, 100);   // and the near-ties reach the exact comparison (400)
}

std::size_t random_case_count() {
  if (const char* e = std::getenv("CDBENCH_SWEEP_CASES")) return std::strtoull(e, nullptr, 10);
  return 100000;
}

// Random cases of four kinds: small integer grids (rich in degeneracies: coplanar, parallel,
// collinear), dyadic perturbations of them, general doubles aimed so that most lines hit, and
// everything in one plane.
TEST(TriangleSweep, RandomCasesAgainstMinkowskiReference) {
  std::mt19937_64 rng(20261122);
  std::uniform_int_distribution<int> small(-3, 3);
  const auto small_coordinate = [&] { return static_cast<double>(small(rng)); };
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const std::size_t n = random_case_count();
  std::size_t hits = 0, exact_paths = 0;
  std::size_t entry_kind[6] = {0, 0, 0, 0, 0, 0};
  for (std::size_t k = 0; k < n; ++k) {
    Triangle A, B;
    Vec3 v;
    const int family = static_cast<int>(k % 4);
    const auto grid = [&] { return Vec3{small_coordinate(), small_coordinate(), small_coordinate()}; };
    if (family == 0) {
      for (auto& p : A) p = grid();
      for (auto& p : B) p = grid() + Vec3(0, 0, 2);
      v = grid();
    } else if (family == 1) {
      for (auto& p : A) p = grid() * 0.25;
      for (auto& p : B) {
        const Vec3 at = grid() * 0.25;
        p = at + Vec3{small_coordinate(), small_coordinate(), small_coordinate()} * 0x1p-20;
      }
      v = grid();
    } else if (family == 3) {
      // Everything in one plane: only the edge and vertex cells can be entered.
      const auto flat = [&] { return Vec3{small_coordinate(), small_coordinate(), 0.0}; };
      for (auto& p : A) p = flat();
      for (auto& p : B) p = flat() + Vec3(3, 0, 0);
      v = flat();
      if (k % 8 == 7) {  // points: only vertex-vertex cells exist
        A = {A[0], A[0], A[0]};
        B = {B[0], B[0], B[0]};
        const double along = small_coordinate();
        v = (A[0] - B[0]) * along + (k % 16 == 7 ? flat() : Vec3::Zero());
      }
    } else {
      const Vec3 ca{unit(rng), unit(rng), unit(rng)}, cb = ca + 3.0 * Vec3{unit(rng), unit(rng), unit(rng)};
      for (auto& p : A) p = ca + Vec3{unit(rng), unit(rng), unit(rng)};
      for (auto& p : B) p = cb + Vec3{unit(rng), unit(rng), unit(rng)};
      v = (ca - cb) + 0.5 * Vec3{unit(rng), unit(rng), unit(rng)};
    }
    check_case(A, B, v);
    if (::testing::Test::HasFatalFailure()) return;
    if (v != Vec3::Zero()) {
      const LineContact lc = line_contact(A, B, v);
      // The traversal's filter must keep every pair that meets, at its entry time's upper end.
      ASSERT_TRUE(sweep_pair_may_meet(A, B, v, std::numeric_limits<double>::infinity()) || !lc.hit);
      if (lc.hit) {
        ASSERT_TRUE(sweep_pair_may_meet(A, B, v, lc.t_in.hi)) << "case " << k;
      }
      hits += lc.hit;
      exact_paths += lc.exact_path;
      if (lc.hit) ++entry_kind[lc.in.kind];
    }
  }
  // The families are built so that both outcomes and both evaluation paths are exercised.
  EXPECT_GT(hits, n / 10);
  EXPECT_GT(exact_paths, n / 100);
  EXPECT_LT(exact_paths, n);
  std::printf("random cases: %zu, lines hitting: %zu, exact path taken: %zu\n", n, hits, exact_paths);
  std::printf("entry cell kinds (vertex-face, face-vertex, edge-edge, vertex-edge, edge-vertex, vertex-vertex):");
  for (std::size_t k : entry_kind) std::printf(" %zu", k);
  std::printf("\n");
  // Every kind of cell, including the degenerate ones, must be where some line enters.
  for (std::size_t k : entry_kind) EXPECT_GT(k, 0u);
}

}  // namespace
}  // namespace cdbench
