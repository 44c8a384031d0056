#include "distance/support_planes.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>

#include "bvh/bvh.h"
#include "core/interval.h"
#include "distance/depth_bound.h"
#include "distance/point_triangle_distance.h"
#include "util/large_pages.h"

namespace cdbench {

namespace {

// One face's scan: whether its plane supports F within `slack` and, if so, the largest offset e
// (rounded up) of F's vertices beyond it.
struct FaceScan {
  enum Kind : std::uint8_t { Degenerate, Refuted, Supports, Unscanned } kind = Unscanned;
  double e = 0.0;
};

// A box tree over F's vertices: the vertices beyond a face's plane are found without a scan of
// every vertex (a supporting face of a finely faceted tube had to test all of them: 2,500 outer
// faces x 10,000 vertices passed the budget below, and the tube got no planes).
using VertexTree = Bvh<Aabb>;
VertexTree vertex_tree(const std::vector<Vec3>& V) {
  BvhBuildOptions o;
  o.leaf_size = 8;
  return build_bvh<Aabb>(V, [&](const std::uint32_t* idx, std::uint32_t n) {
    Aabb b;
    for (std::uint32_t i = 0; i < n; ++i) b.extend(V[idx[i]]);
    return b;
  }, o);
}

// The traversal's policy for one face's plane: nodes by the highest value a vertex of theirs can
// give (its negative, as the traversal visits the least first); a node none of whose vertices can
// raise e is skipped. For a vertex v of a box with n-most corner c* and |coordinates| <= M,
//   computed n.v - d + its error <= exact n.v - d + 2 error_v <= exact n.c* - d + 2 E
//                                  <= value(c*) + error(c*) + 2 E,
// E = 2e-15 (sum |n_k| M_k + |d|) >= error_v (each operation is monotone), and round_up and the
// doubles' sums add well under 2 E more: so a skipped vertex's rounded-up offset is below e, and e
// is exactly a scan's maximum.
struct BeyondPlane {
  const std::vector<Vec3>& V;
  const TrianglePlane& pl;
  double slack;
  double e = -std::numeric_limits<double>::infinity();
  std::int64_t refuter = -1;
  std::uint64_t work = 0;
  double bound(const Aabb& b) {
    ++work;
    Vec3 c;
    double T = std::abs(pl.d);
    for (int k = 0; k < 3; ++k) {
      c[k] = pl.n[k] >= 0.0 ? b.hi[k] : b.lo[k];
      T += std::abs(pl.n[k] * std::max(std::abs(b.lo[k]), std::abs(b.hi[k])));
    }
    const PlaneOffset o = plane_offset(pl.n, pl.d, c);
    return -(o.value + o.error + 4.0 * (2e-15 * T));
  }
  double prune_bound() const { return -e; }
  void leaf(std::uint32_t k) {
    ++work;
    const PlaneOffset o = plane_offset(pl.n, pl.d, V[k]);  // exact n.v - d <= value + error
    e = std::max(e, round_up(o.value + o.error));
    if (e > slack) refuter = k;
  }
  bool done() const { return refuter >= 0; }
};

// The vertex at `refuter` is tried first and, on a refutation, replaced by the refuting one:
// neighbouring faces of a non-convex part are mostly refuted by the same vertices. `work` gains
// the vertex tests and the tree's node bounds.
FaceScan scan_face(const std::vector<Vec3>& V, const VertexTree& tree, const TrianglePlane& pl, double slack,
                   std::size_t& refuter, std::uint64_t& work) {
  FaceScan r;
  BeyondPlane q{V, pl, slack};
  q.leaf(static_cast<std::uint32_t>(refuter));
  if (!q.done()) traverse_nearest_first(tree, q);
  work += q.work;
  if (q.done()) {
    refuter = static_cast<std::size_t>(q.refuter);
    r.kind = FaceScan::Refuted;
    return r;
  }
  r.kind = FaceScan::Supports;
  r.e = q.e;
  return r;
}

}  // namespace

SupportPlanes SupportPlanes::build(const TriangleMesh& F, double max_work, double relative_slack) {
  SupportPlanes S;
  if (F.faces.empty()) return S;
  const double diagonal = F.bbox().diagonal();
  const double slack = relative_slack * diagonal;
  const std::size_t n = F.faces.size();
  // Planes by their normal and offset rounded to 1e-9: a face on the plane of one found before (a
  // planar face of many triangles, a tube's end) maps to it unscanned. Its bound is that plane's,
  // valid as any supporting plane's; near its own within the rounding.
  const auto key_of = [&](const TrianglePlane& pl) {
    const double q = 1e9, dq = 1e9 / (1.0 + diagonal);
    return std::array<long long, 4>{std::llround(pl.n[0] * q), std::llround(pl.n[1] * q), std::llround(pl.n[2] * q),
                                    std::llround(pl.d * dq)};
  };
  const auto finite_key = [&](const TrianglePlane& pl) { return std::abs(pl.d) < 1e6 * (1.0 + diagonal); };
  const auto near = [&](const TrianglePlane& pl, const Vec3& qn, double qd) {
    return (pl.n - qn).cwiseAbs().maxCoeff() <= 1e-9 && std::abs(pl.d - qd) <= 1e-9 * (1.0 + diagonal);
  };
  // Its pages first touched on every thread when large (a million faces: 16 MB).
  std::vector<FaceScan, LargePageAllocator<FaceScan>> scan(n);
  const VertexTree tree = vertex_tree(F.vertices);
  // The scans run in fixed blocks of faces, in parallel, each block with its own refuter and its
  // own map of planes found (the work, and so whether the budget holds, is the same for any number
  // of threads). A block stops once the work of all (flushed now and then) passes the budget: the
  // set is then empty whatever the other blocks find.
  constexpr std::size_t kBlock = 2048;
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::atomic<std::uint64_t> total_work{0};
  const std::uint64_t budget = max_work >= 1.8e19 ? std::numeric_limits<std::uint64_t>::max()
                                                  : static_cast<std::uint64_t>(std::max(0.0, max_work));
  std::vector<std::vector<std::array<long long, 4>>> block_keys(blocks);  // each block's `seen` keys
  tbb::parallel_for(std::size_t{0}, blocks, [&](std::size_t b) {
    std::size_t refuter = 0;
    std::uint64_t work = 0;
    std::map<std::array<long long, 4>, std::pair<Vec3, double>> seen;  // a key's first supporting plane
    const std::size_t end = std::min(n, (b + 1) * kBlock);
    for (std::size_t fi = b * kBlock; fi < end; ++fi) {
      if (total_work.load(std::memory_order_relaxed) > budget) return;
      const Face& f = F.faces[fi];
      const TrianglePlane pl = make_triangle_plane(F.vertices[f[0]], F.vertices[f[1]], F.vertices[f[2]]);
      if (!std::isfinite(pl.eps)) {
        scan[fi].kind = FaceScan::Degenerate;
        continue;
      }
      if (finite_key(pl)) {
        const auto it = seen.find(key_of(pl));
        if (it != seen.end() && near(pl, it->second.first, it->second.second)) continue;  // Unscanned
      }
      const std::uint64_t before = work;
      scan[fi] = scan_face(F.vertices, tree, pl, slack, refuter, work);
      if (scan[fi].kind == FaceScan::Supports && finite_key(pl))
        seen.emplace(key_of(pl), std::make_pair(pl.n, pl.d));
      total_work.fetch_add(work - before, std::memory_order_relaxed);
    }
    for (const auto& entry : seen) block_keys[b].push_back(entry.first);
  });
  if (total_work.load() > budget) return SupportPlanes();
  // In face order, as one scan would: a face whose key matches a plane found before maps to it; any
  // other takes its own scan's result (a face its block left unscanned, matching a plane of the
  // block that itself mapped to an earlier block's, is scanned here: rare).
  // Only faces whose key is some supporting (or unscanned) face's can map to a plane: the others'
  // outcome is their own scan's (refuted), so they are set apart on all threads first (armadillo
  // x16: 832,000 faces looked up one by one took 0.13 s). Those keys are the blocks' `seen` maps'
  // (a supporting face's key is entered there, an unscanned face's was found there).
  std::vector<std::array<long long, 4>> keys;  // of the faces that may support F
  for (const auto& k : block_keys) keys.insert(keys.end(), k.begin(), k.end());
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  std::vector<std::uint8_t> may_map(n, 0);  // a refuted face whose key is among them
  if (!keys.empty())
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t fi = r.begin(); fi < r.end(); ++fi) {
      if (scan[fi].kind != FaceScan::Refuted) continue;
      const Face& f = F.faces[fi];
      const TrianglePlane pl = make_triangle_plane(F.vertices[f[0]], F.vertices[f[1]], F.vertices[f[2]]);
      may_map[fi] = finite_key(pl) && std::binary_search(keys.begin(), keys.end(), key_of(pl));
    }
  });
  std::vector<SupportPlane> found;  // in face order
  std::vector<std::int64_t> found_of(n, -1);  // each face's entry of `found`, if any
  std::map<std::array<long long, 4>, std::size_t> seen;
  bool all = true;
  std::uint64_t work = total_work.load();
  std::size_t refuter = 0;
  for (std::size_t fi = 0; fi < n; ++fi) {
    if (scan[fi].kind == FaceScan::Degenerate || (scan[fi].kind == FaceScan::Refuted && !may_map[fi])) {
      all = false;
      continue;
    }
    const Face& f = F.faces[fi];
    const TrianglePlane pl = make_triangle_plane(F.vertices[f[0]], F.vertices[f[1]], F.vertices[f[2]]);
    if (finite_key(pl)) {
      const auto it = seen.find(key_of(pl));
      if (it != seen.end() && near(pl, found[it->second].n, found[it->second].d)) {
        found_of[fi] = static_cast<std::int64_t>(it->second);
        continue;
      }
    }
    if (scan[fi].kind == FaceScan::Unscanned) {
      scan[fi] = scan_face(F.vertices, tree, pl, slack, refuter, work);
      if (work > budget) return SupportPlanes();
    }
    if (scan[fi].kind != FaceScan::Supports) {
      all = false;
      continue;
    }
    SupportPlane p;
    p.n = pl.n;
    p.d = pl.d;
    p.e = scan[fi].e;
    p.norm_lo = norm3_lower(pl.n.squaredNorm());
    p.norm_up = norm3_upper(pl.n.squaredNorm());
    if (finite_key(pl)) seen.emplace(key_of(pl), found.size());
    found_of[fi] = static_cast<std::int64_t>(found.size());
    found.push_back(p);
  }
  S.convex_ = all;
  // Coplanar faces give (nearly) the same plane: one of them is kept (any subset stays valid), and
  // each face maps to it (its plane's bound, within the merging tolerance, is the kept one's).
  std::vector<std::size_t> order(found.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const SupportPlane &x = found[a], &y = found[b];
    for (int k = 0; k < 3; ++k)
      if (x.n[k] != y.n[k]) return x.n[k] < y.n[k];
    return x.d < y.d || (x.d == y.d && a < b);
  });
  std::vector<std::int32_t> kept(found.size());  // each entry's plane in planes_
  const double scale = 1e-12 * (1.0 + diagonal);
  for (const std::size_t i : order) {
    const SupportPlane& p = found[i];
    std::int64_t same = -1;
    for (std::size_t k = S.planes_.size(); k-- > 0 && same < 0;) {
      const SupportPlane& q = S.planes_[k];
      if (p.n[0] - q.n[0] > 1e-12) break;  // sorted by n[0]: no later kept plane is nearer
      if ((p.n - q.n).cwiseAbs().maxCoeff() <= 1e-12 && std::abs(p.d - q.d) <= scale)
        same = static_cast<std::int64_t>(k);
    }
    if (same >= 0) {
      if (p.e < S.planes_[static_cast<std::size_t>(same)].e) S.planes_[static_cast<std::size_t>(same)] = p;
    } else {
      same = static_cast<std::int64_t>(S.planes_.size());
      S.planes_.push_back(p);
    }
    kept[i] = static_cast<std::int32_t>(same);
  }
  S.face_plane_.resize(F.faces.size());
  for (std::size_t f = 0; f < F.faces.size(); ++f)
    S.face_plane_[f] = found_of[f] < 0 ? -1 : kept[static_cast<std::size_t>(found_of[f])];
  S.build_groups(0.5 * (F.bbox().lo + F.bbox().hi));
  return S;
}

