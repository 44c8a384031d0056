#include "placement/advance.h"

#include <CGAL/Interval_nt.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/interval.h"
#include "distance/deep_cover.h"
#include "distance/point_triangle_distance.h"
#include "distance/triangle_distance.h"
#include "sweep/mesh_sweep.h"
#include "util/thread_scratch.h"

namespace cdbench {
namespace {

// The transform's rounding at the pose t and at any pose an advance of at most h_max reaches:
// |t'_k| <= |t_k| + h_max |d_k| + slack.
struct AdvanceRounding {
  double at_t, farthest;
};
AdvanceRounding advance_rounding(const MoverOrientation& o, const Vec3& t, const Vec3& d, double slack, double h_max) {
  Vec3 far_t;
  for (int k = 0; k < 3; ++k) far_t[k] = std::abs(t[k]) + 1.001 * h_max * std::abs(d[k]) + slack;
  return {o.transform_error(t), o.transform_error(far_t)};
}

// The pair traversal: node pairs in order of the time their boxes (the fixed one grown by `reach`)
// can first meet, pruned at the least pair bound so far. Runs under upward rounding (the box times
// are interval computations); the mover's vertices are placed in round-to-nearest, as everywhere.
struct AdvancePolicy {
  const TriangleMesh& F;
  const std::vector<TrianglePlane>& planes;
  const MoverOrientation& o;
  const Vec3& t;
  Vec3 v;        // the motion per unit of advance: -d
  double reach;  // target + margins, rounded up
  double best;   // the least bound so far (starts at h_max)
  std::int64_t best_f = -1, best_m = -1;
  Vec3 D = Vec3::Zero();  // with sweep trees: t - mover_t and its pad (MoverOrientation::shift_from)
  double shift_pad = 0.0;
  ObbTrial trial = ObbTrial();

  // Under upward rounding: lo - x rounded down is -((-lo) + x).
  double bound(const Aabb& f, const Aabb& m) const {
    Aabb n;
    for (int k = 0; k < 3; ++k) {
      n.lo[k] = -(-m.lo[k] - t[k]);  // contains fl(p + t) for p in m (round-to-nearest is monotone)
      n.hi[k] = m.hi[k] + t[k];
    }
    return placed_bound(f, n);
  }

  // The sweep trees' volumes (SweepTrees): the mover's hold its points placed at mover_t; at the
  // pose t they lie within shift_pad of them moved by D = t - mover_t. The box bound, then (while
  // ObbTrial keeps it) the oriented boxes' entry time, each box padded by reach and the mover's
  // also by shift_pad and its moved centre's rounding: the later of the two.
  double bound(const SweepVolume& f, const SweepVolume& m) {
    Aabb n;
    for (int k = 0; k < 3; ++k) {
      n.lo[k] = -((-m.box.lo[k] - D[k]) + shift_pad);
      n.hi[k] = (m.box.hi[k] + D[k]) + shift_pad;
    }
    const double box = placed_bound(f.box, n);
    if (!(box < best) || f.obb.half[0] < 0.0 || m.obb.half[0] < 0.0) return box;
    if (!trial.try_pair()) return box;
    Obb g = f.obb;
    g.pad = g.pad + reach;
    const Obb o = shifted_obb(m.obb, D, shift_pad);
    const double oriented = obb_entry_time_lower_bound(g, o, v, 0.0);
    trial.record(!(oriented < best));
    return std::max(box, oriented);
  }
  bool split_first(const SweepVolume& f, const SweepVolume& m) const { return split_first(f.box, m.box); }

  // f: a fixed node's box; n: a mover node's box at the pose t (it holds the placed points).
  double placed_bound(const Aabb& f, const Aabb& n) const {
    Aabb g;
    for (int k = 0; k < 3; ++k) {
      g.lo[k] = -(-f.lo[k] + reach);
      g.hi[k] = f.hi[k] + reach;
    }
    const double box = box_entry_time_lower_bound_upward(g, n, v, 0.0);
    if (!(box < best)) return box;
    // Growing a box by reach per axis reaches sqrt(3) reach at its corners; the boxes' Euclidean
    // distance now, less reach, bounds the time too (|v| <= 1 + 2u; the distance changes at most
    // that fast). Under upward rounding: sqrt rounds up (the factor covers it), reach - x rounds
    // up, so its negation is a lower bound.
    const double s = std::sqrt(squared_distance_lower_bound(f, n)) * (1.0 - 4e-15);
    const double now = -(reach - s);
    return std::max(box, now * (1.0 - 1e-15));
  }
  double prune_bound() const { return best; }
  bool split_first(const Aabb& f, const Aabb& m) const { return f.extent().squaredNorm() >= m.extent().squaredNorm(); }
  void leaf(std::uint32_t fi, std::uint32_t mi) {
    const Face& a = F.faces[fi];
    const Face& b = (*o.faces)[mi];
    const Vec3 &A0 = F.vertices[a[0]], &A1 = F.vertices[a[1]], &A2 = F.vertices[a[2]];
    Vec3 B0, B1, B2;
    {
      CGAL::Protect_FPU_rounding<true> nearest(CGAL_FE_TONEAREST);
      const PlacedView P = o.placed_view(t);
      B0 = P[b[0]];
      B1 = P[b[1]];
      B2 = P[b[2]];
    }
    // First along the fixed triangle's stored plane (cheap; the nearest direction of a face
    // contact), then along the estimated closest-point direction; both are lower bounds.
    double s = plane_pair_reach_time_lower_bound(planes[fi], B0, B1, B2, v, reach);
    if (!(s < best)) return;
    // The mover triangle's plane against the fixed one (A moves by -v relative to it).
    s = std::max(s, plane_pair_reach_time_lower_bound(make_triangle_plane(B0, B1, B2), A0, A1, A2, -v, reach));
    if (!(s < best)) return;
    Vec3 p, q;
    const double e2 = triangle_triangle_closest_points(A0, A1, A2, B0, B1, B2, &p, &q);
    if (e2 > 0.0) s = std::max(s, triangle_reach_time_lower_bound(A0, A1, A2, B0, B1, B2, q - p, v, reach));
    if (s < best) {
      best = s;
      best_f = fi;
      best_m = mi;
    }
  }
  bool done() const { return !(best > 0.0); }
};

}  // namespace

SeparatedAdvance separated_advance(const SignedDistance& fixed, const MoverOrientation& orientation, const Vec3& t,
                                   const Vec3& d, double target, double slack, double h_max,
                                   std::int64_t hint_fixed, std::int64_t hint_mover, const SweepTrees* trees) {
  SeparatedAdvance r;
  if (!(h_max > 0.0)) return r;
  const AdvanceRounding rounding = advance_rounding(orientation, t, d, slack, h_max);
  const double margin = slack + rounding.at_t + rounding.farthest;
  const double reach = round_up(target + margin);
  CGAL::Protect_FPU_rounding<true> guard;
  AdvancePolicy policy{fixed.mesh(), fixed.planes(), orientation, t, -d, reach, h_max};
  if (hint_fixed >= 0 && hint_mover >= 0 && static_cast<std::size_t>(hint_fixed) < fixed.mesh().faces.size() &&
      static_cast<std::size_t>(hint_mover) < orientation.faces->size())
    policy.leaf(static_cast<std::uint32_t>(hint_fixed), static_cast<std::uint32_t>(hint_mover));
  if (trees && trees->fixed && trees->mover) {
    const MoverOrientation::Shift shift = orientation.shift_from(trees->mover_t, t);
    policy.D = shift.D;
    policy.shift_pad = shift.pad;
    if (!policy.done()) traverse_pairs_nearest_first(trees->fixed->tree, trees->mover->tree, policy);
    r.oriented_paid = policy.trial.paid();
  } else if (!policy.done()) {
    traverse_pairs_nearest_first(fixed.tree(), orientation.boxes, policy);
  }
  r.h = std::max(0.0, std::min(policy.best, h_max));
  r.fixed_face = policy.best_f;
  r.mover_face = policy.best_m;
  return r;
}

namespace {

// The mover's box tree walked best-first with F's planes (HalfspacePolicy): a node's bound is the
// planes' bound over its translated box's 8 corners (the box holds the node's placed triangles,
// rounding to nearest being monotone), a leaf's over its placed triangle. Minimised: the bound's
// value at mu = 0 (`step` false) or the step it allows towards the target (`step` true).
struct HalfspacePolicy {
  const SupportPlanes& S;
  const MoverOrientation& o;
  const PlacedView P;
  const Vec3& t;
  const Vec3& d;
  bool step;
  double target, margin, best;
  HalfspaceMinimum out;
  HalfspaceSeeds* seeds = nullptr;

