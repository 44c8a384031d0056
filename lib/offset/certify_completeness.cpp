#include "offset/certify_completeness.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <new>
#include <set>

#include "distance/point_triangle_distance.h"
#include "mesh/components.h"
#include "util/timer.h"

namespace cdbench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Missed cells' centres kept during the search, and the spread subset reported (the seeds of the
// next attempt: one per missed region first, so that a region with many cells does not crowd out
// a small one); unresolved cells' centres reported.
constexpr std::size_t kMissedKept = 4096, kMissedReported = 64, kUnresolvedReported = 64;

// Up to n of the points, spread out: farthest-point order from the first (ties to the earlier).
std::vector<Vec3> spread_points(const std::vector<Vec3>& points, std::size_t n) {
  if (points.size() <= n) return points;
  std::vector<Vec3> out{points.front()};
  std::vector<double> to_chosen(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) to_chosen[i] = (points[i] - points.front()).squaredNorm();
  while (out.size() < n) {
    const std::size_t far = static_cast<std::size_t>(std::max_element(to_chosen.begin(), to_chosen.end()) - to_chosen.begin());
    out.push_back(points[far]);
    for (std::size_t i = 0; i < points.size(); ++i)
      to_chosen[i] = std::min(to_chosen[i], (points[i] - points[far]).squaredNorm());
  }
  return out;
}

// Cells are boxes with exact double corners; children split at the rounded midpoint, so they tile
// exactly. Each keeps its parent's centre and that centre's sides of F and of S_d (0: unknown): a
// centre's side is then the crossing parity of the short segment from it instead of a ray out of
// the bounding box (SignedDistance::side with a reference point; exact either way). Where the
// parent's covering ball missed F (or S_d), the segment lies in that ball and crosses nothing: the
// side is the parent's, with no query (`same_f`, `same_s`).
// `hint`: the triangle of F nearest to the parent's centre, which the distance query tries first
// (it only orders the search: the same enclosure). `node`: the cell's entry in a prefetch's tree
// (-1: none).
struct Cell : Aabb {
  Vec3 ref = Vec3::Zero();
  std::int8_t ref_side_f = 0, ref_side_s = 0;
  bool same_f = false, same_s = false;
  std::int32_t hint = -1;
  std::int32_t node = -1;
};

// What a cell's classification leaves for its children: its centre's sides of F and of S_d (0:
// unknown), whether its covering ball missed each, F's triangle nearest to it, the first of its
// children's entries in the prefetch's tree (-1: none), and whether its facts about F came from there.
struct CellSides {
  std::int8_t f = 0, s = 0;
  bool off_f = false, off_s = false;
  std::int32_t nearest = -1;
  std::int32_t children = -1;
  bool prefetched = false;
};

// The facts about F of one cell, as the search computes them and a prefetch keeps them: the
// enclosure of the distance from the centre to F, its nearest triangle, the centre's side, and
// rule (3)'s verdict (0: not evaluated, 1: no extremum proven, 2: not proven). `expand`: the
// prefetch split the cell (`children`: its children's first entry, once made).
struct FNode {
  Interval du;
  std::uint32_t nearest = 0;
  std::int32_t children = -1, parent = -1;
  std::int8_t side = 0, ncp = 0;
  bool known = false, expand = false;
};

// Discard: rule (1) or (3), which depend on s alone; Beside: rule (2), which depends on S_d too.
enum class Verdict : unsigned char { Discard, Beside, Split, Missed, Unresolved };

// The nearest points on triangle `id` of the cell's points, when the disc bound of max_towards
// fails, by where such a point p lies (doc/offsets.md, rule (3)). In T's interior, x - p is a
// positive multiple of sign * n_T (outward n_T): checked here. In an edge's interior, a nonnegative
// combination of sign * n_T and sign * n_T' (T' across the edge), or no such p exists (an edge
// reflex on x's side): T' is within rho too, so its own check covers p. At a vertex v within rho,
// w.(x - v) is bounded from the corners. `sign`: +1 for a cell outside F, -1 inside; `floor`: a
// lower bound of min over the cell of w.(x - c).
bool sharp_bound_holds(const TriangleMesh& m, std::uint32_t id, const Vec3& w, const Vec3& c, double rho, double sign,
                       double floor) {
  const Face& f = m.faces[id];
  const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &q = m.vertices[f[2]];
  const Vec3 e1 = b - a, e2 = q - a;
  // w.N > 0 for the exact N = (b - a) x (q - a): the computed differences, cross and dot products
  // carry far less than 1e-13 |b - a| |q - a| of rounding (|w| <= 1 + 1e-15).
  if (!(sign * w.dot(e1.cross(e2)) > 1e-13 * e1.norm() * e2.norm())) return false;
  const double reach2 = rho * rho * (1.0 + 1e-9);  // beyond rho no point can be nearest
  for (const Vec3* v : {&a, &b, &q}) {
    const Vec3 cv = *v - c;
    if (cv.squaredNorm() > reach2 + 1e-12 * cv.squaredNorm()) continue;
    if (!(w.dot(cv) + 1e-14 * (cv.cwiseAbs().sum() + v->cwiseAbs().sum()) < floor)) return false;
  }
  return true;
}