void SupportPlanes::build_groups(const Vec3& centre) {
  constexpr std::uint32_t kLeaf = 8;
  groups_.clear();
  order_.resize(planes_.size());
  for (std::uint32_t j = 0; j < order_.size(); ++j) order_[j] = j;
  if (planes_.empty()) return;
  // The planes' offsets are measured from F's box centre (n.y - d = n.(y - c) + (n.c - d)): a
  // group's bound is then tight however far F lies from the origin. Any point would be valid.
  double dmax = 0.0, emax = 0.0;
  for (const SupportPlane& p : planes_) {
    dmax = std::max(dmax, std::abs(p.d));
    emax = std::max(emax, std::abs(p.e));
  }
  centre_ = centre.allFinite() ? centre : Vec3::Zero();
  magnitude_ = centre_.cwiseAbs().sum() + dmax + emax + 1.0;
  // Split at the median along the normals' widest axis; children stored in pairs. Each group's
  // box and tops are set when it comes up.
  groups_.push_back(Group{Vec3::Zero(), Vec3::Zero(), 0.0, 0.0, 0, static_cast<std::uint32_t>(planes_.size())});
  for (std::size_t i = 0; i < groups_.size(); ++i) {
    Group g = groups_[i];
    Vec3 glo = planes_[order_[g.first]].n, ghi = glo;
    double top = -HUGE_VAL, top_e = -HUGE_VAL;
    for (std::uint32_t k = g.first; k < g.first + g.count; ++k) {
      const SupportPlane& p = planes_[order_[k]];
      glo = glo.cwiseMin(p.n);
      ghi = ghi.cwiseMax(p.n);
      const double o = p.n.dot(centre_) - p.d;
      top = std::max(top, o);
      top_e = std::max(top_e, o - p.e);
    }
    groups_[i].lo = glo;
    groups_[i].hi = ghi;
    groups_[i].top = top;
    groups_[i].top_e = top_e;
    if (g.count <= kLeaf) continue;
    int axis = 0;
    const Vec3 ext = ghi - glo;
    if (ext[1] > ext[axis]) axis = 1;
    if (ext[2] > ext[axis]) axis = 2;
    const auto b = order_.begin() + g.first, m = b + g.count / 2, e = b + g.count;
    std::nth_element(b, m, e, [&](std::uint32_t u, std::uint32_t v) {
      return planes_[u].n[axis] < planes_[v].n[axis] || (planes_[u].n[axis] == planes_[v].n[axis] && u < v);
    });
    const std::uint32_t left = static_cast<std::uint32_t>(groups_.size());
    groups_.push_back(Group{Vec3::Zero(), Vec3::Zero(), 0.0, 0.0, g.first, g.count / 2});
    groups_.push_back(Group{Vec3::Zero(), Vec3::Zero(), 0.0, 0.0, g.first + g.count / 2, g.count - g.count / 2});
    groups_[i].first = left;
    groups_[i].count = 0;
  }
}