  // The step a bound allows: s >= lower - mu rate - margin stays above the target while
  // mu < (lower - margin - target) / rate, rounded down; 0 when it is not above it now.
  double allowed(const HalfspaceBound& b) const {
    const double room = round_down(round_down(b.lower - margin) - target);
    if (!(room > 0.0)) return 0.0;
    return b.rate > 0.0 ? round_down(room / b.rate) : HUGE_VAL;
  }
  // With the mover's sweep tree (SweepTrees): its volumes hold the placed points at mover_t; at t
  // they lie within shift_pad of them moved by D = t - mover_t (MoverOrientation::shift_from).
  Vec3 D = Vec3::Zero();
  double shift_pad = 0.0;
  // The planes the best triangle so far weighted: members of every node's program from then on
  // (a node's box has no column generation, and the planes highest at its centre need not be those
  // active where it is deepest: a long node across a faceted rod).
  HalfspaceSeed node_seed{};

  double key(const HalfspaceBound& b) const { return step ? allowed(b) : b.lower; }
  double bound(const Aabb& box) const {
    std::array<Vec3, 8> c;
    for (int k = 0; k < 8; ++k)
      for (int a = 0; a < 3; ++a) c[k][a] = ((k >> a) & 1 ? box.hi[a] : box.lo[a]) + t[a];
    HalfspaceSeed seed = node_seed;
    return key(halfspace_bound(S, c.data(), 8, d, 6, &seed));
  }
  // A sweep-tree node: the planes' bound over its oriented box moved by D, a parallelepiped whose
  // 8 corners are computed; every point it holds lies within `far` of their hull (below), and s is
  // 1-Lipschitz, so the hull's bound less `far` holds for them (the rate is unchanged). A long,
  // tilted node's axis-aligned box has corners far from its triangles (a rotated rod: 81 % of its
  // poses' instructions were this walk on the box tree; doc/poses.md, "Supporting planes").
  double bound(const SweepVolume& v) const {
    std::array<Vec3, 8> c;
    const Obb o = shifted_obb(v.obb, D, shift_pad);
    std::array<Vec3, 3> h;
    double magnitude = std::abs(o.center[0]) + std::abs(o.center[1]) + std::abs(o.center[2]);
    for (int k = 0; k < 3; ++k) {
      h[k] = o.half[k] * o.axes.col(k);
      magnitude += std::abs(h[k][0]) + std::abs(h[k][1]) + std::abs(h[k][2]);
    }
    for (int k = 0; k < 8; ++k)
      for (int a = 0; a < 3; ++a)
        c[k][a] = o.center[a] + ((k & 1) ? h[0][a] : -h[0][a]) + ((k & 2) ? h[1][a] : -h[1][a]) +
                  ((k & 4) ? h[2][a] : -h[2][a]);
    // The exact corners centre +- half_k axes_k (of the computed centre, axes and halves) lie
    // within the coordinates' rounding of the computed ones: a product and three sums, at most
    // 8 u (|centre_a| + sum_k half_k |axes_ka|) per coordinate in any rounding mode (u = 2^-53),
    // whose sum over a bounds the distance; a convex combination of exact corners lies as near to
    // the same combination of computed ones. Plus the box's pad.
    const double far = round_up(o.pad + 1e-15 * round_up(magnitude * (1.0 + 1e-12)));
    HalfspaceSeed seed = node_seed;
    HalfspaceBound b = halfspace_bound(S, c.data(), 8, d, 6, &seed);
    b.lower = round_down(b.lower - far);
    return key(b);
  }
  double prune_bound() const { return best; }
  bool done() const { return step && best <= 0.0; }
  void leaf(std::uint32_t f) {
    const Face& face = (*o.faces)[f];
    const std::array<Vec3, 3> v{P[face[0]], P[face[1]], P[face[2]]};
    HalfspaceSeed seed = seeds ? (*seeds)[f] : HalfspaceSeed{};
    const HalfspaceBound b = halfspace_bound(S, v.data(), 3, d, 6, &seed);
    if (seeds) (*seeds)[f] = seed;
    const double k = key(b);
    if (k < best || out.face < 0) {
      best = std::min(best, k);
      out.lower = b.lower;
      out.face = f;
      out.beta = b.beta;
      out.gamma = b.gamma;
      node_seed = seed;
    }
  }
};

// Every triangle for a small mover (its few tree nodes, each an 8-corner program, cost more than
// they prune: a tetrahedron's poses several times slower walked), else the walk: on the mover's
// sweep tree when the caller has it (oriented boxes), else on its box tree.
void visit(const MoverOrientation& o, HalfspacePolicy& p, const SweepTrees* trees, std::int64_t hint) {
  constexpr std::size_t kLoopFaces = 64;
  if (o.faces->size() > kLoopFaces) {
    if (hint >= 0 && static_cast<std::size_t>(hint) < o.faces->size()) p.leaf(static_cast<std::uint32_t>(hint));
    // (A tree built without oriented boxes has none at any node: the box tree then.)
    if (trees && trees->mover && !trees->mover->tree.empty() && trees->mover->tree.nodes[0].bv.obb.half[0] >= 0.0) {
      if (trees->mover->faces.size() != o.faces->size())
        throw std::invalid_argument("supporting planes' walk: the sweep mesh is not the mover's");
      const MoverOrientation::Shift shift = o.shift_from(trees->mover_t, p.t);
      p.D = shift.D;
      p.shift_pad = shift.pad;
      traverse_nearest_first(trees->mover->tree, p);
      return;
    }
    traverse_nearest_first(o.boxes, p);
    return;
  }
  for (std::uint32_t f = 0; f < o.faces->size() && !p.done(); ++f) p.leaf(f);
}

// Where a moving box or triangle can meet a box of the deep-zone cover (doc/poses.md, "Deep-zone
// jumps"): the mover's rotated doubles a moved to a + t0 + lambda d (exact in lambda), the cover's
// boxes grown by `margin`. Each separating axis gives an interval of lambda outside of which it
// separates them, computed outwards (every operation rounded and then moved one ulp out, valid in
// any rounding mode); their intersection holds every lambda where the two meet.
struct LambdaRange {
  double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
  bool empty() const { return !(lo <= hi); }
  void meet(double l, double h) {
    lo = std::max(lo, l);
    hi = std::min(hi, h);
  }
};

// Along an axis where the moving range is [p_lo, p_hi] + lambda w (w in [w_lo, w_hi], of one sign
// or zero) and the fixed one [b_lo, b_hi] (every bound already outward): the lambdas where they may
// overlap.
void axis_range(double p_lo, double p_hi, double b_lo, double b_hi, double w_lo, double w_hi, LambdaRange& r) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (w_lo == 0.0 && w_hi == 0.0) {
    if (!(p_lo <= b_hi && p_hi >= b_lo)) r.meet(kInf, -kInf);
    return;
  }
  if (!(w_lo > 0.0) && !(w_hi < 0.0)) return;  // the sign of the motion is uncertain: no constraint
  if (w_hi < 0.0) {  // mirror the axis
    axis_range(-p_hi, -p_lo, -b_hi, -b_lo, -w_hi, -w_lo, r);
    return;
  }
  // p_hi + lambda w >= b_lo and p_lo + lambda w <= b_hi, for the exact w in [w_lo, w_hi] > 0.
  // Division is monotone in any rounding mode: the smaller quotient of n1 is over the larger w
  // when n1 >= 0, and the larger of n2 over the smaller w when n2 >= 0 (one division each).
  const double n1 = round_down(b_lo - p_hi), n2 = round_up(b_hi - p_lo);
  const double lo = round_down(n1 >= 0.0 ? n1 / w_hi : n1 / w_lo);
  const double hi = round_up(n2 >= 0.0 ? n2 / w_lo : n2 / w_hi);
  r.meet(lo, hi);
}

// A moving triangle's separating axes against a box (its normal, its edges crossed with the
// coordinate axes), its extent along each, moved by t0, and the motion d along each (all outward):
// the same for every cube a query tests it against, so made once per face and query.
struct MovingTriangle {
  std::array<Vec3, 10> axes;
  std::array<double, 10> m_lo, m_hi;  // the triangle's extent along the axis, moved by t0
  std::array<double, 10> w_lo, w_hi;  // d along the axis
  std::uint16_t nonzero = 0;          // bit i: axis i is not the zero vector
};
// Items a query makes once per index (a mover face, a sweep-tree node), per thread
// (ThreadScratch): slot[i] holds the query's stamp and the item's index in `items` once made; at
// most kMaxItems, then made afresh for each use (a million-face mover's query must not keep one
// per face).
template <class Item>
struct QueryTable {
  static constexpr std::size_t kMaxItems = 65536;
  std::vector<std::uint64_t> slot;
  std::vector<Item> items;
  std::uint32_t stamp = 0;
  void start(std::size_t n) {
    if (slot.size() != n || stamp == 0xffffffffu) {
      slot.assign(n, 0);
      stamp = 0;
    }
    ++stamp;
    items.clear();
  }
  // Item i, made by make(Item&) the first time this query asks (in `local` once the table is full).
  template <class Make>
  const Item& get(std::uint32_t i, Item& local, const Make& make) {
    std::uint64_t& s = slot[i];
    if (s >> 32 == stamp) return items[s & 0xffffffffu];
    if (items.size() >= kMaxItems) {
      make(local);
      return local;
    }
    s = (static_cast<std::uint64_t>(stamp) << 32) | items.size();
    items.emplace_back();
    make(items.back());
    return items.back();
  }
};
// A query's moving triangles (about 40 MB at most).
using MovingTriangles = QueryTable<MovingTriangle>;

// A deep-zone query's octree and work lists, kept per thread from query to query: allocating them
// afresh (and faulting their pages in) was a tenth of rotor's queries. Storage past kKeepBytes is
// given back after a query, so a thin shell's 4-million-cube query does not stay resident.
struct ZoneOctree {
  // 96 bytes: a thin shell's query holds millions (its clips apart, in `clips`).
  struct Node {
    Aabb box;  // the rest of its DeepCube is its parent's (deep_cube_child)
    DeepCubeHead verdict;
    bool classified = false;
    bool leaf = false;              // kept: in the zone, or undecided at most the leaf size
    std::uint32_t first_child = 0;  // 0: none yet
    std::uint32_t parent = 0;       // (the root's: itself)
    std::int32_t list = -1;         // its children's list in `lists` (-1: not made yet, -2: none)
    std::uint32_t clips = 0;        // its verdict's clips: clips[this, this + verdict.n_clips)
  };
  static_assert(sizeof(Node) <= 96, "a node's clips belong in `clips`");
  // Pairs (mover node, cube) by the latest lambda at which they may meet, latest first.
  struct Pair {
    std::uint32_t a, b;
    double hi;
  };
  static constexpr std::size_t kKeepBytes = std::size_t{64} << 20;
  // A split cube lists the triangles near it for its children (deep_cube_list), at most this many.
  static constexpr std::size_t kMaxListed = 64;
  std::vector<Node> nodes;
  std::vector<DeepClip> clips;
  std::vector<DeepCubeList> lists;  // [0, n_lists) in use; the rest keep their storage
  std::size_t n_lists = 0;
  std::vector<Pair> heap;
  std::vector<std::uint32_t> ids;
  void start() {
    nodes.clear();
    clips.clear();
    heap.clear();
    n_lists = 0;
  }
  // After a query: a large octree's storage is given back.
  void trim() {
    const std::size_t bytes = nodes.capacity() * sizeof(Node) + clips.capacity() * sizeof(DeepClip) +
                              heap.capacity() * sizeof(Pair) +
                              lists.capacity() * (sizeof(DeepCubeList) + kMaxListed * sizeof(std::uint32_t));
    if (bytes <= kKeepBytes) return;
    std::vector<Node>().swap(nodes);
    std::vector<DeepClip>().swap(clips);
    std::vector<Pair>().swap(heap);
    std::vector<DeepCubeList>().swap(lists);
    n_lists = 0;
  }
};

// A cube's clips (DeepClip), wherever its octree keeps them.
struct ClipSpan {
  const DeepClip* at = nullptr;
  int n = 0;
};

// The lambdas where the mover (rotated doubles moved by t0 + lambda d, exactly) can meet a box
// of a deep-zone cover grown by `margin`.
struct CoverGeometry {
  const MoverOrientation& o;
  Vec3 t0, d;
  double margin;
  MovingTriangles* cache = nullptr;  // optional: the query's moving triangles