// For each connected component G of F, a point q strictly on the `side` of F (-1 inside, +1
// outside) whose nearest points all lie on G: the segment from q to a nearest point stays off F,
// so q lies in the component of the solid's interior (exterior) that meets G's inner (outer) side.
// Tried just off a few faces of G, at a few distances; false when some component got no point.
bool side_points(const SignedDistance& sdf, int side, std::vector<Vec3>& points) {
  const TriangleMesh& m = sdf.mesh();
  std::size_t count = 0;
  const std::vector<std::uint32_t> comp = face_components(m, &count);
  std::vector<char> done(count, 0);
  std::vector<int> tries(count, 0);
  points.assign(count, Vec3::Zero());
  std::vector<std::uint32_t> ids;
  std::size_t found = 0;
  for (std::uint32_t i = 0; i < m.faces.size() && found < count; ++i) {
    const std::uint32_t g = comp[i];
    if (done[g] || tries[g]++ >= 16) continue;
    const Face& f = m.faces[i];
    const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &q = m.vertices[f[2]];
    const Vec3 n = (b - a).cross(q - a);
    const double longest = std::max({(b - a).norm(), (q - b).norm(), (a - q).norm()});
    if (!(n.norm() > 0.0) || !(longest > 0.0)) continue;
    const double height = n.norm() / longest;  // the least altitude
    const Vec3 centroid = (a + b + q) / 3.0;
    for (double delta = 0.1 * height; delta > 1e-3 * height && !done[g]; delta *= 0.125) {
      const Vec3 x = centroid + (side * delta / n.norm()) * n;
      const Interval du = sdf.unsigned_distance(x);
      if (!(du.lo > 0.0) || sdf.side(x, du) != side) continue;
      if (!sdf.triangles_within(x, du.hi, 256, ids)) continue;
      if (std::all_of(ids.begin(), ids.end(), [&](std::uint32_t id) { return comp[id] == g; })) {
        points[g] = x;
        done[g] = 1;
        ++found;
      }
    }
  }
  return found == count;
}

// The least of w.(x - c) over the cell's corners (a linear function's minimum over a box), and the
// magnitude that the rounding margins of increases_along scale with.
void cell_floor(const Aabb& cell, const Vec3& c, const Vec3& w, double* floor, double* scale) {
  double nearest_corner = kInf, corner_size = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 v = cell.corner(corner);
    nearest_corner = std::min(nearest_corner, w.dot(v - c));
    corner_size = std::max(corner_size, v.cwiseAbs().sum());
  }
  *floor = nearest_corner;
  *scale = corner_size + c.cwiseAbs().sum();
}

// Triangles of F's tree whose box may come within the radius of c and is not wholly behind the cell
// along w: a subtree is skipped when every point x of its box has w.(x - c) below `floor` (the
// cell's least corner value) by more than increases_along's margin for any triangle in it. A
// triangle in such a box passes increases_along's first test for certain (its points are points of
// the box, a linear function peaks at a box corner, and the margin here, with 3 * the box's largest
// coordinate sums, is at least the triangle's), so leaving it out changes no verdict. Thousands of
// triangles within the radius of a cell on a finely tessellated surface cost a few boxes.
struct AheadPolicy {
  Vec3 c, w;
  double radius_sq, floor, scale;
  std::size_t max_count;
  std::vector<std::uint32_t>& out;
  bool overflow = false;
  double bound(const Aabb& box) const {
    const double d2 = squared_distance_lower_bound(box, c);
    return d2 > radius_sq || behind(box) ? kInf : d2;
  }
  double prune_bound() const { return radius_sq; }
  bool done() const { return overflow; }
  void leaf(std::uint32_t f) {
    out.push_back(f);
    overflow = out.size() > max_count;
  }
  bool behind(const Aabb& box) const {
    double top = -kInf, size = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 v = box.corner(corner);
      top = std::max(top, w.dot(v - c) + 1e-14 * ((v - c).cwiseAbs().sum() + v.cwiseAbs().sum()));
    }
    for (int a = 0; a < 3; ++a) size += std::max(std::abs(box.lo[a]), std::abs(box.hi[a]));
    return floor - top > 1e-12 * (scale + 3.0 * size);
  }
};

}  // namespace

// Every nearest point p of a point x of the cell lies on the triangles within radius of c; w is a
// heuristic (from the nearest few hundred of them), the proof is increases_along's over all of them
// but those in subtrees wholly behind the cell (AheadPolicy).
bool no_critical_point(const SignedDistance& sdf, const Aabb& cell, const Vec3& c, double radius, double sign,
                       std::vector<std::uint32_t>& ids, Vec3* direction) {
  // Far from F, or on a finely tessellated F, the possibly-nearest set holds many triangles: the
  // direction comes from the first few hundred found (nearest first).
  const bool all = sdf.triangles_within(c, radius, 256, ids);
  if (ids.empty()) return false;
  const TriangleMesh& m = sdf.mesh();
  // Heuristic direction: min-norm point of the hull of the nearest-point directions (Frank-Wolfe).
  std::vector<Vec3> g(ids.size());
  for (std::size_t j = 0; j < ids.size(); ++j) {
    const Face& f = m.faces[ids[j]];
    const Vec3 v = c - closest_point_on_triangle(c, m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]]);
    if (!(v.norm() > 0)) return false;
    g[j] = v.normalized();
  }
  std::vector<double> lambda;
  const Vec3 x = min_norm_combination(g, lambda, 60);
  if (!(x.norm() > 1e-6)) return false;
  const Vec3 w = x.normalized();
  if (!all) {
    double floor = 0.0, scale = 0.0;
    cell_floor(cell, c, w, &floor, &scale);
    std::vector<std::uint32_t> boxed;
    AheadPolicy q{c, w, round_up(radius * radius) * (1.0 + 1e-12), floor, scale, std::size_t{1} << 16, boxed};
    traverse_nearest_first(sdf.tree(), q);
    if (q.overflow) return false;
    sdf.triangles_within_among(c, radius, boxed, ids);  // the exact within test on those
  }
  if (!increases_along(sdf, cell, c, radius, sign, w, ids)) return false;
  if (direction) *direction = w;
  return true;
}