double SupportPlanes::group_bound(const Group& g, const Vec3& y, bool with_e) const {
  // For n in [lo, hi]: n.(y - c) <= sum over axes of max(lo u, hi u), u = y - c. The planes' computed
  // values differ from the exact ones, and this sum and their n.c - d from theirs, by a few
  // rounding errors of magnitudes |y|_1 + |c|_1 + |d| + e (|n| about 1): the margin covers them
  // a thousandfold.
  const Vec3 u = y - centre_;
  double s = with_e ? g.top_e : g.top;
  for (int a = 0; a < 3; ++a) s += std::max(g.lo[a] * u[a], g.hi[a] * u[a]);
  return s + 1e-13 * (magnitude_ + y.cwiseAbs().sum() + u.cwiseAbs().sum());
}

// Depth first, the higher child first; a group is skipped when its bound (computed once, when its
// parent is opened) is below `floor` (which `leaf` may raise as it finds planes).
template <class Leaf>
void SupportPlanes::walk(const Vec3& y, bool with_e, const double& floor, const Leaf& leaf) const {
  if (groups_.empty()) return;
  std::array<std::pair<std::uint32_t, double>, 64> stack;
  int top = 0;
  stack[top++] = {0, group_bound(groups_[0], y, with_e)};
  while (top > 0) {
    const auto [id, bound] = stack[--top];
    if (bound < floor) continue;
    const Group& g = groups_[id];
    if (g.count > 0) {
      for (std::uint32_t k = g.first; k < g.first + g.count; ++k) leaf(order_[k]);
      continue;
    }
    const double a = group_bound(groups_[g.first], y, with_e), b = group_bound(groups_[g.first + 1], y, with_e);
    // The higher pushed last (popped first).
    if (a >= b) {
      stack[top++] = {g.first + 1, b};
      stack[top++] = {g.first, a};
    } else {
      stack[top++] = {g.first, a};
      stack[top++] = {g.first + 1, b};
    }
  }
}

