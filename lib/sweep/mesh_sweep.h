#pragma once
// The paper's dynamic collision query: the first contact of a translating mesh with a fixed one,
// exact. Both meshes carry a bounding-sphere hierarchy (with a box per node too); the traversal
// keeps the best contact time T so far, prunes node pairs whose spheres or boxes cannot meet before
// T (entry times computed in interval arithmetic, so a pruned pair provably cannot hold an earlier
// contact), visits node pairs best-first by entry time (one heap) and runs exact triangle sweeps at the
// leaves.
#include <cstdint>
#include <limits>
#include <vector>

#include "bvh/bvh.h"
#include "bvh/obb.h"
#include "bvh/sphere.h"
#include "core/triangle_mesh.h"
#include "sweep/triangle_sweep.h"

namespace cdbench {

// A sweep tree node's volume: its bounding sphere (the paper's), its axis-aligned box and an
// oriented box (principal axes; absent, half < 0, when the tree is built without). The exact
// traversal bounds a node pair's entry time by each (the latest of them): a long, thin triangle's
// sphere is far looser than its box, and a tilted one's axis-aligned box far looser than its
// oriented box (pinion: 16,000 node pairs per approach with the first two, 700 with all three).
// The float twin keeps the paper's spheres alone.
struct SweepVolume {
  Sphere sphere;
  Aabb box;
  Obb obb;
};

struct SweepMesh {
  std::vector<Vec3> vertices;
  std::vector<Face> faces;
  Bvh<SweepVolume> tree;  // one triangle per leaf unless built otherwise