// w.(x - c) is least at a corner; for each triangle, the disc bound first, then sharp_bound_holds.
bool increases_along(const SignedDistance& sdf, const Aabb& cell, const Vec3& c, double radius, double sign,
                     const Vec3& w, const std::vector<std::uint32_t>& ids) {
  const TriangleMesh& m = sdf.mesh();
  double nearest_corner = 0.0, scale = 0.0;
  cell_floor(cell, c, w, &nearest_corner, &scale);
  for (std::uint32_t id : ids) {
    const Face& f = m.faces[id];
    const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &q = m.vertices[f[2]];
    // Margin far above the rounding of the 3-term dot products and differences of these magnitudes.
    const double margin = 1e-12 * (scale + a.cwiseAbs().sum() + b.cwiseAbs().sum() + q.cwiseAbs().sum());
    if (nearest_corner - max_towards(w, c, radius, a, b, q) > margin) continue;
    if (!sharp_bound_holds(m, id, w, c, radius, sign, nearest_corner - margin)) return false;
  }
  return true;
}

std::string budget_note(const CompletenessResult& r) {
  return r.budget_exhausted ? " (cell budget reached after " + std::to_string(r.cells) + " cells)" : std::string();
}

// The vertex bound: a linear function on a triangle peaks at a vertex. The disc bound: with n* the
// exact unit normal and h* = (c - a).n*, every such p has p - c = u - h* n*, u orthogonal to n*,
// |u|^2 <= rho^2 - h*^2, so w.(p - c) <= |w - (w.n*) n*| sqrt(rho^2 - h*^2) - h* (w.n*). The
// computed normal n is within kappa of n* (cross-product rounding relative to |b - a| |q - a|,
// divided by |N|: large for slivers, where the vertex bound serves); h and w.n are widened by it.
// -inf when the ball misses the plane (no point of the triangle can be nearest).
double max_towards(const Vec3& w, const Vec3& c, double rho, const Vec3& a, const Vec3& b, const Vec3& q) {
  double vertices = -kInf;  // each with its rounding (a difference and a 3-term dot product)
  for (const Vec3* v : {&a, &b, &q})
    vertices = std::max(vertices, w.dot(*v - c) + 1e-14 * ((*v - c).cwiseAbs().sum() + v->cwiseAbs().sum()));
  const Vec3 e1 = b - a, e2 = q - a, N = e1.cross(e2);
  const double len = N.norm();
  if (!(len > 0.0)) return vertices;
  const double kappa = 1e-14 * e1.norm() * e2.norm() / len;
  if (!(kappa < 1e-3)) return vertices;
  const Vec3 n = N / len;
  const double ca = (c - a).norm();
  const double h = (c - a).dot(n), eh = ca * (kappa + 1e-15);
  const double wn = w.dot(n), ewn = kappa + 1e-15;
  const double h_lo = std::max(0.0, std::abs(h) - eh);
  if (h_lo > rho) return -kInf;
  const double wn_lo = std::max(0.0, std::abs(wn) - ewn);
  // rho^2 - h_lo^2 may cancel: its absolute rounding (below 3 u rho^2) is added before the root,
  // where it would otherwise grow to sqrt(u) rho; likewise |w|^2 <= 1 + 4 u.
  const double chord2 = rho * rho - h_lo * h_lo + 1e-15 * rho * rho;
  const double along = std::sqrt(std::max(0.0, 1.0 + 1e-14 - wn_lo * wn_lo)) * std::sqrt(std::max(0.0, chord2));
  const double across = -h * wn + std::abs(h) * ewn + std::abs(wn) * eh + eh * ewn;
  // The other roundings of these terms stay far below 1e-12 (rho + |c - a|).
  const double disc = along + across + 1e-12 * (rho + ca);
  return std::min(vertices, disc);
}

namespace {

// Everything a cell's verdict depends on: F, S_d (null when it is empty), the level, the band, the
// sides searched, the smallest cell; and where F's facts may be looked up (null: nowhere), the
// domain its cells tile.
struct SearchSetup {
  const SignedDistance* sdf = nullptr;
  const SignedDistance* surface = nullptr;
  double d = 0.0, eps = 0.0;
  bool need_min = true, need_max = true;  // minima in A, maxima in B
  double min_size = 0.0;
  const std::vector<FNode>* tree = nullptr;
  Aabb domain;
};

// Every bounded component of {s < d - eps} or {s > d + eps} lies in the input's box grown by
// max(d, 0): sublevel points are within d of the solid, exterior pockets within its hull. `band`
// is at least eps (CompletenessOptions::band_bound).
Aabb search_domain(const SignedDistance& sdf, double d, double band) {
  Aabb domain = sdf.bbox();
  const double grow = std::max(d, 0.0) + band + 1e-3 * domain.diagonal();
  domain.lo -= Vec3::Constant(grow);
  domain.hi += Vec3::Constant(grow);
  return domain;
}

std::vector<Cell> root_cells(const Aabb& domain) {
  std::vector<Cell> roots;
  const int n = 8;
  const Vec3 step = domain.extent() / n;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        Cell c;
        c.lo = domain.lo + Vec3(i * step.x(), j * step.y(), k * step.z());
        c.hi = domain.lo + Vec3((i + 1) * step.x(), (j + 1) * step.y(), (k + 1) * step.z());
        if (i == n - 1) c.hi.x() = domain.hi.x();
        if (j == n - 1) c.hi.y() = domain.hi.y();
        if (k == n - 1) c.hi.z() = domain.hi.z();
        c.node = static_cast<std::int32_t>(roots.size());  // a prefetch's tree holds the roots first
        roots.push_back(c);
      }
  return roots;
}

