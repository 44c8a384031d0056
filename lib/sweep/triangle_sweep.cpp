#include "sweep/triangle_sweep.h"

#include <CGAL/Interval_nt.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

#include "core/interval.h"

namespace cdbench {
namespace {

using I = CGAL::Interval_nt<false>;

template <class NT>
struct V3 {
  NT x, y, z;
};
template <class NT>
V3<NT> sub(const V3<NT>& a, const V3<NT>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class NT>
V3<NT> scale(const NT& s, const V3<NT>& a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class NT>
V3<NT> add(const V3<NT>& a, const V3<NT>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class NT>
NT dot(const V3<NT>& a, const V3<NT>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class NT>
V3<NT> cross(const V3<NT>& a, const V3<NT>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

// Signs. For intervals an undecidable sign throws CGAL::Uncertain_conversion_exception, which
// sends the whole computation to the exact path.
inline int sgn(const I& x) { return static_cast<int>(CGAL::sign(x).make_certain()); }
inline int sgn(const mpq_class& x) { return ::sgn(x); }
// Whether all components are zero; for intervals, false as soon as one is certainly nonzero.
inline bool all_zero(const V3<I>& a) {
  const auto excludes_zero = [](const I& x) { return x.inf() > 0.0 || x.sup() < 0.0; };
  if (excludes_zero(a.x) || excludes_zero(a.y) || excludes_zero(a.z)) return false;
  return sgn(a.x) == 0 && sgn(a.y) == 0 && sgn(a.z) == 0;
}
inline bool all_zero(const V3<mpq_class>& a) { return sgn(a.x) == 0 && sgn(a.y) == 0 && sgn(a.z) == 0; }
inline bool certainly_nonzero(const I& x) { return x.inf() > 0.0 || x.sup() < 0.0; }
inline bool certainly_nonzero(const mpq_class& x) { return sgn(x) != 0; }
// The float twin (line_contact_float): plain doubles, signs taken at face value.
inline int sgn(double x) { return (x > 0.0) - (x < 0.0); }
inline bool all_zero(const V3<double>& a) { return a.x == 0.0 && a.y == 0.0 && a.z == 0.0; }
inline bool certainly_nonzero(double x) { return x != 0.0; }

template <class NT>
V3<NT> lift(const Vec3& p) {
  return {NT(p.x()), NT(p.y()), NT(p.z())};
}

template <class NT>
struct Inputs {
  V3<NT> a[3], b[3], v;
  Inputs(const Triangle& A, const Triangle& B, const Vec3& vel) {
    for (int k = 0; k < 3; ++k) {
      a[k] = lift<NT>(A[k]);
      b[k] = lift<NT>(B[k]);
    }
    v = lift<NT>(vel);
  }
};

// Whether the point q = p0 + Q/den of the plane of (p0, p0 + e1, p0 + e2), with n = e1 x e2, lies
// in the closed triangle; Q is given premultiplied by den (den != 0) so no division is needed.
template <class NT>
bool in_triangle_scaled(const V3<NT>& Q, const NT& den, const V3<NT>& e1, const V3<NT>& e2, const V3<NT>& n) {
  const int s = sgn(den);
  const NT beta = dot(n, cross(Q, e2));   // den * beta * |n|^2
  if (s * sgn(beta) < 0) return false;
  const NT gamma = dot(n, cross(e1, Q));  // den * gamma * |n|^2
  if (s * sgn(gamma) < 0) return false;
  return s * sgn(den * dot(n, n) - beta - gamma) >= 0;
}

// Calls f(candidate, t) for every valid candidate time (or only for `only`, when given).
template <class NT, class F>
void for_each_candidate(const Inputs<NT>& in, const SweepCandidate* only, F&& f) {
  const auto wanted = [&](int kind, int i, int j) {
    return only == nullptr || (only->kind == kind && only->i == i && only->j == j);
  };
  const V3<NT>& v = in.v;
  // Kind 0: vertex j of B crosses the plane of A inside A.
  {
    const V3<NT> e1 = sub(in.a[1], in.a[0]), e2 = sub(in.a[2], in.a[0]);
    const V3<NT> n = cross(e1, e2);
    const NT den = dot(n, v);
    if (certainly_nonzero(den) || sgn(den) != 0) {
      for (int j = 0; j < 3; ++j) {
        if (!wanted(0, 0, j)) continue;
        const V3<NT> w = sub(in.b[j], in.a[0]);
        const NT num = -dot(n, w);
        const V3<NT> Q = add(scale(den, w), scale(num, v));
        if (in_triangle_scaled(Q, den, e1, e2, n)) f(SweepCandidate{0, 0, static_cast<std::uint8_t>(j)}, NT(num / den));
      }
    }
  }
  // Kind 1: vertex i of A is met by the plane of B inside B (a_i - t v in B).
  {
    const V3<NT> e1 = sub(in.b[1], in.b[0]), e2 = sub(in.b[2], in.b[0]);
    const V3<NT> n = cross(e1, e2);
    const NT den = dot(n, v);
    if (certainly_nonzero(den) || sgn(den) != 0) {
      for (int i = 0; i < 3; ++i) {
        if (!wanted(1, i, 0)) continue;
        const V3<NT> w = sub(in.a[i], in.b[0]);
        const NT num = dot(n, w);
        const V3<NT> Q = sub(scale(den, w), scale(num, v));
        if (in_triangle_scaled(Q, den, e1, e2, n)) f(SweepCandidate{1, static_cast<std::uint8_t>(i), 0}, NT(num / den));
      }
    }
  }
  // Kind 2: edge i of A and edge j of B cross: a_i + s d1 = b_j + u d2 + t v, s, u in [0, 1].
  for (int i = 0; i < 3; ++i) {
    const V3<NT> d1 = sub(in.a[(i + 1) % 3], in.a[i]);
    for (int j = 0; j < 3; ++j) {
      if (!wanted(2, i, j)) continue;
      const V3<NT> d2 = sub(in.b[(j + 1) % 3], in.b[j]);
      const V3<NT> d2xv = cross(d2, v);
      const NT det = dot(d1, d2xv);
      const int s = sgn(det);
      if (s == 0) continue;  // the cell's plane contains v: edge and vertex kinds cover it
      const V3<NT> w = sub(in.b[j], in.a[i]);
      const NT sN = dot(w, d2xv);
      if (s * sgn(sN) < 0 || s * sgn(det - sN) < 0) continue;
      const NT uN = -dot(d1, cross(w, v));
      if (s * sgn(uN) < 0 || s * sgn(det - uN) < 0) continue;
      const NT tN = -dot(d1, cross(d2, w));
      f(SweepCandidate{2, static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(j)}, NT(tN / det));
    }
  }
  // Kind 3: vertex i of A meets edge j of B on the line: w = a_i - b_j = t v + u d2.
  for (int j = 0; j < 3; ++j) {
    const V3<NT> d2 = sub(in.b[(j + 1) % 3], in.b[j]);
    const V3<NT> c = cross(v, d2);
    if (all_zero(c)) continue;  // parallel: vertex-vertex covers it
    const NT cc = dot(c, c);
    for (int i = 0; i < 3; ++i) {
      if (!wanted(3, i, j)) continue;
      const V3<NT> w = sub(in.a[i], in.b[j]);
      if (certainly_nonzero(dot(w, c)) || sgn(dot(w, c)) != 0) continue;  // not coplanar
      const NT uN = -dot(cross(w, v), c);
      if (sgn(uN) < 0 || sgn(cc - uN) < 0) continue;
      f(SweepCandidate{3, static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(j)}, NT(dot(cross(w, d2), c) / cc));
    }
  }
  // Kind 4: vertex j of B meets edge i of A: w = a_i - b_j = t v - s d1.
  for (int i = 0; i < 3; ++i) {
    const V3<NT> d1 = sub(in.a[(i + 1) % 3], in.a[i]);
    const V3<NT> c = cross(v, d1);
    if (all_zero(c)) continue;
    const NT cc = dot(c, c);
    for (int j = 0; j < 3; ++j) {
      if (!wanted(4, i, j)) continue;
      const V3<NT> w = sub(in.a[i], in.b[j]);
      if (certainly_nonzero(dot(w, c)) || sgn(dot(w, c)) != 0) continue;
      const NT sN = dot(cross(w, v), c);
      if (sgn(sN) < 0 || sgn(cc - sN) < 0) continue;
      f(SweepCandidate{4, static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(j)}, NT(dot(cross(w, d1), c) / cc));
    }
  }
  // Kind 5: vertex i of A and vertex j of B meet: a_i - b_j = t v.
  const NT vv = dot(v, v);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (!wanted(5, i, j)) continue;
      const V3<NT> w = sub(in.a[i], in.b[j]);
      if (!all_zero(cross(w, v))) continue;
      f(SweepCandidate{5, static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(j)}, NT(dot(w, v) / vv));
    }
  }
}

template <class NT>
struct Extremes {
  bool hit = false;
  NT t_in, t_out;
  SweepCandidate in, out;
};

template <class NT>
Extremes<NT> extremes(const Inputs<NT>& in) {
  Extremes<NT> e;
  for_each_candidate(in, nullptr, [&](const SweepCandidate& c, const NT& t) {
    if (!e.hit) {
      e.hit = true;
      e.t_in = e.t_out = t;
      e.in = e.out = c;
      return;
    }
    // Ties keep the first candidate in enumeration order (the exact value is the same).
    if (sgn(NT(t - e.t_in)) < 0) {
      e.t_in = t;
      e.in = c;
    }
    if (sgn(NT(t - e.t_out)) > 0) {
      e.t_out = t;
      e.out = c;
    }
  });
  return e;
}

}  // namespace

Interval enclose(const mpq_class& q) {
  const double d = q.get_d();  // truncates towards zero
  const int c = cmp(mpq_class(d), q);
  if (c == 0) return {d, d};
  if (c < 0) return {d, round_up(d)};
  return {round_down(d), d};
}

LineContact line_contact(const Triangle& A, const Triangle& B, const Vec3& v) {
  assert(v != Vec3::Zero());
  LineContact r;
  try {
    CGAL::Protect_FPU_rounding<true> guard;
    const Extremes<I> e = extremes(Inputs<I>(A, B, v));
    r.hit = e.hit;
    if (e.hit) {
      r.t_in = {e.t_in.inf(), e.t_in.sup()};
      r.t_out = {e.t_out.inf(), e.t_out.sup()};
      r.in = e.in;
      r.out = e.out;
    }
    return r;
  } catch (const CGAL::Uncertain_conversion_exception&) {
  }
  const Extremes<mpq_class> e = extremes(Inputs<mpq_class>(A, B, v));
  r.exact_path = true;
  r.hit = e.hit;
  if (e.hit) {
    r.t_in = enclose(e.t_in);
    r.t_out = enclose(e.t_out);
    r.in = e.in;
    r.out = e.out;
  }
  return r;
}

FloatLineContact line_contact_float(const Triangle& A, const Triangle& B, const Vec3& v) {
  const Extremes<double> e = extremes(Inputs<double>(A, B, v));
  FloatLineContact r;
  r.hit = e.hit;
  if (e.hit) {
    r.t_in = e.t_in;
    r.t_out = e.t_out;
  }
  return r;
}

mpq_class exact_candidate_time(const Triangle& A, const Triangle& B, const Vec3& v, const SweepCandidate& c) {
  mpq_class t;
  bool found = false;
  for_each_candidate(Inputs<mpq_class>(A, B, v), &c, [&](const SweepCandidate&, const mpq_class& time) {
    t = time;
    found = true;
  });
  assert(found && "exact_candidate_time: candidate is not valid for these inputs");
  (void)found;
  return t;
}

namespace {
// Sign of the exact value enclosed by `e` whose exact value is candidate c's time.
int sign_of_time(const Interval& e, const Triangle& A, const Triangle& B, const Vec3& v, const SweepCandidate& c) {
  if (e.lo > 0.0) return 1;
  if (e.hi < 0.0) return -1;
  if (e.lo == 0.0 && e.hi == 0.0) return 0;
  return sgn(exact_candidate_time(A, B, v, c));
}
}  // namespace

std::optional<mpq_class> first_contact_time(const Triangle& A, const Triangle& B, const Vec3& v) {
  if (v == Vec3::Zero()) {
    // Static test: the triangles intersect iff 0 lies in [t_in, t_out] along any line.
    const Vec3 u(1.0, 0.0, 0.0);
    const LineContact lc = line_contact(A, B, u);
    if (!lc.hit) return std::nullopt;
    if (sign_of_time(lc.t_in, A, B, u, lc.in) <= 0 && sign_of_time(lc.t_out, A, B, u, lc.out) >= 0)
      return mpq_class(0);
    return std::nullopt;
  }
  const LineContact lc = line_contact(A, B, v);
  if (!lc.hit) return std::nullopt;
  if (sign_of_time(lc.t_in, A, B, v, lc.in) >= 0) return exact_candidate_time(A, B, v, lc.in);
  if (sign_of_time(lc.t_out, A, B, v, lc.out) >= 0) return mpq_class(0);  // touching at t = 0
  return std::nullopt;
}

namespace {
// The geometric event a candidate's time solves for, as the point sets it depends on: kind 0, B's
// vertex j reaching the plane of A (A's three corners); kind 1, the plane of B reaching A's vertex
// i; kind 2, the lines of an edge of each; kinds 3 and 4, a vertex and the line of an edge; kind
// 5, two vertices. The exact time is a function of these sets alone (its formula, evaluated
// exactly, gives the one solution whatever the order of the corners or of an edge's ends), so two
// candidates with equal events have equal times.
struct Event {
  int kind = 0;
  std::array<Vec3, 3> a, b;  // the points, each side sorted; unused slots zero
};
bool point_less(const Vec3& p, const Vec3& q) {
  return std::lexicographical_compare(p.data(), p.data() + 3, q.data(), q.data() + 3);
}
template <std::size_t N>
std::array<Vec3, 3> sorted(const std::array<Vec3, N>& p) {
  std::array<Vec3, 3> r{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};  // Eigen leaves a default Vec3 unset
  std::copy(p.begin(), p.end(), r.begin());
  std::sort(r.begin(), r.begin() + N, point_less);
  return r;
}
std::array<Vec3, 2> edge(const Triangle& T, int i) { return {T[i], T[(i + 1) % 3]}; }
std::array<Vec3, 1> vertex(const Triangle& T, int i) { return {T[i]}; }
Event event_of(const SweepCandidate& c, const Triangle& A, const Triangle& B) {
  Event e;
  e.kind = c.kind;
  switch (c.kind) {
    case 0: e.a = sorted(A), e.b = sorted(vertex(B, c.j)); break;
    case 1: e.a = sorted(vertex(A, c.i)), e.b = sorted(B); break;
    case 2: e.a = sorted(edge(A, c.i)), e.b = sorted(edge(B, c.j)); break;
    case 3: e.a = sorted(vertex(A, c.i)), e.b = sorted(edge(B, c.j)); break;
    case 4: e.a = sorted(edge(A, c.i)), e.b = sorted(vertex(B, c.j)); break;
    default: e.a = sorted(vertex(A, c.i)), e.b = sorted(vertex(B, c.j)); break;
  }
  return e;
}
bool same_event(const Event& x, const Event& y) { return x.kind == y.kind && x.a == y.a && x.b == y.b; }
}  // namespace

int compare_entry_times(const LineContact& c1, const Triangle& A1, const Triangle& B1, const Vec3& v1,
                        const LineContact& c2, const Triangle& A2, const Triangle& B2, const Vec3& v2) {
  if (c1.t_in.hi < c2.t_in.lo) return -1;
  if (c2.t_in.hi < c1.t_in.lo) return 1;
  if (c1.t_in.lo == c1.t_in.hi && c2.t_in.lo == c2.t_in.hi) return 0;  // both exact doubles, equal
  // One event seen from two triangle pairs (a vertex or an edge shared by neighbouring faces: the
  // usual tie of a first contact) needs no rationals.
  if (v1 == v2 && same_event(event_of(c1.in, A1, B1), event_of(c2.in, A2, B2))) return 0;
  return cmp(exact_candidate_time(A1, B1, v1, c1.in), exact_candidate_time(A2, B2, v2, c2.in));
}

}  // namespace cdbench