  // A cover's box grown by the margin, outwards.
  Aabb grown(const Aabb& B) const {
    Aabb G;
    for (int k = 0; k < 3; ++k) {
      G.lo[k] = round_down(B.lo[k] - margin);
      G.hi[k] = round_up(B.hi[k] + margin);
    }
    return G;
  }
  // A box in rotated coordinates moved by t0, outwards.
  Aabb moved_box(const Aabb& A) const {
    Aabb M;
    for (int k = 0; k < 3; ++k) {
      M.lo[k] = round_down(A.lo[k] + t0[k]);
      M.hi[k] = round_up(A.hi[k] + t0[k]);
    }
    return M;
  }
  // A box already moved by t0 (moved_box), moving by lambda d, against the grown box G: the
  // coordinate axes.
  LambdaRange moving_box(const Aabb& M, const Aabb& G) const {
    LambdaRange r;
    for (int k = 0; k < 3 && !r.empty(); ++k) axis_range(M.lo[k], M.hi[k], G.lo[k], G.hi[k], d[k], d[k], r);
    return r;
  }
  // The moving box A (rotated coordinates) against the grown box G.
  LambdaRange boxes(const Aabb& A, const Aabb& G) const { return moving_box(moved_box(A), G); }
  // An upper bound of max m.x over x in G with n.x <= off (Lagrange: for any mu >= 0 it is at most
  // mu off + max over G of (m - mu n).x; the best mu is 0 or where a coordinate of m - mu n changes
  // sign). The computed m - mu n is within a few ulps of the exact; the error term covers that and
  // the sums' rounding. `at_zero`: the bound at mu = 0 (box_max(m, G)), the same for every clip of
  // a cube, so computed once per axis by the caller.
  static double lagrange(const Vec3& m, const Aabb& G, const Vec3& n, double off, double mu) {
    double v = mu == 0.0 ? 0.0 : mu * off, abs_sum = mu == 0.0 ? 0.0 : std::abs(v);
    for (int k = 0; k < 3; ++k) {
      const double c = m[k] - mu * n[k];
      const double x = c >= 0.0 ? G.hi[k] : G.lo[k];
      v += c * x;
      abs_sum += (std::abs(m[k]) + mu * std::abs(n[k])) * std::max(std::abs(G.lo[k]), std::abs(G.hi[k]));
    }
    return round_up(v + 1e-14 * abs_sum + 1e-300);
  }
  static double box_max(const Vec3& m, const Aabb& G) { return lagrange(m, G, m, 0.0, 0.0); }
  static double support(const Vec3& m, const Aabb& G, const Vec3& n, double off, double at_zero) {
    double best = at_zero;
    for (int k = 0; k < 3; ++k) {
      if (n[k] == 0.0) continue;
      const double mu = m[k] / n[k];
      if (mu > 0.0 && std::isfinite(mu)) best = std::min(best, lagrange(m, G, n, off, mu));
    }
    return best;
  }
  // The extent along n of the box B (outwards), and of the triangle abc (distance/point_triangle_distance.h).
  static void extent(const Vec3& n, const Aabb& B, double& lo, double& hi) {
    const AxisExtent e = box_extent(n, B);
    lo = e.lo;
    hi = e.hi;
  }
  static void extent(const Vec3& n, const Vec3& a, const Vec3& b, const Vec3& c, double& lo, double& hi) {
    const AxisExtent e = triangle_extent(n, a, b, c);
    lo = e.lo;
    hi = e.hi;
  }
  // The motion d along n, outwards.
  void motion(const Vec3& n, double& w_lo, double& w_hi) const {
    const PlaneOffset nd = plane_offset(n, 0.0, d);
    w_lo = round_down(nd.value - nd.error);
    w_hi = round_up(nd.value + nd.error);
  }
  // Points whose extent along n is [p_lo, p_hi] in rotated coordinates, moved by t0 (outward), and
  // d along n.
  void moved(const Vec3& n, double p_lo, double p_hi, double& m_lo, double& m_hi, double& w_lo, double& w_hi) const {
    const PlaneOffset nt = plane_offset(n, 0.0, t0);
    m_lo = round_down(p_lo + round_down(nt.value - nt.error));
    m_hi = round_up(p_hi + round_up(nt.value + nt.error));
    motion(n, w_lo, w_hi);
  }
  // Moving points whose extent along n is [p_lo, p_hi] in rotated coordinates, moved by
  // t0 + lambda d, against the fixed extent [b_lo, b_hi], narrowing r.
  void moving(const Vec3& n, double p_lo, double p_hi, double b_lo, double b_hi, LambdaRange& r) const {
    double m_lo, m_hi, w_lo, w_hi;
    moved(n, p_lo, p_hi, m_lo, m_hi, w_lo, w_hi);
    axis_range(m_lo, m_hi, b_lo, b_hi, w_lo, w_hi, r);
  }
  // The moving triangle `face`: its axes, and its extent and motion along each.
  void make_moving(std::uint32_t face, MovingTriangle& t) const {
    const Face& f = (*o.faces)[face];
    const Vec3 &a0 = o.rotated[f[0]], &a1 = o.rotated[f[1]], &a2 = o.rotated[f[2]];
    const std::array<Vec3, 3> edges{a1 - a0, a2 - a1, a0 - a2};
    t.axes[0] = edges[0].cross(a2 - a0);
    for (int e = 0; e < 3; ++e)
      for (int k = 0; k < 3; ++k) t.axes[1 + 3 * e + k] = edges[e].cross(Vec3::Unit(k));
    t.nonzero = 0;
    for (std::size_t i = 0; i < t.axes.size(); ++i) {
      const Vec3& n = t.axes[i];
      if (!(n.cwiseAbs().maxCoeff() > 0.0)) continue;
      t.nonzero = static_cast<std::uint16_t>(t.nonzero | (1u << i));
      double p_lo, p_hi;
      extent(n, a0, a1, a2, p_lo, p_hi);
      moved(n, p_lo, p_hi, t.m_lo[i], t.m_hi[i], t.w_lo[i], t.w_hi[i]);
    }
  }
  // The same from the query's cache when there is one (and it is not full), else made in `local`.
  const MovingTriangle& moving_triangle(std::uint32_t face, MovingTriangle& local) const {
    const auto make = [&](MovingTriangle& t) { make_moving(face, t); };
    if (!cache) {
      make(local);
      return local;
    }
    return cache->get(face, local, make);
  }
  // The moving triangle `face` against the grown box G, and, with v, against the zone's part of the
  // cube (G with each of v's clips grown by the margin): separating axes of a triangle and a
  // polytope (its face normals, the triangle's, and edges crossed with edges), the polytope's
  // extent along each bounded through support(). The box's 13 axes first, as without clips: most
  // pairs part there, and the clipped extents cost more. Any set of axes is valid (a pair no axis
  // parts may meet); the triangle's edges crossed with the clip planes' edges on the box are left
  // out: they parted under 1 % of the pairs and cost a sixth of rotor's -20 % poses
  // (doc/performance.md, "The octree's triangle tests and its cubes' parents"). Narrows r.
  // `clipped_axes` false: the clips only as half-lines, not the 10 axes' clipped extents (a
  // weaker test, as valid; the test before a split, "Coarser tests before a split").
  void triangle(std::uint32_t face, const Aabb& G, LambdaRange& r, ClipSpan v = {}, bool clipped_axes = true) const {
    const Face& f = (*o.faces)[face];
    const Vec3 &a0 = o.rotated[f[0]], &a1 = o.rotated[f[1]], &a2 = o.rotated[f[2]];
    Aabb tri;
    tri.extend(a0);
    tri.extend(a1);
    tri.extend(a2);
    const LambdaRange rb = boxes(tri, G);
    r.meet(rb.lo, rb.hi);
    if (v.n > 0) clips(face, v, r);  // cheap, and often decisive
    if (r.empty()) return;
    // The triangle's normal and its edges crossed with the axes: any vector separates validly; the
    // computed ones nearly as the exact.
    MovingTriangle local;
    const MovingTriangle& t = moving_triangle(face, local);
    const std::array<Vec3, 10>& axes = t.axes;
    for (std::size_t i = 0; i < axes.size(); ++i) {
      if (r.empty()) return;
      if (!(t.nonzero >> i & 1u)) continue;
      double b_lo, b_hi;
      extent(axes[i], G, b_lo, b_hi);
      axis_range(t.m_lo[i], t.m_hi[i], b_lo, b_hi, t.w_lo[i], t.w_hi[i], r);
    }
    const int n_clips = v.n;
    if (n_clips == 0 || r.empty() || !clipped_axes) return;
    // Against the clipped cube: the same axes with its smaller extents.
    std::array<Vec3, 4> cn;
    std::array<double, 4> coff;
    for (int i = 0; i < n_clips; ++i) {
      cn[i] = v.at[i].n;
      coff[i] = grown_off(v.at[i]);
    }
    // The clipped cube's extent along n (the least of the clips' bounds), against the triangle's.
    const auto clipped_extent = [&](const Vec3& n, double& b_lo, double& b_hi) {
      const Vec3 m = -n;
      const double top = box_max(n, G), bottom = box_max(m, G);
      b_lo = -std::numeric_limits<double>::infinity();
      b_hi = -b_lo;
      for (int i = 0; i < n_clips; ++i) {
        b_hi = std::min(b_hi, support(n, G, cn[i], coff[i], top));
        b_lo = std::max(b_lo, -support(m, G, cn[i], coff[i], bottom));
      }
    };
    for (std::size_t i = 0; i < axes.size(); ++i) {
      if (r.empty()) return;
      if (!(t.nonzero >> i & 1u)) continue;
      double b_lo, b_hi;
      clipped_extent(axes[i], b_lo, b_hi);
      axis_range(t.m_lo[i], t.m_hi[i], b_lo, b_hi, t.w_lo[i], t.w_hi[i], r);
    }
  }
  // A clip {n.x <= off} grown by the margin: the margin ball reaches at most margin |n|_1 along n.
  double grown_off(const DeepClip& c) const {
    return round_up(c.off + round_up(margin * c.n.cwiseAbs().sum() * (1.0 + 1e-15)));
  }
  // The moving box A (rotated coordinates), or the mover's triangle `face`, against each of the
  // cube's clips grown by the margin (a half-line of fixed extent), narrowing r.
  void clips(const Aabb& A, ClipSpan v, LambdaRange& r) const {
    for (int i = 0; i < v.n && !r.empty(); ++i) {
      double p_lo, p_hi;
      extent(v.at[i].n, A, p_lo, p_hi);
      moving(v.at[i].n, p_lo, p_hi, -std::numeric_limits<double>::infinity(), grown_off(v.at[i]), r);
    }
  }
  void clips(std::uint32_t face, ClipSpan v, LambdaRange& r) const {
    const Face& f = (*o.faces)[face];
    for (int i = 0; i < v.n && !r.empty(); ++i) {
      double p_lo, p_hi;
      extent(v.at[i].n, o.rotated[f[0]], o.rotated[f[1]], o.rotated[f[2]], p_lo, p_hi);
      moving(v.at[i].n, p_lo, p_hi, -std::numeric_limits<double>::infinity(), grown_off(v.at[i]), r);
    }
  }
};

// The margin of a cover query: the exact mover at a pose fl(t0 + lambda d), |lambda| <=
// lambda_max, lies within the transform's rounding there plus slack of the rotated doubles moved by
// t0 + lambda d, and a double evaluation within the transform's rounding more (advance_rounding's
// farthest pose bounds both).
double cover_margin(const MoverOrientation& o, const Vec3& t0, const Vec3& d, double slack, double lambda_max) {
  return round_up(round_up(2.0 * advance_rounding(o, t0, d, slack, lambda_max).farthest) + slack);
}

// A node of the mover's sweep tree placed at t0 (OrientationFrame::swept) as a cover query sees
// it. Its volumes hold R x + t0 (within their pads) and the placed doubles fl(r + t0); the query's
// points r + t0 (r = fl(R x)) lie within pad = transform_error(t0) of both. Its box in rotated
// coordinates (CoverGeometry's): the placed box less t0, grown by the pad, outwards.
Aabb rotated_box(const Aabb& placed, const Vec3& t0, double pad) {
  Aabb A;
  for (int k = 0; k < 3; ++k) {
    A.lo[k] = round_down(round_down(placed.lo[k] - t0[k]) - pad);
    A.hi[k] = round_up(round_up(placed.hi[k] - t0[k]) + pad);
  }
  return A;
}
// Such a node's part of every cube test that does not depend on the cube: its box (rotated
// coordinates) and that box moved by t0, and along each axis of its oriented box (obb_projection,
// the exact sweep's kernel) its extent, already moved by t0, and the motion d (all outwards).
struct PlacedNode {
  Aabb box, moved;
  bool oriented = false;
  std::array<Vec3, 3> axes;
  std::array<double, 3> p_lo, p_hi, w_lo, w_hi;
};
PlacedNode placed_node(const CoverGeometry& g, const SweepVolume& v, double pad) {
  PlacedNode n;
  n.box = rotated_box(v.box, g.t0, pad);
  n.moved = g.moved_box(n.box);
  n.oriented = v.obb.half[0] >= 0.0;
  if (!n.oriented) return n;
  for (int j = 0; j < 3; ++j) {
    n.axes[j] = v.obb.axes.col(j);
    const ObbProjection p = obb_projection(v.obb, n.axes[j], pad);
    n.p_lo[j] = round_down(p.lo);
    n.p_hi[j] = round_up(p.hi);
    g.motion(n.axes[j], n.w_lo[j], n.w_hi[j]);
  }
  return n;
}
// The lambdas where such a node may meet the grown box G: its box, then its oriented box's axes
// (thin, tilted nodes, whose axis-aligned boxes are far fatter than they are: rotor's blades;
// doc/performance.md, "Oriented boxes in the zone's octree").
LambdaRange placed_node_range(const CoverGeometry& g, const PlacedNode& n, const Aabb& G) {
  LambdaRange r = g.moving_box(n.moved, G);
  if (!n.oriented) return r;
  for (int j = 0; j < 3 && !r.empty(); ++j) {
    double b_lo, b_hi;
    CoverGeometry::extent(n.axes[j], G, b_lo, b_hi);
    axis_range(n.p_lo[j], n.p_hi[j], b_lo, b_hi, n.w_lo[j], n.w_hi[j], r);
  }
  return r;
}
LambdaRange placed_node_range(const CoverGeometry& g, const SweepVolume& v, double pad, const Aabb& G) {
  return placed_node_range(g, placed_node(g, v, pad), G);
}
// A query's placed nodes, made when a node first meets a cube: each meets many (rotor's -20 %
// queries: about 9,500 tests of at most 2,400 nodes), and its part was most of a test (about 18 MB
// at most).
using PlacedNodes = QueryTable<PlacedNode>;
double placed_node_pad(const MoverOrientation& o, const Vec3& t0) {
  return round_up(o.transform_error(t0) * (1.0 + 1e-12));
}

// A query's optional sweep tree must index the mover's faces (its nodes hand out face indices).
void check_mover_sweep(const SweepMesh* mover_sweep, const MoverOrientation& orientation, const char* query) {
  if (mover_sweep && mover_sweep->faces.size() != orientation.faces->size())
    throw std::invalid_argument(std::string(query) + ": the sweep mesh is not the mover's");
}

struct CoverContactPolicy {
  CoverGeometry g;
  const DeepCover& cover;
  double stop_at;  // a contact at or beyond it settles the query
  double pad = 0.0;  // with the mover's sweep tree: placed_node_pad
  double best = -std::numeric_limits<double>::infinity();