// Child k of `cell` (split at its rounded midpoint, so that the eight tile it exactly), with this
// cell's centre and that centre's sides as its reference.
Cell child_cell(const Cell& cell, const CellSides& sides, int k) {
  const Vec3 mid = 0.5 * (cell.lo + cell.hi);
  Cell child;
  child.ref = mid;
  child.ref_side_f = sides.f;
  child.ref_side_s = sides.s;
  child.same_f = sides.off_f && sides.f != 0;
  child.same_s = sides.off_s && sides.s != 0;
  child.hint = sides.nearest;
  child.node = sides.children < 0 ? -1 : sides.children + k;
  for (int a = 0; a < 3; ++a) {
    const bool upper = (k >> a) & 1;
    child.lo[a] = upper ? mid[a] : cell.lo[a];
    child.hi[a] = upper ? cell.hi[a] : mid[a];
  }
  return child;
}

// The eight children of `cell`, those that `keep` accepts.
template <class Keep>
void split_cell(const Cell& cell, const CellSides& sides, const Keep& keep, std::vector<Cell>& out) {
  for (int k = 0; k < 8; ++k) {
    const Cell child = child_cell(cell, sides, k);
    if (keep(child)) out.push_back(child);
  }
}

// Whether the closed boxes meet.
bool meets(const Aabb& a, const Aabb& b) {
  return (a.lo.array() <= b.hi.array()).all() && (b.lo.array() <= a.hi.array()).all();
}

// The covering radius of the cell about its rounded centre c, rounded up generously.
double covering_radius(const Cell& cell, const Vec3& c) {
  return round_up(0.5 * (cell.hi - cell.lo).norm() * (1 + 1e-12) +
                  4 * std::numeric_limits<double>::epsilon() * c.cwiseAbs().maxCoeff());
}

// The cell's facts about F but rule (3)'s (`n.ncp` is left as it is): the distance enclosure from
// its centre c (the parent's nearest triangle tried first: the same enclosure) and c's side, the
// parent's when the parent's covering ball missed F.
void f_facts(const SignedDistance& sdf, const Cell& cell, const Vec3& c, FNode& n) {
  n.du = sdf.unsigned_distance(c, &n.nearest, cell.hint);
  n.side = static_cast<std::int8_t>(cell.same_f ? cell.ref_side_f : sdf.side(c, n.du, cell.ref, cell.ref_side_f));
}

// What a cell's children need from its facts about F (r: its covering radius); the sides of S_d
// are the search's to add.
CellSides sides_from(const FNode& n, double r) {
  CellSides sides;
  sides.f = n.side;
  sides.off_f = n.du.lo > r;
  sides.nearest = static_cast<std::int32_t>(n.nearest);
  sides.children = n.children;
  return sides;
}

// Rule (1) for the sides searched: s over the cell, [s_min, s_max], stays within the band about d.
// (need_min, need_max: minima in A searched, maxima in B.)
bool within_band(bool need_min, bool need_max, double d, double band, double s_min, double s_max) {
  return (!need_min || s_min >= d - band) && (!need_max || s_max <= d + band);
}

// Rule (3): s has no extremum in the cell (s = `s` at its centre c, r its covering radius): it
// avoids the surface, where s is not smooth, and s increases along a proven direction.
bool no_extremum(const SignedDistance& sdf, const Cell& cell, const Vec3& c, double r, const Interval& s,
                 std::vector<std::uint32_t>& ids) {
  return std::abs(s.lo) > r && std::abs(s.hi) > r && std::signbit(s.lo) == std::signbit(s.hi) &&
         no_critical_point(sdf, cell, c, round_up(std::max(std::abs(s.lo), std::abs(s.hi)) + 2 * r),
                           s.lo > 0.0 ? 1.0 : -1.0, ids);
}