void SupportPlanes::highest(const Vec3& g, int k, std::pair<double, std::uint32_t>* out) const {
  k = std::min<int>(k, static_cast<int>(planes_.size()));
  const auto before = [](const std::pair<double, std::uint32_t>& u, const std::pair<double, std::uint32_t>& v) {
    return u.first > v.first || (u.first == v.first && u.second < v.second);
  };
  int have = 0;
  if (!g.allFinite()) {  // no bound orders non-finite values: every plane, as a sort would
    thread_local std::vector<std::pair<double, std::uint32_t>> all;
    all.resize(planes_.size());
    for (std::size_t j = 0; j < planes_.size(); ++j)
      all[j] = {planes_[j].n.dot(g) - planes_[j].d, static_cast<std::uint32_t>(j)};
    std::partial_sort(all.begin(), all.begin() + k, all.end(), before);
    std::copy(all.begin(), all.begin() + k, out);
    return;
  }
  double floor = -HUGE_VAL;  // the k-th value once k are held
  walk(g, false, floor, [&](std::uint32_t j) {
    const std::pair<double, std::uint32_t> x{planes_[j].n.dot(g) - planes_[j].d, j};
    if (have == k && !before(x, out[k - 1])) return;
    int i = have < k ? have++ : k - 1;
    for (; i > 0 && before(x, out[i - 1]); --i) out[i] = out[i - 1];
    out[i] = x;
    if (have == k) floor = out[k - 1].first;
  });
}

