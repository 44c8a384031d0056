#pragma once
// Certificate (c) of an offset mesh S_d with band eps: no point with s < d - eps lies outside S_d
// and no point with s > d + eps lies inside it, so no component of the level set is missing.
// See doc/offsets.md for the argument (components of the sub/superlevel sets, their extrema, and
// a branch and bound that proves where s has no critical point).
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "distance/signed_distance.h"

namespace cdbench {

class CompletenessPrefetch;

struct CompletenessOptions {
  std::uint64_t max_cells = 20000000;  // cells evaluated in all, never exceeded; beyond it: not complete
  double min_cell_relative = 1e-7;  // cells smaller than this x diagonal are reported unresolved
  // Search one side only where one point per component of the solid's interior (or exterior)
  // settles the other (doc/offsets.md); false: both sides everywhere (tests, A/B).
  bool one_sided = true;
  // The search's domain is the input's box grown by max(d, 0) + max(eps, band_bound) + 1e-3 x its
  // diagonal: a caller that searches several candidates of one level (bands up to a tolerance)
  // passes that tolerance, so that every search, and a prefetch, cuts the same cells.
  double band_bound = 0.0;
  // Facts about F computed ahead for this level (null: none); used when its level and domain are
  // this search's. The results are the same with or without it.
  const CompletenessPrefetch* prefetch = nullptr;
};

struct CompletenessResult {
  bool complete = false;             // certified
  std::vector<Vec3> missed;          // points certainly in {s < d - eps} outside S_d, or {s > d + eps} inside it
  std::vector<Vec3> unresolved;      // centres of cells that could not be classified
  std::uint64_t cells = 0;
  bool budget_exhausted = false;    // stopped by max_cells (then `unresolved` says where)
  bool resumed = false;             // resume_completeness took the first search up (not a fresh one)
  std::uint64_t prefetched = 0;     // cells whose facts about F came from options.prefetch
  // The domain's volume and the part of it that discarded cells cover (a resumed search counts the
  // first search's leaves it keeps): equal, up to rounding, when the search is complete. A check
  // of the tiling for tests.
  double domain_volume = 0.0, discarded_volume = 0.0;
  double seconds = 0.0;
};

// What certify_completeness leaves, when it stops at missed cells, for resume_completeness: the
// cells it had not examined, S_d as it was searched, the sides searched. Opaque; moved from.
struct CompletenessCheckpoint {
  CompletenessCheckpoint();
  ~CompletenessCheckpoint();
  CompletenessCheckpoint(CompletenessCheckpoint&&) noexcept;
  CompletenessCheckpoint& operator=(CompletenessCheckpoint&&) noexcept;
  struct State;
  std::unique_ptr<State> state;  // null: nothing to resume
};

// The facts about F alone of a level's search cells (the enclosure of the distance to F, the side,
// rule (3)'s verdict), computed ahead of the search: while the mesher makes a candidate on one
// thread, the others extend this tree breadth first; every search of the level (each candidate, a
// resumed search) then takes those facts from it. They are the values the search would compute
// itself, so its cells, verdicts and results are the same however far the prefetch got
// (doc/offsets.md, "The search's part about F ahead"). Which cells it expands is a guess (the
// one-sided search, a band near band_bound, the cells near the level); only reuse depends on it.
class CompletenessPrefetch {
 public:
  // For level d of `sdf` (kept by reference) and candidates' bands up to band_bound; at most
  // max_cells cells (about 40 bytes each).
  CompletenessPrefetch(const SignedDistance& sdf, double d, double band_bound, std::uint64_t max_cells = 16000000);
  ~CompletenessPrefetch();
  CompletenessPrefetch(const CompletenessPrefetch&) = delete;
  CompletenessPrefetch& operator=(const CompletenessPrefetch&) = delete;
  // Extends the tree until `stop` is set (checked per cell), it is finished, or it is full; on all
  // threads the caller's arena lends it. Not concurrently with itself or with a search using it.
  void run(const std::atomic<bool>& stop);
  std::uint64_t cells() const;  // cells whose facts are known
  bool finished() const;        // nothing left to expand (or full)

  struct State;
  std::unique_ptr<State> state;
};

// " (cell budget reached after N cells)" when the search stopped at its budget, else "": the same
// words wherever an incomplete search is reported.
std::string budget_note(const CompletenessResult& r);

// An upper bound of w.(p - c) over the points p of the closed triangle (a, b, q) within rho of c,
// for a unit w (up to rounding): the smaller of the vertex bound and the bound over the disc where
// the triangle's plane meets the ball (-inf when the ball misses the plane). Rigorous in doubles.
// Used by the search's no-critical-point test: only the parts of long triangles near a cell can hold
// its nearest points.
double max_towards(const Vec3& w, const Vec3& c, double rho, const Vec3& a, const Vec3& b, const Vec3& q);

// Whether s has no local extremum in `cell` (rule (3) of the search): the cell avoids F and lies on
// its side `sign` (+1 outside, -1 inside), c is the cell's centre and `radius` >= |s(c)| + 2r, r the
// cell's covering radius about c (so every nearest point of a point of the cell lies within
// radius of c). True when a direction w is proven along which the distance to F strictly increases
// at every point of the cell (`*direction`, if given, receives it). `ids` is scratch space.
bool no_critical_point(const SignedDistance& sdf, const Aabb& cell, const Vec3& c, double radius, double sign,
                       std::vector<std::uint32_t>& ids, Vec3* direction = nullptr);

// The proof behind no_critical_point for a given unit direction w: `ids` must list every triangle
// within radius of c (no_critical_point leaves out, on large meshes, triangles whose tree box lies
// wholly behind the cell along w by more than this test's margin: they pass its first test
// anyway). True when w.(x - p) > 0 is proven for every point x of the cell and every point p of
// those triangles that can be nearest to x from the side `sign` (doc/offsets.md,
// rule (3): the disc bound, or the faces' normals and the vertices).
bool increases_along(const SignedDistance& sdf, const Aabb& cell, const Vec3& c, double radius, double sign,
                     const Vec3& w, const std::vector<std::uint32_t>& ids);

// `offset` must be a validated closed surface (it may be empty: then every point is outside it).
// `checkpoint` (optional) receives what a search stopped by missed cells leaves (else it is emptied).
CompletenessResult certify_completeness(const SignedDistance& sdf, const TriangleMesh& offset, double d, double eps,
                                        const CompletenessOptions& options = {},
                                        CompletenessCheckpoint* checkpoint = nullptr);

// The same certificate for `offset` = the surface `checkpoint`'s search was given plus `added`
// (closed components disjoint from it: the union validated unchanged) with band eps (at least the
// first search's): that search taken up where it stopped, with only the cells near the added parts
// examined again (doc/offsets.md, "Resuming the search"). A fresh search when it cannot be taken
// up (no checkpoint, another level, a narrower band). Consumes the checkpoint.
CompletenessResult resume_completeness(const SignedDistance& sdf, const TriangleMesh& offset,
                                       const TriangleMesh& added, double d, double eps,
                                       CompletenessCheckpoint& checkpoint, const CompletenessOptions& options = {});

}  // namespace cdbench