  static double later_first(const LambdaRange& r) {
    return r.empty() ? std::numeric_limits<double>::infinity() : -r.hi;
  }
  double bound(const Aabb& A, const Aabb& B) const { return later_first(g.boxes(A, g.grown(B))); }
  double bound(const SweepVolume& A, const Aabb& B) const {
    return later_first(placed_node_range(g, A, pad, g.grown(B)));
  }
  double prune_bound() const { return -best; }
  bool done() const { return best >= stop_at; }
  bool split_first(const Aabb& a, const Aabb& b) const { return a.extent().squaredNorm() >= b.extent().squaredNorm(); }
  bool split_first(const SweepVolume& a, const Aabb& b) const { return split_first(a.box, b); }
  void leaf(std::uint32_t face, std::uint32_t box) {
    LambdaRange r;
    g.triangle(face, g.grown(cover.boxes[box]), r);
    if (!r.empty()) best = std::max(best, r.hi);
  }
};

}  // namespace

double deep_cover_contact(const DeepCover& cover, const MoverOrientation& orientation, const Vec3& t0, const Vec3& d,
                          double slack, double lambda_max, double stop_at, const SweepMesh* mover_sweep) {
  if (!cover.complete || cover.boxes.empty() || orientation.boxes.empty())
    return -std::numeric_limits<double>::infinity();
  check_mover_sweep(mover_sweep, orientation, "deep_cover_contact");
  ThreadScratch<MovingTriangles> moving_scratch;
  moving_scratch.get().start(orientation.faces->size());
  CoverContactPolicy p{{orientation, t0, d, cover_margin(orientation, t0, d, slack, lambda_max), &moving_scratch.get()},
                       cover, stop_at, placed_node_pad(orientation, t0)};
  if (mover_sweep && !mover_sweep->tree.empty())
    traverse_pairs_best_first(mover_sweep->tree, cover.tree, p);
  else
    traverse_pairs_best_first(orientation.boxes, cover.tree, p);
  return p.best;
}