std::int64_t SupportPlanes::highest_above(const Vec3& y, double floor, const std::uint32_t* skip, int n_skip) const {
  std::int64_t join = -1;
  double best = floor;
  const auto leaf = [&](std::uint32_t j) {
    const double h = planes_[j].n.dot(y) - planes_[j].d - planes_[j].e;
    if (!(h > best || (h == best && join >= 0 && j < join))) return;
    if (std::find(skip, skip + n_skip, j) != skip + n_skip) return;
    best = h;
    join = j;
  };
  if (!y.allFinite()) {
    for (std::uint32_t j = 0; j < planes_.size(); ++j) leaf(j);
    return join;
  }
  walk(y, true, best, leaf);
  return join;
}

namespace {

// A lower bound of a / |n| from a lower bound of a, for |n| in [lo, up].
inline double over_norm_down(double a, double lo, double up) { return round_down(a >= 0.0 ? a / up : a / lo); }
inline double over_norm_up(double a, double lo, double up) { return round_up(a >= 0.0 ? a / lo : a / up); }

// The weighted mean sum w_j q_j / sum w_j rounded down (up: of -q, negated), for w >= 0 with a
// positive sum: the computed sums are within (M + 1) u of the exact ones (M <= 16 terms), and the
// factors cover that with margin.
double weighted_mean_down(const double* w, const double* q, int M) {
  double s = 0.0, a = 0.0, W = 0.0;
  for (int j = 0; j < M; ++j) {
    if (!(w[j] > 0.0)) continue;
    s += w[j] * q[j];
    a += std::abs(w[j] * q[j]);
    W += w[j];
  }
  const double lo = round_down(s - 5e-15 * a);
  return round_down(lo >= 0.0 ? lo / (W * (1.0 + 5e-15)) : lo / (W * (1.0 - 5e-15)));
}

// The weights for the members `idx` (plane indices): corner values v (estimates: they only pick the
// weights), the weights w of the linear program, and a guess (beta, gamma) of the point where the
// members' maximum is least.
struct MemberProgram {
  int K = 3, M = 0;  // corners (a triangle's 3 or a box's 8), members
  std::array<std::uint32_t, 16> idx{};
  std::array<std::array<double, 16>, 8> v{};
  std::vector<double> w;
  double beta = 1.0 / 3, gamma = 1.0 / 3, least = HUGE_VAL;