// The verdict on one cell (doc/offsets.md, "(c) Completeness", rules (1)-(3)); `sides` receives
// what its children need.
Verdict classify(const SearchSetup& st, const Cell& cell, CellSides& sides, std::vector<std::uint32_t>& ids) {
  const SignedDistance& sdf = *st.sdf;
  const double d = st.d, eps = st.eps;
  const Vec3 c = 0.5 * (cell.lo + cell.hi);
  const double r = covering_radius(cell, c);
  const FNode* known = st.tree && cell.node >= 0 && (*st.tree)[cell.node].known ? &(*st.tree)[cell.node] : nullptr;
  FNode computed;
  if (!known) f_facts(sdf, cell, c, computed);
  const FNode& ff = known ? *known : computed;
  const Interval du = ff.du;
  const int sf = ff.side;
  sides = sides_from(ff, r);
  sides.prefetched = known != nullptr;
  const Interval s = with_side(du, sf);
  const double s_min = s.lo - r, s_max = s.hi + r;  // s over the cell (1-Lipschitz)
  // (1) the cell holds no point of A = {s < d - eps} nor of B = {s > d + eps} (of those searched).
  if (within_band(st.need_min, st.need_max, d, eps, s_min, s_max)) return Verdict::Discard;
  // (2) the cell misses S_d: all of it is on one side of S_d. A lower bound of dist(c, S_d) that
  // stops below r suffices (no nearest triangle needed: far cheaper on a large S_d).
  const double to_surface = !st.surface ? kInf : st.surface->distance_lower(c, 2.0 * r, r);
  sides.off_s = to_surface > r;
  // The centre's side of S_d, when it is off S_d: needed here when the cell misses S_d, and as the
  // children's reference when the cell is split. `lower`: a lower bound of dist(c, S_d), or
  // negative for one found here (only when the side is not the parent's).
  const auto side_of_surface = [&](double lower) {
    if (!st.surface) return 1;
    if (cell.same_s) return static_cast<int>(cell.ref_side_s);
    if (lower < 0.0) lower = st.surface->distance_lower(c, r);
    return lower > 0.0 ? st.surface->side(c, Interval{lower, kInf}, cell.ref, cell.ref_side_s) : 0;
  };
  if (sides.off_s) {  // the cell lies on the side of its centre
    sides.s = static_cast<std::int8_t>(side_of_surface(to_surface));
    const bool inside = sides.s < 0;
    if (inside ? (!st.need_max || s_max <= d + eps) : (!st.need_min || s_min >= d - eps)) return Verdict::Beside;
    if (inside ? s.lo - r > d + eps : s.hi + r < d - eps)
      return Verdict::Missed;  // wholly in B inside S_d, or wholly in A outside S_d
  }
  // (3) no extremum of s in the cell.
  if (known && known->ncp != 0 ? known->ncp == 1 : no_extremum(sdf, cell, c, r, s, ids)) return Verdict::Discard;
  if ((cell.hi - cell.lo).maxCoeff() < st.min_size) return Verdict::Unresolved;
  // Split: the children's reference side, when the centre is off S_d (most split cells touch S_d).
  if (!sides.off_s) sides.s = static_cast<std::int8_t>(side_of_surface(-1.0));
  return Verdict::Split;
}

// The verdicts on a list of cells, in parallel (each is a function of its cell alone).
void classify_all(const SearchSetup& st, const std::vector<Cell>& cells, std::vector<Verdict>& verdict,
                  std::vector<CellSides>& sides) {
  verdict.assign(cells.size(), Verdict::Split);
  sides.assign(cells.size(), CellSides{});
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, cells.size(), 32), [&](const auto& range) {
    thread_local std::vector<std::uint32_t> ids;
    for (std::size_t i = range.begin(); i != range.end(); ++i) verdict[i] = classify(st, cells[i], sides[i], ids);
  });
}

}  // namespace

// What a search stopped by missed cells leaves for resume_completeness.
struct CompletenessCheckpoint::State {
  SearchSetup setup;                         // as searched (its pointers are not kept)
  std::unique_ptr<SignedDistance> surface;   // S_d as searched
  int side = 0;                   // the one-sided search's side of F (0: both sides searched)
  std::vector<Vec3> side_points;  // and its points, one per component of that side
  std::vector<Cell> frontier;     // the cells not examined, all at depth frontier_depth
  int frontier_depth = 0;
  std::vector<Cell> open;         // the missed and unresolved cells
  double discarded_volume = 0.0;
  const std::vector<FNode>* nodes_of = nullptr;  // the prefetch tree the cells' nodes index (identity only)
};

CompletenessCheckpoint::CompletenessCheckpoint() = default;
CompletenessCheckpoint::~CompletenessCheckpoint() = default;
CompletenessCheckpoint::CompletenessCheckpoint(CompletenessCheckpoint&&) noexcept = default;
CompletenessCheckpoint& CompletenessCheckpoint::operator=(CompletenessCheckpoint&&) noexcept = default;

struct CompletenessPrefetch::State {
  const SignedDistance* sdf = nullptr;
  double d = 0.0, band_bound = 0.0;
  bool need_min = true, need_max = true;  // the one-sided search's guess
  Aabb domain;
  double min_size = 0.0;
  std::uint64_t max_cells = 0;
  std::vector<FNode> nodes;  // the roots first, then each split cell's 8 children together
  std::uint64_t known = 0;
  bool full = false;  // no more children are made
  bool done = false;  // every node is known
};

CompletenessPrefetch::CompletenessPrefetch(const SignedDistance& sdf, double d, double band_bound,
                                           std::uint64_t max_cells)
    : state(std::make_unique<State>()) {
  State& s = *state;
  s.sdf = &sdf;
  s.d = d;
  s.band_bound = band_bound;
  s.need_min = !(d > 0.0);  // as the search settles it once the sides' points are found
  s.need_max = !(d < 0.0);
  s.domain = search_domain(sdf, d, band_bound);
  s.min_size = CompletenessOptions{}.min_cell_relative * s.domain.diagonal();
  s.max_cells = std::min<std::uint64_t>(max_cells, std::uint64_t{1} << 30);
  const std::size_t roots = root_cells(s.domain).size();
  if (roots > s.max_cells) {
    s.done = s.full = true;
    return;
  }
  try {
    s.nodes.reserve(s.max_cells);  // address space only until used; never moved
  } catch (const std::bad_alloc&) {  // no address space for it: no prefetch
    s.done = s.full = true;
    return;
  }
  s.nodes.resize(roots);
}