// The mover's tree a deep-zone query walks: the orientation's sweep tree placed at t0 when the
// caller has it (placed_node_range), else its box tree. Both index the same faces; boxes are
// handed out in rotated coordinates (CoverGeometry's).
struct ZoneMover {
  const Bvh<Aabb>* boxes = nullptr;
  const Bvh<SweepVolume>* sweep = nullptr;
  double pad = 0.0;  // placed_node_pad
  PlacedNodes* placed = nullptr;  // the sweep tree's nodes as placed (PlacedNodes::start done)

  std::uint32_t count(std::uint32_t a) const { return sweep ? sweep->nodes[a].count : boxes->nodes[a].count; }
  std::uint32_t first(std::uint32_t a) const { return sweep ? sweep->nodes[a].first : boxes->nodes[a].first; }
  std::uint32_t face(std::uint32_t i) const { return sweep ? sweep->order[i] : boxes->order[i]; }
  // The sweep tree's node a as placed (only with `sweep`).
  const PlacedNode& node(const CoverGeometry& g, std::uint32_t a, PlacedNode& local) const {
    return placed->get(a, local, [&](PlacedNode& n) { n = placed_node(g, sweep->nodes[a].bv, pad); });
  }
  Aabb box(const CoverGeometry& g, std::uint32_t a) const {
    PlacedNode local;
    return sweep ? node(g, a, local).box : boxes->nodes[a].bv;
  }
  // The lambdas where the node may meet the grown box G.
  LambdaRange range(const CoverGeometry& g, std::uint32_t a, const Aabb& G) const {
    PlacedNode local;
    return sweep ? placed_node_range(g, node(g, a, local), G) : g.boxes(boxes->nodes[a].bv, G);
  }
};