  void solve(const std::vector<SupportPlane>& P, const Vec3* x) {
    double vmax = -HUGE_VAL, vmin = HUGE_VAL;
    for (int k = 0; k < K; ++k)
      for (int j = 0; j < M; ++j) {
        const SupportPlane& p = P[idx[j]];
        v[k][j] = p.n.dot(x[k]) - p.d - p.e;
        vmax = std::max(vmax, v[k][j]);
        vmin = std::min(vmin, v[k][j]);
      }
    // Weights maximising the least corner value of the weighted mean: minimax_weights on
    // 1 + (vmax - v) / spread (positive, about 1; the same optimum).
    thread_local std::vector<double> D;
    D.resize(static_cast<std::size_t>(K * M));
    const double spread = std::max(vmax - vmin, 1e-300);
    for (int k = 0; k < K; ++k)
      for (int j = 0; j < M; ++j) D[k * M + j] = 1.0 + (vmax - v[k][j]) / spread;
    if (!minimax_weights(D.data(), K, M, w)) {
      w.assign(static_cast<std::size_t>(M), 0.0);  // the best single plane instead
      int best = 0;
      double best_v = -HUGE_VAL;
      for (int j = 0; j < M; ++j) {
        double m = HUGE_VAL;
        for (int k = 0; k < K; ++k) m = std::min(m, v[k][j]);
        if (m > best_v) {
          best_v = m;
          best = j;
        }
      }
      w[static_cast<std::size_t>(best)] = 1.0;
    }
    if (K == 3) guess();
  }

