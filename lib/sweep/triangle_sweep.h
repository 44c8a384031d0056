#pragma once
// Exact time of first contact between a fixed triangle A and a triangle B translating with
// constant velocity v (B(t) = B + t v), for the exact real geometry given by the doubles.
//
// Contact at time t means t v lies in the Minkowski difference M = A - B, a convex polytope; the
// line t v meets it in one interval [t_in, t_out]. Every point of M lies in a cell of one of six
// kinds (the sums of faces of A and -B whose dimensions add up to at most 2): vertex of B in face
// of A, vertex of A in face of B, edge-edge, vertex of A on an edge of B, vertex of B on an edge
// of A, vertex-vertex. The line enters M through such a cell, either crossing its plane (the first
// three kinds) or, when it runs inside that plane, through an edge (next two) or a vertex (last).
// Each candidate time is a rational function of the inputs; t_in and t_out are the least and the
// greatest valid candidate. See doc/sweep.md for the argument.
//
// Evaluation is filtered: the candidates are computed in interval arithmetic (CGAL::Interval_nt
// with outward rounding) and recomputed with GMP rationals only when a decision is uncertain (a
// sign or an ordering that the intervals cannot settle) -- the same code, instantiated twice.
#include <gmpxx.h>

#include <array>
#include <cstdint>
#include <optional>

#include "core/interval.h"
#include "core/triangle_mesh.h"

namespace cdbench {

using Triangle = std::array<Vec3, 3>;

// Which cell of the Minkowski difference produced a candidate time; enough to recompute it exactly.
struct SweepCandidate {
  std::uint8_t kind = 0;  // 0: vertex j of B in face A; 1: vertex i of A in face B; 2: edge i of A x edge j of B;
                          // 3: vertex i of A on edge j of B; 4: vertex j of B on edge i of A; 5: vertices i, j
  std::uint8_t i = 0, j = 0;
  bool operator==(const SweepCandidate& o) const { return kind == o.kind && i == o.i && j == o.j; }
};

// The interval of times at which the triangles touch, as double enclosures of exact rationals plus
// the candidates that attain them (exact values on demand with exact_candidate_time).
struct LineContact {
  bool hit = false;
  Interval t_in, t_out;  // enclosures: t_in.lo <= exact t_in <= t_in.hi (a single double when exact)
  SweepCandidate in, out;
  bool exact_path = false;  // the interval filter failed and rationals decided (for statistics)
};

// All t in R (not only t >= 0) at which A and B + t v intersect. v must be nonzero.
LineContact line_contact(const Triangle& A, const Triangle& B, const Vec3& v);

// The float twin of line_contact, as the paper's pipeline computes it: the same candidates in
// plain doubles (round to nearest; the caller must not have changed the rounding mode), signs
// taken at face value, no exact fallback. Not rigorous: near degenerate configurations (a
// direction almost in a cell's plane, a candidate on a cell boundary) a candidate can be
// wrongly kept or dropped; tests compare it with line_contact on random and degenerate pairs.
struct FloatLineContact {
  bool hit = false;
  double t_in = 0.0, t_out = 0.0;
};
FloatLineContact line_contact_float(const Triangle& A, const Triangle& B, const Vec3& v);

// The exact rational time of one candidate (the candidate must be valid for these inputs).
mpq_class exact_candidate_time(const Triangle& A, const Triangle& B, const Vec3& v, const SweepCandidate& c);

// Exact first contact time min{t >= 0 : A and B + t v intersect}; nullopt when they never touch.
// Handles contact at t = 0 (returns 0) and zero motion (0 if they intersect, else nullopt).
std::optional<mpq_class> first_contact_time(const Triangle& A, const Triangle& B, const Vec3& v);

// Exact comparison of the entry times of two contacts (each from line_contact on its own inputs):
// negative, zero or positive as t_in(first) <, =, > t_in(second). Uses the enclosures when they
// decide and the exact rationals otherwise.
int compare_entry_times(const LineContact& c1, const Triangle& A1, const Triangle& B1, const Vec3& v1,
                        const LineContact& c2, const Triangle& A2, const Triangle& B2, const Vec3& v2);

// Double enclosure [lo, hi] of a rational (lo, hi adjacent doubles or equal).
Interval enclose(const mpq_class& q);

}  // namespace cdbench
