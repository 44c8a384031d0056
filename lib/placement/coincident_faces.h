#pragma once
// Mover faces placed onto faces of F, exactly or up to rounding. Where the placed corners of a mover
// face, as computed (fl(fl(R x) + t), the placement every certificate bounds before it widens for
// the transform's rounding), lie within e of the three corners of one of F's faces, every point of
// the face lies within e of that triangle of F (a convex combination of the corners, each moved by
// at most e), so |s| <= e there, as s is 1-Lipschitz and 0 on F: a cell of it is settled at
// [-e, e] without a distance query (e = 0 for the exact corners). A part against itself at the
// identity, a copy turned by a signed permutation, stacked parts sharing a face (exact); a copy
// turned by R and placed back by R^T, whose corners come back a few ulps off (up to rounding): the
// branch and bound otherwise splits each such face towards the tolerance (armadillo x16 against
// itself at the identity, or against a turned copy placed back, ran out of its 400,000 cells).
// Recognition only chooses which valid bound a cell gets (doc/poses.md, "Faces placed onto F's
// faces").
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "bvh/bvh.h"
#include "core/aabb.h"
#include "core/pose_transform.h"
#include "core/triangle_mesh.h"
#include "distance/signed_distance.h"

namespace cdbench {

class CoincidentFaces {
 public:
  // radius: how far a placed corner may lie from F's vertex to be matched with it; by default
  // (negative) 2^-40 of F's largest coordinate magnitude, thousands of ulps (a turned copy placed
  // back lands within a few), far below any tolerance. It only steers: the bound e is computed from
  // the corners matched.
  explicit CoincidentFaces(const TriangleMesh& fixed, double radius = -1.0);
  double radius() const { return radius_; }
  // A rigorous upper bound e of the largest distance from a corner of abc (in any order) to the
  // vertex of F it is matched with, where the three matched vertices form one of F's faces and
  // each lies within radius() of its corner (then every point of abc lies within e of F); 0 when
  // the corners are those of one of F's faces exactly (-0 and +0 alike); negative for none.
  double match(const Vec3& a, const Vec3& b, const Vec3& c) const;
  // Whether abc is one of F's faces, corner for corner in exact coordinates.
  bool contains(const Vec3& a, const Vec3& b, const Vec3& c) const { return match(a, b, c) == 0.0; }
  // Whether any of the n vertices placed by P may lie within radius() of a vertex of F: without
  // one no face can be matched, and the search skips every lookup (a pose of unknown status
  // seldom places one: the scan, a bit test a vertex in a filter of the grid's cells, costs a few
  // per cent of a certificate's cells).
  bool any_vertex(const PlacedView& P, std::size_t n) const;

 private:
  struct Key {
    std::uint64_t x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const;
  };
  // The grid cell (side 64 radius()) holding p, false where p is too far out to be numbered (none
  // of F's vertices is near it).
  bool cell_of(const Vec3& p, Key* k) const;
  // The two bits of the filter (below) a cell sets.
  std::array<std::size_t, 2> filter_slots(const Key& k) const;
  bool in_filter(const Key& k) const;
  // Up to max of F's vertices within radius() of p (each listed once, by its first index among
  // those with its coordinates), among the first 64 entries of p's cell; returns how many.
  int near_vertices(const Vec3& p, std::uint32_t* out, int max) const;
  double radius_ = 0.0, inv_side_ = 1.0;
  const std::vector<Vec3>* vertices_;
  // F's distinct vertices by grid cell: each in every cell that meets the cube of half side
  // radius() (a little more) about it, as a list through Entry::next (head_: a cell's first entry).
  struct Entry {
    std::uint32_t vertex, next;
  };
  std::unordered_map<Key, std::uint32_t, KeyHash> head_;
  std::vector<Entry> entries_;
  // Whether F has a face with the corners a, b, c (as near_vertices() numbers them, any order).
  bool has_face(std::uint32_t a, std::uint32_t b, std::uint32_t c) const;
  // F's faces with their corners so numbered, and the faces about each such vertex (CSR: those
  // of vertex v are about_[about_first_[v] .. about_first_[v + 1])).
  std::vector<std::array<std::uint32_t, 3>> corners_;
  std::vector<std::uint32_t> about_first_, about_;
  // A Bloom filter of the grid's occupied cells (two bits from each key's hash, at least 16 bits an
  // entry): a placed vertex whose cell has a bit clear is near none of F's.
  std::vector<std::uint64_t> filter_;
  std::size_t filter_mask_ = 0;
};

// F's faces indexed for matches within a wider radius, built on first use (thread-safe): a
// certificate that ran out of cells asks for it (ClearanceOptions::coincident_retry); most runs never
// do, and the index of armadillo x16 costs tenths of a second and tens of MB.
class LazyCoincidentFaces {
 public:
  LazyCoincidentFaces(const TriangleMesh& fixed, double radius) : fixed_(fixed), radius_(radius) {}
  const CoincidentFaces& get() const;

 private:
  const TriangleMesh& fixed_;
  double radius_;
  mutable std::once_flag once_;
  mutable std::unique_ptr<CoincidentFaces> index_;
};

// match() of a placed mover's faces and of the nodes of its box tree (a node's: the largest over
// its faces, negative once one has none), each computed once for the placement. A node's walk
// stops at its first unmatched face, and the search asks about nested nodes: unmemoised, a partly
// coincident mover cost O(n log n) lookups. The tree's depth bounds the recursion (median splits).
class PlacedMatches {
 public:
  PlacedMatches(const CoincidentFaces& index, const Bvh<Aabb>& boxes, const std::vector<Face>& faces,
                const PlacedView& P);
  double node(std::uint32_t n);
  double face(std::uint32_t f);

 private:
  const CoincidentFaces& index_;
  const Bvh<Aabb>& boxes_;
  const std::vector<Face>& faces_;
  const PlacedView& P_;
  std::vector<double> node_, face_;  // NaN: not computed yet
};

// Whether a match up to e settles a cell of a search that ends at `tolerance` wide: [-e, e] must
// leave it room to end (a cell's lower end at most half the tolerance below the upper end), else
// the split cells would be settled at -e again and again (a tolerance near the doubles' resolution).
inline bool match_settles(double e, double tolerance) { return e == 0.0 || (e > 0.0 && e <= 0.25 * tolerance); }
// F's triangles that may meet the relative interior of the triangle abc (exact predicates on the
// doubles): every triangle of F that meets the open triangle is listed (a certified superset).
// Dropped are those apart from abc, those whose plane supports abc (abc on one closed side, not
// in it: they meet abc at most in the corners or the edge in that plane), and those abc's plane
// supports with only corners of abc in it. A mover face hinged on an edge of F from outside (it
// coincides with F but for a vertex pushed out) lists only the triangles about its two ends that
// it straddles. False (out partial) for a degenerate abc or more than max_count triangles.
bool triangles_meeting_interior(const SignedDistance& fixed, const Vec3& a, const Vec3& b, const Vec3& c,
                                std::size_t max_count, std::vector<std::uint32_t>& out);

}  // namespace cdbench