// A held query (HeldZoneQuery): its octree and queue, what it was asked, and how far it got.
struct HeldZoneQuery::State {
  ZoneOctree z;
  const SignedDistance* fixed = nullptr;
  const MoverOrientation* orientation = nullptr;
  const SweepMesh* mover_sweep = nullptr;
  const DeepCubeMemo* memo = nullptr;
  double target = 0.0, cell_size = 0.0, clipped_cell_size = 0.0, slack = 0.0, lambda_max = 0.0;
  Vec3 t0 = Vec3::Zero(), d = Vec3::Zero();
  double best = 0.0;         // its latest contact so far
  std::int64_t best_face = -1;  // and where (DeepZoneContact::face, cube_centre)
  Vec3 best_centre = Vec3::Zero();
  std::uint64_t cubes = 0;   // classified since it started
};

HeldZoneQuery::HeldZoneQuery() = default;
HeldZoneQuery::~HeldZoneQuery() = default;
HeldZoneQuery::HeldZoneQuery(HeldZoneQuery&&) noexcept = default;
HeldZoneQuery& HeldZoneQuery::operator=(HeldZoneQuery&&) noexcept = default;
bool HeldZoneQuery::held() const { return state_ != nullptr; }
double HeldZoneQuery::cell_size() const { return state_ ? state_->cell_size : 0.0; }
double HeldZoneQuery::clipped_cell_size() const { return state_ ? state_->clipped_cell_size : 0.0; }
void HeldZoneQuery::clear() { state_.reset(); }