  // Among the corners, the points of the edges where two weighted members are equal and the point
  // where three are, the least maximum of the members (affine in the barycentrics): the vertices
  // of the linear program over the triangle whose optimum the weights certify (complementary
  // slackness).
  void guess() {
    const auto value_at = [&](double be, double ga) {
      double h = -HUGE_VAL;
      for (int j = 0; j < M; ++j) h = std::max(h, v[0][j] + be * (v[1][j] - v[0][j]) + ga * (v[2][j] - v[0][j]));
      return h;
    };
    std::array<int, 3> sup{};
    int ns = 0;
    for (int j = 0; j < M && ns < 3; ++j)
      if (w[j] > 0.0) sup[ns++] = j;
    least = HUGE_VAL;
    const auto offer = [&](double be, double ga) {
      if (!(be >= 0.0 && ga >= 0.0 && be + ga <= 1.0)) return;
      const double h = value_at(be, ga);
      if (h < least) {
        least = h;
        beta = be;
        gamma = ga;
      }
    };
    offer(0.0, 0.0);
    offer(1.0, 0.0);
    offer(0.0, 1.0);
    const std::array<std::array<double, 2>, 3> corner{{{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}}};
    for (int i = 0; i < ns; ++i)
      for (int l = i + 1; l < ns; ++l) {
        const int p = sup[i], q = sup[l];
        for (int k = 0; k < 3; ++k) {
          const int k2 = (k + 1) % 3;
          const double f0 = v[k][p] - v[k][q], f1 = v[k2][p] - v[k2][q];
          if (!(f0 != f1)) continue;
          const double t = f0 / (f0 - f1);
          if (t > 0.0 && t < 1.0)
            offer(corner[k][0] + t * (corner[k2][0] - corner[k][0]), corner[k][1] + t * (corner[k2][1] - corner[k][1]));
        }
      }
    if (ns == 3) {
      // h_p - h_q = 0 and h_p - h_r = 0, affine in (beta, gamma).
      const auto diff = [&](int p, int q) {
        const double f0 = v[0][p] - v[0][q];
        return std::array<double, 3>{f0, (v[1][p] - v[1][q]) - f0, (v[2][p] - v[2][q]) - f0};
      };
      const auto A = diff(sup[0], sup[1]), B = diff(sup[0], sup[2]);
      const double det = A[1] * B[2] - A[2] * B[1];
      if (det != 0.0) offer((-A[0] * B[2] + A[2] * B[0]) / det, (-A[1] * B[0] + A[0] * B[1]) / det);
    }
  }
};

}  // namespace

namespace {
// The rigorous bound with the program's weights: per corner, per member, (n.x - d - e) / |n|
// rounded down, and the rate along d.
HalfspaceBound rigorous_bound(const std::vector<SupportPlane>& P, const MemberProgram& lp, const Vec3* x, int n,
                              const Vec3& d);
}  // namespace

HalfspaceBound halfspace_bound(const SupportPlanes& S, const Vec3* x, int n, const Vec3& d, int max_members,
                               HalfspaceSeed* seed) {
  HalfspaceBound r;
  const std::vector<SupportPlane>& P = S.planes();
  if (P.empty() || n < 1 || n > 8) {
    r.lower = -std::numeric_limits<double>::infinity();
    return r;
  }
  thread_local MemberProgram lp;
  lp.K = n;
  // The members: first the planes highest at the centroid; then, for a triangle, while a plane
  // not among them is higher at the guessed least point than the members' maximum there, it joins
  // (column generation: at the program's optimum no plane is higher, and the bound is then exact
  // for a convex F), until the program holds 16. Only the weights depend on this. (Four rounds
  // were too few for a long sliver across a finely faceted rod, whose centroid's planes are not
  // those active where it is deepest: the bound stayed 10 % of the depth low.)
  const int first = std::min<int>(static_cast<int>(P.size()), std::clamp(max_members, 1, 16));
  Vec3 g = Vec3::Zero();
  for (int k = 0; k < n; ++k) g += x[k];
  g /= static_cast<double>(n);
  std::array<std::pair<double, std::uint32_t>, 16> top;
  S.highest(g, first, top.data());
  lp.M = first;
  for (int j = 0; j < first; ++j) lp.idx[j] = top[j].second;
  // Then a seed's planes (those a nearby pose weighted: column generation then mostly confirms
  // them instead of finding them one solve at a time).
  if (seed)
    for (int j = 0; j < seed->n && lp.M < 16; ++j)
      if (seed->idx[j] < P.size() &&
          std::find(lp.idx.begin(), lp.idx.begin() + lp.M, seed->idx[j]) == lp.idx.begin() + lp.M)
        lp.idx[lp.M++] = seed->idx[j];
  lp.solve(P, x);
  while (n == 3 && lp.M < 16) {  // each round adds a member
    const Vec3 y = x[0] + lp.beta * (x[1] - x[0]) + lp.gamma * (x[2] - x[0]);
    const double tol = 1e-12 * (1.0 + std::abs(lp.least));
    const std::int64_t join = S.highest_above(y, lp.least + tol, lp.idx.data(), lp.M);
    if (join < 0) break;
    lp.idx[lp.M++] = static_cast<std::uint32_t>(join);
    lp.solve(P, x);
  }
  if (seed) {
    seed->n = 0;
    for (int j = 0; j < lp.M && seed->n < 4; ++j)
      if (lp.w[static_cast<std::size_t>(j)] > 0.0) seed->idx[seed->n++] = lp.idx[j];
  }
  return rigorous_bound(P, lp, x, n, d);
}