CompletenessPrefetch::~CompletenessPrefetch() = default;

std::uint64_t CompletenessPrefetch::cells() const { return state->known; }
bool CompletenessPrefetch::finished() const { return state->done; }

namespace {

// A prefetched cell: its facts, then whether to expand it (a guess at whether the search will split
// it). Not expanded: cells set aside by rule (1) for the band bound; cells whose s misses the level
// by more than a quarter of the band bound (they lie off S_d but where its faces bulge most, and
// the search's rule (2) sets them aside: expanding them made rotor's -20 % prefetch 6x the search);
// cells that rule (3) sets aside; the smallest.
void prefetch_cell(const CompletenessPrefetch::State& st, const Cell& cell, FNode& n, std::vector<std::uint32_t>& ids) {
  const Vec3 c = 0.5 * (cell.lo + cell.hi);
  const double r = covering_radius(cell, c);
  f_facts(*st.sdf, cell, c, n);
  n.known = true;
  const Interval s = with_side(n.du, n.side);
  const double d = st.d, band = st.band_bound;
  if (within_band(st.need_min, st.need_max, d, band, s.lo - r, s.hi + r)) return;
  if (!(s.lo - r <= d + 0.25 * band && s.hi + r >= d - 0.25 * band)) return;
  n.ncp = no_extremum(*st.sdf, cell, c, r, s, ids) ? 1 : 2;
  if (n.ncp == 1 || (cell.hi - cell.lo).maxCoeff() < st.min_size) return;
  n.expand = true;
}

// The cell of tree node `node`, made from its root by the search's splits (a node keeps no box: a
// prefetch's frontier of cells would hold more memory than its tree).
Cell cell_of(const CompletenessPrefetch::State& s, const std::vector<Cell>& roots, std::int32_t node) {
  int path[64];  // child indices, leaf first (cells split 64 times are below any double's resolution)
  int depth = 0;
  while (s.nodes[node].parent >= 0) {
    const std::int32_t parent = s.nodes[node].parent;
    path[depth++] = node - s.nodes[parent].children;
    node = parent;
  }
  Cell cell = roots[node];
  while (depth > 0) {
    const CellSides sides = sides_from(s.nodes[cell.node], covering_radius(cell, 0.5 * (cell.lo + cell.hi)));
    cell = child_cell(cell, sides, path[--depth]);
  }
  return cell;
}

// The prefetch's tree for this search, when it was made for its level and domain (else null).
const std::vector<FNode>* prefetched_tree(const CompletenessOptions& options, const SignedDistance& sdf,
                                          const SearchSetup& st) {
  const CompletenessPrefetch* p = options.prefetch;
  if (!p || !p->state) return nullptr;
  const CompletenessPrefetch::State& s = *p->state;
  const bool same = s.sdf == &sdf && s.d == st.d && s.domain.lo == st.domain.lo && s.domain.hi == st.domain.hi;
  return same ? &s.nodes : nullptr;
}

}  // namespace

void CompletenessPrefetch::run(const std::atomic<bool>& stop) {
  State& s = *state;
  if (s.done || stop.load(std::memory_order_relaxed)) return;
  const std::vector<Cell> roots = root_cells(s.domain);
  std::vector<std::int32_t> frontier;  // the nodes not known yet, all at one depth
  for (std::size_t i = 0; i < s.nodes.size(); ++i)
    if (!s.nodes[i].known) frontier.push_back(static_cast<std::int32_t>(i));
  while (!frontier.empty()) {
    std::atomic<std::uint64_t> done{0};
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, frontier.size(), 32), [&](const auto& range) {
      thread_local std::vector<std::uint32_t> ids;
      std::uint64_t count = 0;
      for (std::size_t i = range.begin(); i != range.end() && !stop.load(std::memory_order_relaxed); ++i) {
        FNode& n = s.nodes[frontier[i]];
        if (n.known) continue;
        prefetch_cell(s, cell_of(s, roots, frontier[i]), n, ids);
        ++count;
      }
      done += count;
    });
    s.known += done;
    // Stopped: the depth may be unfinished, taken up by the next run.
    if (std::any_of(frontier.begin(), frontier.end(), [&](std::int32_t i) { return !s.nodes[i].known; })) return;
    // The next depth: the children of the cells to expand, while they fit.
    std::vector<std::int32_t> next;
    for (std::int32_t i : frontier) {
      if (!s.nodes[i].expand || s.full) continue;
      if (s.nodes.size() + 8 > s.max_cells) {
        s.full = true;
        break;
      }
      const auto first = static_cast<std::int32_t>(s.nodes.size());
      s.nodes[i].children = first;
      s.nodes.resize(s.nodes.size() + 8);
      for (std::int32_t k = 0; k < 8; ++k) {
        s.nodes[first + k].parent = i;
        next.push_back(first + k);
      }
    }
    frontier = std::move(next);  // once full, the children made so far are the last depth
  }
  s.done = true;
}

