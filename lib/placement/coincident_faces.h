#pragma once
// Mover faces placed exactly onto faces of F. Where the placed corners of a mover face, as computed
// (fl(fl(R x) + t), the placement every certificate bounds before it widens for the transform's
// rounding), are the three corners of one of F's faces, the face is that triangle of F: every point
// of it lies on F, so s = 0 there exactly, and a cell of it is settled at [0, 0] without a distance
// query. A part against itself at the identity, a copy turned by a signed permutation that maps its
// vertices onto themselves, stacked parts sharing a face: the branch and bound otherwise splits
// each such face towards the tolerance (armadillo x16 against itself at the identity ran out of
// its 400,000 cells). Recognition only chooses which valid bound a cell gets (doc/poses.md, "Faces
// placed onto F's faces").
#include <array>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "bvh/bvh.h"
#include "core/aabb.h"
#include "core/pose_transform.h"
#include "core/triangle_mesh.h"
#include "distance/signed_distance.h"

namespace cdbench {

class CoincidentFaces {
 public:
  explicit CoincidentFaces(const TriangleMesh& fixed);
  // Whether the triangle with corners a, b, c (in any order) is one of F's faces, corner for corner
  // in exact coordinates (-0 and +0 alike).
  bool contains(const Vec3& a, const Vec3& b, const Vec3& c) const;
  // Whether any of the n vertices placed by P is a vertex of F: without one no face can be one of
  // F's, and the search skips every lookup (a pose of unknown status seldom places one: the scan,
  // a bit test a vertex in a filter of F's vertices, costs a few per cent of a certificate's cells).
  bool any_vertex(const PlacedView& P, std::size_t n) const;

 private:
  struct Key {
    std::uint64_t x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const;
  };
  static Key key_of(const Vec3& p);
  // The two bits of the filter (below) a key sets.
  std::array<std::size_t, 2> filter_slots(const Key& k) const;
  // F's vertices by coordinates (the first of any that share them) and its faces by their sorted
  // vertices so numbered.
  std::unordered_map<Key, std::uint32_t, KeyHash> vertex_;
  std::unordered_set<Key, KeyHash> faces_;
  // A Bloom filter of F's vertices' keys (two bits from each key's hash, at least 16 bits a
  // vertex): a placed vertex with a bit clear is none of F's.
  std::vector<std::uint64_t> filter_;
  std::size_t filter_mask_ = 0;
};

// Whether every face under node n of the mover's box tree, placed by P, is one of F's faces (stops
// at the first that is not).
bool faces_on_f(const CoincidentFaces& index, const Bvh<Aabb>& boxes, const std::vector<Face>& faces,
                const PlacedView& P, std::uint32_t n);
// Whether the mover face f, placed by P, is one of F's faces.
inline bool face_on_f(const CoincidentFaces& index, const std::vector<Face>& faces, const PlacedView& P,
                      std::uint32_t f) {
  const Face& x = faces[f];
  return index.contains(P[x[0]], P[x[1]], P[x[2]]);
}

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