HalfspaceBound halfspace_bound_among(const SupportPlanes& S, const std::int32_t* members, int n_members,
                                     const Vec3* x, int n, const Vec3& d) {
  HalfspaceBound r;
  const std::vector<SupportPlane>& P = S.planes();
  thread_local MemberProgram lp;
  lp.K = n;
  lp.M = 0;
  for (int j = 0; j < n_members && lp.M < 16; ++j)
    if (members[j] >= 0 && static_cast<std::size_t>(members[j]) < P.size())
      lp.idx[lp.M++] = static_cast<std::uint32_t>(members[j]);
  if (lp.M == 0 || n < 1 || n > 8) {
    r.lower = -std::numeric_limits<double>::infinity();
    return r;
  }
  lp.solve(P, x);
  return rigorous_bound(P, lp, x, n, d);
}

namespace {

HalfspaceBound rigorous_bound(const std::vector<SupportPlane>& P, const MemberProgram& lp, const Vec3* x, int n,
                              const Vec3& d) {
  HalfspaceBound r;
  const int M = lp.M;
  const std::vector<double>& w = lp.w;
  // The rigorous bound with these weights: per corner, per member, (n.x - d - e) / |n| rounded down.
  std::array<double, 16> q{};
  r.lower = HUGE_VAL;
  for (int k = 0; k < n; ++k) {
    for (int j = 0; j < M; ++j) {
      if (!(w[j] > 0.0)) continue;
      const SupportPlane& p = P[lp.idx[j]];
      const PlaneOffset o = plane_offset(p.n, p.d, x[k]);
      q[j] = over_norm_down(round_down(round_down(o.value - o.error) - p.e), p.norm_lo, p.norm_up);
    }
    r.lower = std::min(r.lower, weighted_mean_down(w.data(), q.data(), M));
  }
  // The rate: sum w (n.d) / |n| / sum w, rounded up (the mean of -rates rounded down, negated).
  for (int j = 0; j < M; ++j) {
    if (!(w[j] > 0.0)) continue;
    const SupportPlane& p = P[lp.idx[j]];
    const double t0 = p.n[0] * d[0], t1 = p.n[1] * d[1], t2 = p.n[2] * d[2];
    const double hi = round_up(t0 + t1 + t2 + 2e-15 * (std::abs(t0) + std::abs(t1) + std::abs(t2)));
    q[j] = -over_norm_up(hi, p.norm_lo, p.norm_up);
  }
  r.rate = -weighted_mean_down(w.data(), q.data(), M);
  if (std::isnan(r.lower) || std::isnan(r.rate)) {
    r.lower = -std::numeric_limits<double>::infinity();
    r.rate = 0.0;
  }
  if (n == 3) {
    r.beta = lp.beta;
    r.gamma = lp.gamma;
  }
  return r;
}

}  // namespace

}  // namespace cdbench