DeepZoneContact deep_zone_contact(const SignedDistance& fixed, double target, double cell_size,
                                  const MoverOrientation& orientation, const Vec3& t0, const Vec3& d, double slack,
                                  double lambda_max, double lambda_top, double stop_at, std::uint64_t max_cubes,
                                  DeepCubeMemo* memo, double clipped_cell_size, HeldZoneQuery* held,
                                  const SweepMesh* mover_sweep) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kPresplitLeaves = 8.0;
  DeepZoneContact out;
  out.lambda = -kInf;
  if (!(target < 0.0) || fixed.mesh().faces.empty() || orientation.boxes.empty()) {
    if (held) held->clear();
    out.complete = true;
    return out;
  }
  ThreadScratch<MovingTriangles> moving_scratch;
  moving_scratch.get().start(orientation.faces->size());
  const CoverGeometry g{orientation, t0, d, cover_margin(orientation, t0, d, slack, lambda_max), &moving_scratch.get()};
  check_mover_sweep(mover_sweep, orientation, "deep_zone_contact");
  ThreadScratch<PlacedNodes> placed_scratch;
  const Bvh<SweepVolume>* sweep_tree = mover_sweep && !mover_sweep->tree.empty() ? &mover_sweep->tree : nullptr;
  if (sweep_tree) placed_scratch.get().start(sweep_tree->nodes.size());
  const ZoneMover mover{&orientation.boxes, sweep_tree, placed_node_pad(orientation, t0), &placed_scratch.get()};
  // A held query of the same question continues where it stopped: every pair it set aside had no
  // contact later than its best, which is at most lambda_top, so its queue still holds every
  // pair that may meet later (pairs queued under an earlier lambda_top keep upper bounds that are
  // still valid, and their tests now stop at lambda_top).
  HeldZoneQuery::State* h = held ? held->state_.get() : nullptr;
  const bool resume = h && h->fixed == &fixed && h->orientation == &orientation && h->mover_sweep == mover_sweep &&
                      h->memo == memo && h->target == target && h->cell_size == cell_size &&
                      h->clipped_cell_size == clipped_cell_size && h->slack == slack && h->lambda_max == lambda_max &&
                      h->t0 == t0 && h->d == d && !(h->best > lambda_top);
  if (held && !resume) held->clear();
  std::uint64_t done = resume ? h->cubes : 0;  // cubes of this query classified before this call
  // The octree, grown on demand (ZoneOctree): a cube that a pair holding it finds neither dropped
  // nor kept is split into eight, classified at once, so that no pair with a dropped child is
  // queued (classified when its first pair came up, half of the pairs were such, each queued with
  // its box's range; rotor's queries, doc/performance.md, "Children classified when made").
  ThreadScratch<ZoneOctree> scratch;
  ZoneOctree& z = resume ? h->z : scratch.get();
  struct Trim {
    ZoneOctree& z;
    ~Trim() { z.trim(); }
  } trim_after{scratch.get()};
  std::vector<ZoneOctree::Node>& nodes = z.nodes;
  const DeepCube root = deep_cover_root(fixed);
  if (resume) {
    out.lambda = h->best;
    out.face = h->best_face;
    out.cube_centre = h->best_centre;
  } else {
    z.start();
    nodes.push_back({root.box, {}, false, false, 0, 0, -2, 0});
  }
  // A split cube's list of nearby triangles, made when one of its children is first classified
  // here: the children's queries scan it instead of the tree. A deterministic function of the cube
  // (its verdict is), so a verdict does not depend on which query classified it.
  const auto parent_list = [&](std::uint32_t child) -> const DeepCubeList* {
    ZoneOctree::Node& p = nodes[nodes[child].parent];
    if (p.list == -1) {
      if (z.n_lists == z.lists.size()) z.lists.emplace_back();
      p.list = deep_cube_list(fixed, p.box, p.verdict, ZoneOctree::kMaxListed, z.lists[z.n_lists])
                   ? static_cast<std::int32_t>(z.n_lists++)
                   : -2;
    }
    return p.list >= 0 ? &z.lists[static_cast<std::size_t>(p.list)] : nullptr;
  };
  std::vector<std::uint32_t>& ids = z.ids;
  using Pair = ZoneOctree::Pair;
  // A max-heap on hi, ties by the pair: the order pairs come up in is a function of the pairs queued,
  // not of the order they were queued in, so a held query continued does what one fresh query with
  // the whole budget would.
  const auto earlier = [](const Pair& x, const Pair& y) {
    return x.hi < y.hi || (x.hi == y.hi && (x.a > y.a || (x.a == y.a && x.b > y.b)));
  };
  std::vector<Pair>& heap = z.heap;
  // Out of budget: the query is held (the pair just taken put back) when the caller keeps it.
  const auto run_out = [&](const Pair& e) {
    out.complete = false;
    if (!held) return;
    heap.push_back(e);
    std::push_heap(heap.begin(), heap.end(), earlier);
    if (!resume) {
      auto s = std::make_unique<HeldZoneQuery::State>();
      std::swap(s->z, z);  // the thread's scratch is left empty
      s->fixed = &fixed;
      s->orientation = &orientation;
      s->mover_sweep = mover_sweep;
      s->memo = memo;
      s->target = target;
      s->cell_size = cell_size;
      s->clipped_cell_size = clipped_cell_size;
      s->slack = slack;
      s->lambda_max = lambda_max;
      s->t0 = t0;
      s->d = d;
      held->state_ = std::move(s);
      h = held->state_.get();
    }
    h->best = out.lambda;
    h->best_face = out.face;
    h->best_centre = out.cube_centre;
    h->cubes = done + out.cubes;
  };
  const auto push = [&](std::uint32_t a, std::uint32_t b) {
    // A cube dropped meets nothing (only the root is queued before its verdict).
    if (nodes[b].classified && nodes[b].verdict.what == DeepCubeVerdict::drop) return;
    LambdaRange r = mover.range(g, a, g.grown(nodes[b].box));
    r.meet(-kInf, lambda_top);
    if (r.empty() || !(r.hi > out.lambda)) return;
    heap.push_back({a, b, r.hi});
    std::push_heap(heap.begin(), heap.end(), earlier);
  };
  const auto classify = [&](std::uint32_t b) {
    ++out.cubes;
    ZoneOctree::Node& nb = nodes[b];
    DeepCubeVerdict v;
    if (!(memo && memo->find(nb.box, &v))) {
      // Cell size 0: "split" is "not decided", the cell size applied below, so that the memo
      // serves queries of any cell size.
      const DeepCube cube = b == 0 ? root : deep_cube_child(nb.box, nodes[nb.parent].box, nodes[nb.parent].verdict);
      v = classify_deep_cube(fixed, target, 0.0, cube, ids, b == 0 ? nullptr : parent_list(b));
      if (memo) memo->insert(nb.box, v);
    }
    nb.verdict = v;
    nb.clips = static_cast<std::uint32_t>(z.clips.size());
    z.clips.insert(z.clips.end(), v.clips.begin(), v.clips.begin() + v.n_clips);
    nb.classified = true;
    const double leaf_size = nb.verdict.n_clips > 0 ? std::max(cell_size, clipped_cell_size) : cell_size;
    nb.leaf = nb.verdict.what == DeepCubeVerdict::keep ||
              (nb.verdict.what == DeepCubeVerdict::split && deep_cube_radius(nb.box) <= leaf_size);
  };
  // A cube the mover comes near, undecided by its verdict: its second stage (deep_cube_regions), in
  // the memo as well. A deterministic function of the cube, as the verdict is.
  const auto refine = [&](std::uint32_t b) {
    ZoneOctree::Node& nb = nodes[b];
    DeepCubeVerdict v;
    if (memo && memo->find(nb.box, &v) && v.regions_tried) {
      nb.verdict.what = v.what;
    } else {
      const DeepCube cube = b == 0 ? root : deep_cube_child(nb.box, nodes[nb.parent].box, nodes[nb.parent].verdict);
      if (deep_cube_regions(fixed, target, cube, nb.verdict, ids, b == 0 ? nullptr : parent_list(b)))
        nb.verdict.what = DeepCubeVerdict::drop;
      if (memo) {
        DeepCubeHead head = nb.verdict;
        head.regions_tried = true;
        if (head.what == DeepCubeVerdict::drop) head.n_clips = 0;
        memo->refine(nb.box, head);
      }
    }
    nb.verdict.regions_tried = true;
  };
  if (!resume) push(0, 0);
  while (!heap.empty()) {
    std::pop_heap(heap.begin(), heap.end(), earlier);
    const Pair e = heap.back();
    heap.pop_back();
    if (!(e.hi > out.lambda)) break;  // no waiting pair can meet later than the best contact
    if (out.lambda >= stop_at) break;
    if (!nodes[e.b].classified) {  // the root
      // Every cube counts against the budget, found in the memo or not: whether it is found there
      // depends on other threads, the answer must not.
      if (done + out.cubes >= max_cubes) {
        run_out(e);
        return out;
      }
      classify(e.b);
    }
    ZoneOctree::Node& nb = nodes[e.b];
    if (nb.verdict.what == DeepCubeVerdict::split && !nb.verdict.regions_tried) refine(e.b);
    if (nb.verdict.what == DeepCubeVerdict::drop) continue;
    const std::uint32_t na_count = mover.count(e.a), na_first = mover.first(e.a);
    const Aabb na_box = mover.box(g, e.a);
    const ClipSpan clips{z.clips.data() + nb.clips, nb.verdict.n_clips};
    if (clips.n > 0) {  // the pair again, against the zone's part of the cube
      LambdaRange r;
      r.meet(-kInf, e.hi);
      g.clips(na_box, clips, r);
      if (r.empty() || !(r.hi > out.lambda)) continue;
    }
    const bool cube_leaf = nb.leaf;
    if (na_count > 0 && !cube_leaf && clips.n > 0 &&
        deep_cube_radius(nodes[e.b].box) <= kPresplitLeaves * std::max(cell_size, clipped_cell_size)) {
      // The mover's triangles against the zone's part of the cube before splitting it: where the
      // clips hold the zone, a cube the triangles miss needs no children. Only near the leaves'
      // size: larger cubes' clips seldom part them from whole triangles, and testing every level
      // doubled a thin shell's queries (repaired lion -20 %). Without the clipped extents along
      // the triangle's axes: two thirds of these tests find a meeting and the cube is split all
      // the same, and those extents were most of their cost (doc/performance.md, "Coarser tests
      // before a split").
      const Aabb G = g.grown(nodes[e.b].box);
      bool meets = false;
      for (std::uint32_t i = 0; i < na_count && !meets; ++i) {
        // From the best contact so far: a range narrowed below it is as good as empty, and the
        // test stops at the first axis that shows it (the same answer as from -inf).
        LambdaRange r;
        r.meet(out.lambda, lambda_top);
        g.triangle(mover.face(na_first + i), G, r, clips, false);
        meets = !r.empty() && r.hi > out.lambda;
      }
      if (!meets) continue;
    }
    if (na_count > 0 && cube_leaf) {
      const Aabb G = g.grown(nodes[e.b].box);
      for (std::uint32_t i = 0; i < na_count; ++i) {
        LambdaRange r;
        r.meet(out.lambda, lambda_top);  // as above: only a later contact matters
        const std::uint32_t face = mover.face(na_first + i);
        g.triangle(face, G, r, clips);
        if (!r.empty() && r.hi > out.lambda) {
          out.lambda = r.hi;
          out.face = face;
          out.cube_centre = nodes[e.b].box.center();
        }
      }
      continue;
    }
    // Split the larger of the two (a leaf never).
    const bool split_mover =
        cube_leaf || (na_count == 0 && na_box.extent().squaredNorm() >= nodes[e.b].box.extent().squaredNorm());
    if (split_mover) {
      push(na_first, e.b);
      push(na_first + 1, e.b);
      continue;
    }
    if (nodes[e.b].first_child == 0) {
      // Its eight children count against the budget together (the pair is held unsplit).
      if (done + out.cubes + 8 > max_cubes) {
        run_out(e);
        return out;
      }
      const std::array<Aabb, 8> children = deep_cube_child_boxes(nodes[e.b].box);
      nodes[e.b].first_child = static_cast<std::uint32_t>(nodes.size());
      for (const Aabb& c : children) nodes.push_back({c, {}, false, false, 0, e.b, -1, 0});  // (nb is stale now)
      for (std::uint32_t k = 0; k < 8; ++k) classify(nodes[e.b].first_child + k);
    }
    const std::uint32_t first = nodes[e.b].first_child;
    for (std::uint32_t k = 0; k < 8; ++k) push(e.a, first + k);
  }
  out.complete = true;
  if (held) held->clear();
  return out;
}