  Triangle triangle(std::uint32_t f) const {
    return {vertices[faces[f][0]], vertices[faces[f][1]], vertices[faces[f][2]]};
  }
};

// oriented = false: no oriented boxes (the float twin's trees, which use spheres alone). By default
// split by surface area (fewer volumes visited beside a CAD part's long faces: certified pose sets
// 1-4 % fewer instructions, doc/performance.md, "Distance trees split by surface area"); the float
// pipeline passes its own options (median splits, as the paper's method builds them).
SweepMesh make_sweep_mesh(std::vector<Vec3> vertices, std::vector<Face> faces,
                          const BvhBuildOptions& options = {1, BvhSplit::surface_area},
                          bool oriented = true);

// The sweep mesh of a mover placed by (R, t), from its sweep mesh in its own coordinates (`own`,
// built once): vertices `placed` (the caller's fl(fl(R x) + t), each within `err` of R x + t for
// the stored R and t, MoverOrientation::transform_error), the same tree with every volume carried
// by x -> R x + t and grown to cover that and its own rounding (the spheres by a bound of |R|, so R
// need not be exactly orthonormal). O(nodes): no tree is rebuilt per orientation.
SweepMesh placed_sweep_mesh(const SweepMesh& own, const Eigen::Matrix3d& R, const Vec3& t, std::vector<Vec3> placed,
                            double err);

// The fixed surface's and a mover's sweep meshes, the mover's placed at the pose mover_t (for the
// rotation R: vertices fl(fl(R x) + mover_t)): pair traversals at another pose t of the same
// rotation may visit these instead of box trees, their oriented boxes pruning as well. The mover's
// points at t lie within transform_error(t) + transform_error(mover_t) (placement/mover.h) of those
// at mover_t moved by t - mover_t (both are fl(r + .) of the same r = fl(R x)), plus the rounding
// of that difference.
struct SweepTrees {
  const SweepMesh* fixed = nullptr;  // over F's faces (the same face ids)
  const SweepMesh* mover = nullptr;  // over the mover's faces
  Vec3 mover_t = Vec3::Zero();
};

// A mover node's oriented box of SweepTrees moved by D (a pose's t - mover_t, as computed) and
// grown by `pad` (the callers' shift pad: the two poses' transform errors and the rounding of D,
// taken in their rounding mode) plus the rounding of its moved centre (1e-15 of the magnitudes
// summed, any rounding mode).
inline Obb shifted_obb(const Obb& m, const Vec3& D, double pad) {
  Obb o = m;
  const Vec3 c = m.center;
  o.center = Vec3(c[0] + D[0], c[1] + D[1], c[2] + D[2]);
  o.pad = (o.pad + pad) + 1e-15 * (c.cwiseAbs().sum() + D.cwiseAbs().sum());
  return o;
}

// `m` moved by t as a pose places it: vertices fl(v + t) (bit for bit what place_point gives for
// rotated vertices v), the same tree with centres fl(c + t) and radii grown to cover the rounding
// of both (|fl(v+t) - fl(c+t)| <= |v - c| + u (|v+t| + |c+t|)). Costs a copy, not a rebuild.
SweepMesh translated_sweep_mesh(const SweepMesh& m, const Vec3& t);

struct MeshContact {
  bool hit = false;
  Interval t;  // encloses the exact first-contact time (a single double when it is one)
  std::uint32_t fixed_face = 0, moving_face = 0;  // a pair attaining it
  SweepCandidate candidate;                       // the cell of that pair's Minkowski difference
  // Work counters.
  std::uint64_t sphere_tests = 0, triangle_sweeps = 0, exact_fallbacks = 0;
};

// A lower bound of the first t at which the sphere `moving` translated by t v meets `fixed`
// (+inf when it never does), rigorous: interval arithmetic with outward rounding.
double sphere_entry_time_lower_bound(const Sphere& fixed, const Sphere& moving, const Vec3& v);
// The same for boxes: the latest of the three axes' entry times, +inf when some axis never overlaps
// or the axes' overlap intervals are disjoint.
double box_entry_time_lower_bound(const Aabb& fixed, const Aabb& moving, const Vec3& v);
// The same counting only times >= from (+inf when the boxes meet only before), for callers that
// already run under upward rounding (CGAL::Protect_FPU_rounding<true>) for a whole traversal.
double box_entry_time_lower_bound_upward(const Aabb& fixed, const Aabb& moving, const Vec3& v, double from);
// The entry time for oriented boxes, each the parallelepiped {centre + axes a : |a_k| <= half_k}
// (fit_obb contains its points in that sense whatever the axes' rounding): on any axis L the projections
// overlap on an interval of t; the latest entry over the 15 axes of the separating-axis theorem
// (both boxes' axes and their cross products), +inf when some axis never overlaps or the
// intervals are disjoint. Any axis gives a valid bound, so L is whatever the doubles give; the
// rounding of each projection is covered by a slack far above it. Any rounding mode.
// `from`: only times >= from count (+inf when the boxes meet only before).
double obb_entry_time_lower_bound(const Obb& fixed, const Obb& moving, const Vec3& v,
                                  double from = -std::numeric_limits<double>::infinity());
// A lower bound of the squared distance between two oriented boxes (read as above, pads
// included): the largest gap between their projections on the same 15 axes, over the axis' length.
// Any rounding mode.
double obb_squared_distance_lower_bound(const Obb& a, const Obb& b);

// Whether a pair traversal should still try the oriented boxes: they prune a large part of the
// pairs the boxes leave on long, tilted triangles (machined parts) and almost none on rounded
// nodes, where their 15 axes cost more than they save. Tried on a window of kTrial pairs the boxes
// leave; kept only when they pruned at least a quarter of them. Once off, tried again after
// kRetrial such pairs: the first pairs of a traversal are its largest nodes, where the oriented
// boxes rarely prune even on parts where the deeper pairs gain (pinion: 5-15 of the first 64,
// 18-28 of later windows; doc/performance.md). Only the work depends on it, and it depends only
// on the traversal's own order (deterministic).
struct ObbTrial {
  static constexpr int kTrial = 64;
  static constexpr int kRetrial = 2048;
  int tried = 0, pruned = 0, skipped = 0;
  bool on = true;
  bool failed = false;  // the last window judged pruned too few
  // A pair the boxes left, bounded with the oriented boxes: whether they pruned it.
  void record(bool did_prune) {
    ++tried;
    pruned += did_prune;
    if (tried != kTrial) return;
    failed = 4 * pruned < kTrial;
    on = !failed;
  }
  // Whether the oriented test paid by the traversal's end: the last window judged, and before any
  // was, yes (a window begun after a failed one counts as the failure).
  bool paid() const { return on && !failed; }
  // A pair the boxes left: whether to bound it with the oriented boxes too (while off, it counts
  // towards the next window).
  bool try_pair() {
    if (on) return true;
    skip();
    return false;
  }
  // A pair the boxes left while the oriented test is off.
  void skip() {
    if (++skipped < kRetrial) return;
    on = true;
    tried = pruned = skipped = 0;
  }
};

// A rigorous necessary condition, cheaper than the sweep, for triangles A and B + t v to meet at
// some t <= t_max (t_max = +inf: at any t): false only when they cannot. The exact traversal skips
// pairs for which it is false; their shadows on the plane normal to v are disjoint, or they could
// meet only after the best contact so far.
bool sweep_pair_may_meet(const Triangle& A, const Triangle& B, const Vec3& v, double t_max);

// The least t in R at which `moving` translated by t v touches `fixed`: the first contact of the
// mover coming from far away on the side of -v. v must be nonzero.
MeshContact first_contact_along_line(const SweepMesh& fixed, const SweepMesh& moving, const Vec3& v);

// The float twin of first_contact_along_line (the paper's float placement): the same sphere-tree
// traversal with sphere entry times and triangle sweeps (line_contact_float) in plain doubles, no
// exact fallback. Not rigorous (doc/float-pipeline.md); runs in the default rounding mode.
struct FloatMeshContact {
  bool hit = false;
  double t = 0.0;
  std::uint32_t fixed_face = 0, moving_face = 0;
  std::uint64_t sphere_tests = 0, triangle_sweeps = 0;
};
FloatMeshContact first_contact_along_line_float(const SweepMesh& fixed, const SweepMesh& moving, const Vec3& v);

// The same by exact sweeps of all triangle pairs (reference for tests).
MeshContact first_contact_brute_force(const SweepMesh& fixed, const SweepMesh& moving, const Vec3& v);

// The exact rational time of a contact found by either function.
mpq_class exact_contact_time(const SweepMesh& fixed, const SweepMesh& moving, const Vec3& v, const MeshContact& c);

}  // namespace cdbench