namespace {

// The branch and bound from `frontier`, level by level, counting on from result.cells. `keep`
// (optional) receives the cells left when it stops at missed cells.
void run_search(const SearchSetup& st, std::vector<Cell> frontier, const CompletenessOptions& options,
                CompletenessResult& result, CompletenessCheckpoint::State* keep) {
  // The budget bounds the cells evaluated and so the memory: a level starts only when it fits, and
  // a cell is split only while its children fit too (the next level would not start otherwise).
  std::vector<Vec3> missed;
  std::vector<Verdict> verdict;
  std::vector<CellSides> sides;
  int depth = 0;
  while (!frontier.empty() && !result.budget_exhausted) {
    if (result.cells + frontier.size() > options.max_cells) {
      result.budget_exhausted = true;
      break;
    }
    classify_all(st, frontier, verdict, sides);
    std::vector<Cell> next;
    const std::uint64_t level_end = result.cells + frontier.size();
    for (std::size_t i = 0; i < frontier.size(); ++i) {
      ++result.cells;
      result.prefetched += sides[i].prefetched;
      const Cell& cell = frontier[i];
      switch (verdict[i]) {
        case Verdict::Discard:
        case Verdict::Beside: result.discarded_volume += cell.extent().prod(); break;
        case Verdict::Missed:
          if (missed.size() < kMissedKept) missed.push_back(0.5 * (cell.lo + cell.hi));
          if (keep) keep->open.push_back(cell);
          break;
        case Verdict::Unresolved:
          if (result.unresolved.size() < kUnresolvedReported) result.unresolved.push_back(0.5 * (cell.lo + cell.hi));
          if (keep) keep->open.push_back(cell);
          break;
        case Verdict::Split:
          if (level_end + next.size() + 8 > options.max_cells) {
            result.budget_exhausted = true;
            if (result.unresolved.size() < kUnresolvedReported) result.unresolved.push_back(0.5 * (cell.lo + cell.hi));
            break;
          }
          split_cell(cell, sides[i], [](const Cell&) { return true; }, next);
          break;
      }
    }
    frontier = std::move(next);
    ++depth;
    // A certain violation settles the answer; its points are the seeds the caller needs.
    if (!missed.empty()) break;
  }
  result.missed = spread_points(missed, kMissedReported);
  if (result.missed.empty())
    for (const Cell& cell : frontier)
      if (result.unresolved.size() < kUnresolvedReported) result.unresolved.push_back(0.5 * (cell.lo + cell.hi));
  result.complete = frontier.empty() && !result.budget_exhausted && result.missed.empty() && result.unresolved.empty();
  if (keep) {
    keep->frontier = std::move(frontier);
    keep->frontier_depth = depth;
  }
}

}  // namespace

CompletenessResult certify_completeness(const SignedDistance& sdf, const TriangleMesh& offset, double d, double eps,
                                        const CompletenessOptions& options, CompletenessCheckpoint* checkpoint) {
  Timer timer;
  CompletenessResult result;
  if (checkpoint) checkpoint->state.reset();
  std::unique_ptr<SignedDistance> surface;
  if (!offset.faces.empty()) surface = std::make_unique<SignedDistance>(offset);
  SearchSetup st;
  st.sdf = &sdf;
  st.surface = surface.get();
  st.d = d;
  st.eps = eps;
  const Aabb domain = search_domain(sdf, d, std::max(eps, options.band_bound));
  st.domain = domain;
  st.min_size = options.min_cell_relative * domain.diagonal();
  st.tree = prefetched_tree(options, sdf, st);
  result.domain_volume = domain.extent().prod();

  // Which extrema the search must exclude (doc/offsets.md, "Completeness"). Above the band
  // (d - eps > 0) a bad component of A has its minimum inside the solid, in a component of the
  // solid's interior, and those are checked through one point each; below it (d + eps < 0) B's
  // maxima lie outside the solid, and the exterior's components are checked likewise. The
  // search then needs only the other side, and cells across F are set aside by s alone.
  int side = 0;
  std::vector<Vec3> points;
  if (options.one_sided && (d - eps > 0.0 || d + eps < 0.0)) {
    side = d > 0.0 ? -1 : 1;
    if (side_points(sdf, side, points)) {
      for (const Vec3& x : points) {
        // Off S_d: S_d lies within eps of the level, x on the other side of F.
        const int sx = !surface ? 1 : surface->side(x, surface->unsigned_distance(x));
        if (sx != side && result.missed.size() < kMissedReported) result.missed.push_back(x);  // wholly on the wrong side
      }
      if (!result.missed.empty()) {
        result.seconds = timer.seconds();
        return result;
      }
      (d > 0.0 ? st.need_min : st.need_max) = false;
    } else {
      side = 0;
      points.clear();
    }
  }
  auto keep = checkpoint ? std::make_unique<CompletenessCheckpoint::State>() : nullptr;
  run_search(st, root_cells(domain), options, result, keep.get());
  if (keep && !result.missed.empty() && !result.budget_exhausted) {
    keep->setup = st;
    keep->setup.sdf = nullptr;
    keep->setup.surface = nullptr;
    keep->setup.tree = nullptr;
    keep->nodes_of = st.tree;
    keep->surface = std::move(surface);
    keep->side = side;
    keep->side_points = std::move(points);
    keep->discarded_volume = result.discarded_volume;
    checkpoint->state = std::move(keep);
  }
  result.seconds = timer.seconds();
  return result;
}