HalfspaceMinimum least_halfspace_bound(const SupportPlanes& support, const MoverOrientation& orientation,
                                       const Vec3& t, HalfspaceSeeds* seeds, const SweepTrees* trees, std::int64_t hint) {
  HalfspacePolicy p{support, orientation, orientation.placed_view(t), t, Vec3::Zero(), false, 0.0, 0.0,
                    std::numeric_limits<double>::infinity(), {}, seeds};
  p.out.lower = std::numeric_limits<double>::infinity();
  visit(orientation, p, trees, hint);
  return p.out;
}

HalfspaceAdvance halfspace_advance(const SupportPlanes& support, const MoverOrientation& orientation, const Vec3& t,
                                   const Vec3& d, double target, double slack, double h_max,
                                   HalfspaceSeeds* seeds, const SweepTrees* trees, std::int64_t hint) {
  // The exact mover at a pose t' within slack of t - mu d lies within transform_error(t) + slack of
  // the placed one moved by -mu d, and a double evaluation at t' within transform_error(t') more
  // (advance_rounding, as in separated_advance); c is 1-Lipschitz in them.
  const AdvanceRounding rounding = advance_rounding(orientation, t, d, slack, h_max);
  const double margin = round_up(round_up(slack + rounding.at_t) + rounding.farthest);
  HalfspacePolicy p{support, orientation, orientation.placed_view(t), t, d, true, target, margin,
                    std::max(0.0, h_max), {}, seeds};
  visit(orientation, p, trees, hint);
  HalfspaceAdvance r;
  r.h = std::min(p.best, std::max(0.0, h_max));
  r.face = p.out.face;
  r.beta = p.out.beta;
  r.gamma = p.out.gamma;
  return r;
}

}  // namespace cdbench