// doc/offsets.md, "Resuming the search". The first search's leaves tile its domain; those set
// aside by rules (1) and (3) depend on s alone (and hold for a wider band); those set aside by
// rule (2) hold for the union when they meet none of the added components' boxes (they then miss
// the added parts and lie outside them, so their side is unchanged). The rest is searched again
// with the union: the cells left, missed or unresolved, and every rule-(2) leaf that meets a box,
// found by replaying the first search within the boxes (the same cells with the same references).
CompletenessResult resume_completeness(const SignedDistance& sdf, const TriangleMesh& offset,
                                       const TriangleMesh& added, double d, double eps,
                                       CompletenessCheckpoint& checkpoint, const CompletenessOptions& options) {
  Timer timer;
  const std::unique_ptr<CompletenessCheckpoint::State> cp = std::move(checkpoint.state);
  const auto fresh = [&] { return certify_completeness(sdf, offset, d, eps, options); };
  if (!cp || added.faces.empty() || d != cp->setup.d || !(eps >= cp->setup.eps) ||
      offset.faces.size() != cp->surface->mesh().faces.size() + added.faces.size())
    return fresh();
  // The one-sided search stays one-sided only while the band keeps clear of F.
  if (cp->side != 0 && !(d > 0.0 ? d - eps > 0.0 : d + eps < 0.0)) return fresh();
  const Aabb domain = cp->setup.domain;  // the first search's
  const SignedDistance parts(added);
  // The boxes of the added components: each holds its component and what it encloses.
  std::size_t count = 0;
  const std::vector<std::uint32_t> comp = face_components(added, &count);
  std::vector<Aabb> boxes(count);
  for (std::size_t i = 0; i < added.faces.size(); ++i)
    for (std::uint32_t v : added.faces[i]) boxes[comp[i]].extend(added.vertices[v]);
  const auto near_parts = [&](const Aabb& cell) {
    return std::any_of(boxes.begin(), boxes.end(), [&](const Aabb& b) { return meets(cell, b); });
  };
  // +1 outside the added parts, -1 inside, 0 on them (exact).
  const auto side_of_parts = [&](const Vec3& p) {
    const bool in_a_box = std::any_of(boxes.begin(), boxes.end(), [&](const Aabb& b) { return b.contains(p); });
    return in_a_box ? parts.side(p) : 1;
  };
  CompletenessResult result;
  result.resumed = true;
  result.domain_volume = domain.extent().prod();
  result.discarded_volume = cp->discarded_volume;  // less the rule-(2) leaves examined again
  // The union's side is S_d's, reversed inside the added parts.
  for (const Vec3& x : cp->side_points) {
    const int k = side_of_parts(x);
    if (k == 0) return fresh();
    if (k < 0 && result.missed.size() < kMissedReported) result.missed.push_back(x);  // now on the wrong side
  }
  if (!result.missed.empty()) {
    result.seconds = timer.seconds();
    return result;
  }
  const auto to_union = [&](Cell& cell) {
    cell.same_s = false;  // the segment from the reference may cross the added parts
    if (cell.ref_side_s == 0) return;
    const int k = side_of_parts(cell.ref);
    cell.ref_side_s = static_cast<std::int8_t>(k == 0 ? 0 : k * cell.ref_side_s);
  };
  std::vector<Cell> frontier;
  for (Cell cell : cp->frontier)
    if (!near_parts(cell)) {  // those near the added parts are replayed
      to_union(cell);
      frontier.push_back(cell);
    }
  cp->frontier = std::vector<Cell>();
  // The missed and unresolved cells are all examined again; those the replay meets again are not
  // added twice.
  const auto corners = [](const Cell& c) {
    return std::array<double, 6>{c.lo.x(), c.lo.y(), c.lo.z(), c.hi.x(), c.hi.y(), c.hi.z()};
  };
  std::set<std::array<double, 6>> open_near;
  for (Cell cell : cp->open) {
    if (near_parts(cell)) open_near.insert(corners(cell));
    to_union(cell);
    frontier.push_back(cell);
  }
  // The replay, with S_d as it was: cells near the added parts only, down to the first search's frontier.
  SearchSetup before = cp->setup;
  before.sdf = &sdf;
  before.surface = cp->surface.get();
  before.tree = prefetched_tree(options, sdf, before);
  if (before.tree != cp->nodes_of) {  // the kept cells' nodes index another tree, or none
    for (Cell& cell : frontier) cell.node = -1;
  }
  std::vector<Cell> level;
  for (const Cell& root : root_cells(domain))
    if (near_parts(root)) level.push_back(root);
  std::vector<Verdict> verdict;
  std::vector<CellSides> sides;
  for (int depth = 0; !level.empty(); ++depth) {
    if (depth == cp->frontier_depth) {
      for (Cell& cell : level) {
        to_union(cell);
        frontier.push_back(cell);
      }
      break;
    }
    if (result.cells + level.size() > options.max_cells) return fresh();
    classify_all(before, level, verdict, sides);
    std::vector<Cell> next;
    for (std::size_t i = 0; i < level.size(); ++i) {
      ++result.cells;
      switch (verdict[i]) {
        case Verdict::Discard: break;  // rules (1), (3): s alone
        case Verdict::Beside:
        case Verdict::Missed:
        case Verdict::Unresolved: {
          Cell cell = level[i];
          if (verdict[i] == Verdict::Beside) result.discarded_volume -= cell.extent().prod();
          else if (open_near.count(corners(cell))) break;
          to_union(cell);
          frontier.push_back(cell);
          break;
        }
        case Verdict::Split:
          split_cell(level[i], sides[i], [&](const Cell& c) { return near_parts(c); }, next);
          break;
      }
    }
    level = std::move(next);
  }
  const SignedDistance both(offset);
  SearchSetup now = cp->setup;
  now.sdf = &sdf;
  now.surface = &both;
  now.eps = eps;
  now.tree = before.tree;
  run_search(now, std::move(frontier), options, result, nullptr);
  result.seconds = timer.seconds();
  return result;
}

}  // namespace cdbench
