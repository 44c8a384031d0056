#include "distance/depth_bound.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "distance/planar_patch.h"
#include "distance/point_triangle_distance.h"

namespace cdbench {

double translated_depth(const TranslatedDepthBound& b, const Vec3& D) {
  if (b.n == 0) return std::numeric_limits<double>::infinity();
  const double d2 = D.squaredNorm(), dn = std::sqrt(d2);
  double worst = 0.0;
  for (int k = 0; k < b.n; ++k) {
    const CornerMoments& m = b.corners[k];
    // The computed A and W are within (n + 5) u (n <= 48 weights) of the exact means of the
    // computed w: 1e-13 relative for A, 1e-13 sqrt(A) for W (|W| <= sqrt(A) by Cauchy-Schwarz).
    // The sum then rounds by a few u times (sqrt(A) + |D|)^2; 1e-12 of it covers that.
    const double sa = std::sqrt(m.a);
    double g = m.a * (1.0 + 1e-13) + 2.0 * m.w.dot(D) + 2e-13 * sa * dn + d2;
    g += 1e-12 * (sa + dn) * (sa + dn);
    worst = std::max(worst, g);
  }
  return round_up(round_up(std::sqrt(worst)) + b.err);
}

namespace {
// With sparse weights (a few weighted triangles) the 16 nearest suffice, and gathering and sorting
// fewer is cheaper (doc/performance.md, "Sparse weights for the pose certificates": 8, 12 and 16
// measured alike, 5-10 % faster than 49).
constexpr std::size_t kMaxSparseTriangles = 16;
// Planes tried for patches: those of the nearest triangles (the cell's nearest face is among them).
constexpr std::size_t kPatchPlanes = 4;

// A corner's weighted sum of member bounds, divided by the weights and rounded up. Positive terms
// only: the relative rounding error of at most ~50 additions and one product each is below 1e-13;
// the factors cover it with margin.
inline double weighted_mean_up(double sum, double weights) {
  return sum * (1.0 + 1e-12) / (weights * (1.0 - 1e-12));
}

// The weights' Frank-Wolfe stop (DepthWeights).
inline double weights_gap(DepthWeights w) { return w == DepthWeights::sparse ? 0.5 : 1e-15; }
inline std::size_t max_triangles(DepthWeights w) {
  return w == DepthWeights::sparse ? kMaxSparseTriangles : kMaxDepthTriangles;
}

// The convexity bound with near-coplanar triangles merged into planar patches where they provably
// cover the cell (distance/planar_patch.h): each patch alone, and every member weighted at the
// min-norm point of the gradients at c, a patch's gradient being its plane's normal. +inf when no
// patch of two or more triangles covers the cell. ids and nearest: the candidates nearest first.
double patched_depth_bound(const SignedDistance& sdf, const Vec3& c, const std::vector<std::uint32_t>& ids,
                           const std::vector<Vec3>& nearest, const Vec3* corners, int n_corners,
                           const Vec3* plane_normal, double slack, int* worst_corner, DepthWeights weights,
                           const Vec3* cover_box) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const TriangleMesh& m = sdf.mesh();
  const std::size_t n = ids.size();
  struct Patch {
    const TrianglePlane* plane;
    double eta;
  };
  thread_local std::vector<int> group_of;
  thread_local std::vector<Patch> patches;
  thread_local std::vector<std::uint32_t> members;
  thread_local std::vector<std::size_t> at;
  group_of.assign(n, -1);
  patches.clear();
  std::size_t tried = 0;
  for (std::size_t j = 0; j < n && tried < kPatchPlanes; ++j) {
    if (group_of[j] >= 0) continue;
    const TrianglePlane& pl = sdf.planes()[ids[j]];
    if (!(pl.eps <= slack)) continue;
    ++tried;
    double eta = pl.eps;
    at.assign(1, j);
    for (std::size_t k = j + 1; k < n; ++k) {
      if (group_of[k] >= 0) continue;
      const Face& f = m.faces[ids[k]];
      double e = 0.0;
      for (int q = 0; q < 3 && e <= slack; ++q) {
        const PlaneOffset o = plane_offset(pl.n, pl.d, m.vertices[f[q]]);  // |exact n.w - d| <= this
        e = std::max(e, std::abs(o.value) + o.error);
      }
      if (e <= slack) {
        at.push_back(k);
        eta = std::max(eta, e);
      }
    }
    if (at.size() < 2) continue;
    members.clear();
    for (std::size_t k : at) members.push_back(ids[k]);
    if (!(cover_box ? patch_covers_cell(m, members, pl.n, pl.d, cover_box, 8)
                    : patch_covers_cell(m, members, pl.n, pl.d, corners, n_corners)))
      continue;
    for (std::size_t k : at) group_of[k] = static_cast<int>(patches.size());
    patches.push_back({&pl, round_up(eta * (1.0 + 2e-15))});
  }
  if (patches.empty()) return kInf;
  double best = kInf;
  int best_corner = 0;
  const auto offer = [&](double bound, int corner) {
    if (bound < best) {
      best = bound;
      best_corner = corner;
    }
  };
  // Each patch alone (the touching case: one plane decides).
  for (const Patch& p : patches) {
    double worst = 0.0;
    int wc = 0;
    for (int k = 0; k < n_corners; ++k) {
      const double b = patch_distance_bound(*p.plane, p.eta, corners[k]);
      if (b > worst || k == 0) {
        worst = std::max(worst, b);
        wc = k;
      }
    }
    offer(worst, wc);
  }
  // Every member weighted (a cell between parallel patches, or a patch beside a crease).
  thread_local std::vector<Vec3> g;
  thread_local std::vector<long> who;  // >= 0: a patch; < 0: -(j + 1), the triangle ids[j]
  thread_local std::vector<double> lambda;
  g.clear();
  who.clear();
  for (std::size_t p = 0; p < patches.size(); ++p) {
    const TrianglePlane& pl = *patches[p].plane;
    const double side = plane_offset(pl.n, pl.d, c).value;
    g.push_back((side < 0.0 ? -pl.n : pl.n).normalized());
    who.push_back(static_cast<long>(p));
  }
  for (std::size_t j = 0; j < n; ++j) {
    if (group_of[j] >= 0) continue;
    const Vec3 v = c - nearest[j];
    const double len = v.norm();
    if (!(len > 0.0)) return round_up(best);
    g.push_back(v / len);
    who.push_back(-static_cast<long>(j) - 1);
  }
  if (plane_normal)
    for (Vec3& x : g) x -= x.dot(*plane_normal) * *plane_normal;
  min_norm_combination(g, lambda, 100, weights_gap(weights));
  double worst = 0.0;
  int wc = 0;
  for (int k = 0; k < n_corners; ++k) {
    const Vec3& v = corners[k];
    double sum = 0.0, weights = 0.0;
    for (std::size_t i = 0; i < g.size(); ++i) {
      if (lambda[i] <= 0.0) continue;
      double d;
      if (who[i] >= 0) {
        const Patch& p = patches[static_cast<std::size_t>(who[i])];
        d = patch_distance_bound(*p.plane, p.eta, v);
      } else {
        d = point_triangle_distance_upper_near(v, m, ids[static_cast<std::size_t>(-who[i] - 1)]);
      }
      sum += lambda[i] * d;
      weights += lambda[i];
    }
    const double bound = weighted_mean_up(sum, weights);
    if (bound > worst || k == 0) {
      worst = std::max(worst, bound);
      wc = k;
    }
  }
  offer(worst, wc);
  if (worst_corner) *worst_corner = best_corner;
  return round_up(best);
}

}  // namespace

// With u = lambda / t the program is the standard form max 1.u subject to D u <= 1, u >= 0, whose
// origin is feasible: a dense simplex with Bland's rule.
bool minimax_weights(const double* D, int K, int M, std::vector<double>& lambda) {
  const int W = M + K + 1;  // members, slacks, right-hand side
  thread_local std::vector<double> T;
  thread_local std::vector<int> basis;
  T.assign(static_cast<std::size_t>((K + 1) * W), 0.0);
  basis.resize(static_cast<std::size_t>(K));
  const auto at = [&](int r, int c) -> double& { return T[static_cast<std::size_t>(r * W + c)]; };
  for (int k = 0; k < K; ++k) {
    for (int j = 0; j < M; ++j) at(k, j) = D[k * M + j];
    at(k, M + k) = 1.0;
    at(k, W - 1) = 1.0;
    basis[k] = M + k;
  }
  for (int j = 0; j < M; ++j) at(K, j) = -1.0;  // objective row: -c
  for (int iteration = 0; iteration < 200; ++iteration) {
    int p = -1;
    for (int j = 0; j < W - 1 && p < 0; ++j)
      if (at(K, j) < -1e-12) p = j;
    if (p < 0) {
      lambda.assign(static_cast<std::size_t>(M), 0.0);
      double total = 0.0;
      for (int k = 0; k < K; ++k)
        if (basis[k] < M) {
          lambda[basis[k]] = std::max(0.0, at(k, W - 1));
          total += lambda[basis[k]];
        }
      if (!(total > 0.0) || !std::isfinite(total)) return false;
      for (double& l : lambda) l /= total;
      return true;
    }
    int r = -1;
    double best = 0.0;
    for (int k = 0; k < K; ++k) {
      if (!(at(k, p) > 1e-12)) continue;
      const double ratio = at(k, W - 1) / at(k, p);
      if (r < 0 || ratio < best || (ratio == best && basis[k] < basis[r])) {
        r = k;
        best = ratio;
      }
    }
    if (r < 0) return false;  // unbounded: some member is at distance 0 from every corner
    const double pivot = at(r, p);
    for (int c = 0; c < W; ++c) at(r, c) /= pivot;
    for (int k = 0; k <= K; ++k) {
      if (k == r) continue;
      const double f = at(k, p);
      if (f == 0.0) continue;
      for (int c = 0; c < W; ++c) at(k, c) -= f * at(r, c);
    }
    basis[r] = p;
  }
  return false;
}


namespace {
// The four largest positive weights of lambda (members ids, in order), largest first, ties by
// position; weights that round to 0 in float are left out.
void keep_witness(const std::vector<std::uint32_t>& ids, const std::vector<double>& lambda, std::size_t n,
                  DepthWitness* w) {
  if (!w) return;
  w->n = 0;
  std::array<std::size_t, 4> best{};
  int k = 0;
  for (std::size_t j = 0; j < n; ++j) {
    if (!(lambda[j] > 0.0)) continue;
    int at = k < 4 ? k++ : 4;
    while (at > 0 && lambda[best[at - 1]] < lambda[j]) {
      if (at < 4) best[at] = best[at - 1];
      --at;
    }
    if (at < 4) best[at] = j;
  }
  for (int i = 0; i < k; ++i) {
    const float x = static_cast<float>(lambda[best[i]]);
    if (!(x > 0.0f)) continue;
    w->face[w->n] = ids[best[i]];
    w->weight[w->n] = x;
    ++w->n;
  }
}
}  // namespace

double witness_depth_bound(const SignedDistance& sdf, const DepthWitness& w, const Vec3* corners, int n_corners) {
  if (w.n == 0) return std::numeric_limits<double>::infinity();
  const TriangleMesh& m = sdf.mesh();
  double weights = 0.0;
  for (int j = 0; j < w.n; ++j) weights += w.weight[j];
  double worst = 0.0;
  for (int k = 0; k < n_corners; ++k) {
    double sum = 0.0;
    for (int j = 0; j < w.n; ++j) sum += w.weight[j] * point_triangle_distance_upper_near(corners[k], m, w.face[j]);
    worst = std::max(worst, weighted_mean_up(sum, weights));
  }
  return round_up(worst);
}

double CornerDistances::at(const TriangleMesh& m, const Vec3* corners, int k, std::size_t j,
                           std::uint32_t face) const {
  const double v =
      k >= 0 && k < 8 && j < 4 ? d[static_cast<std::size_t>(k)][j] : std::numeric_limits<double>::quiet_NaN();
  return std::isnan(v) ? point_triangle_distance_upper_near(corners[k], m, face) : v;
}

double minimax_depth_bound(const SignedDistance& sdf, const std::vector<std::uint32_t>& ids, const Vec3* corners,
                           int n_corners, std::size_t max_members, DepthWitness* witness,
                           const CornerDistances* known) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const std::size_t M = std::min({ids.size(), max_members, std::size_t{16}});
  if (M == 0 || n_corners <= 0 || n_corners > 16) return kInf;
  const TriangleMesh& m = sdf.mesh();
  // Certified upper ends of the corner-to-member distances.
  thread_local std::vector<double> D;
  thread_local std::vector<double> lambda;
  D.resize(static_cast<std::size_t>(n_corners) * M);
  for (int k = 0; k < n_corners; ++k)
    for (std::size_t j = 0; j < M; ++j)
      D[k * M + j] = known ? known->at(m, corners, k, j, ids[j])
                           : point_triangle_distance_upper_near(corners[k], m, ids[j]);
  const double bound = minimax_bound(D.data(), n_corners, static_cast<int>(M), &lambda);
  if (!lambda.empty()) keep_witness(ids, lambda, M, witness);
  return bound;
}

double minimax_bound(const double* D, int K, int M, std::vector<double>* weights_out) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  thread_local std::vector<double> own;
  std::vector<double>& lambda = weights_out ? *weights_out : own;
  if (K <= 0 || M <= 0 || K > 16 || M > 16) return kInf;
  if (!minimax_weights(D, K, M, lambda)) {
    // The simplex's fixed tolerances can stall on nearly equal members far below 1 (a wall's
    // coplanar facets): again on D scaled to at most 1 (the same optimum).
    double top = 0.0;
    for (int i = 0; i < K * M; ++i) top = std::max(top, D[i]);
    std::array<double, 16 * 16> scaled;
    for (int i = 0; i < K * M; ++i) scaled[static_cast<std::size_t>(i)] = D[i] / top;
    if (!(top > 0.0) || !std::isfinite(top) || !minimax_weights(scaled.data(), K, M, lambda)) {
      lambda.clear();
      return kInf;
    }
  }
  double worst = 0.0;
  for (int k = 0; k < K; ++k) {
    double sum = 0.0, weights = 0.0;
    for (int j = 0; j < M; ++j) {
      if (!(lambda[j] > 0.0)) continue;
      sum += lambda[j] * D[k * M + j];
      weights += lambda[j];
    }
    const double bound = weighted_mean_up(sum, weights);
    if (!(weights > 0.0) || std::isnan(bound)) return kInf;  // never drop a corner
    worst = std::max(worst, bound);
  }
  return round_up(worst);
}

double depth_upper_bound(const SignedDistance& sdf, const Vec3& c, double radius, const Vec3* corners, int n_corners,
                         std::vector<std::uint32_t>& ids, Vec3* candidate, const Vec3* plane_normal, int* worst_corner,
                         TranslatedDepthBound* moments, double coplanar_slack, DepthWeights weights,
                         DepthWitness* witness, CornerDistances* computed) {
  sdf.triangles_within(c, radius, max_triangles(weights) - 1, ids);  // stops after max_triangles
  return depth_upper_bound_among(sdf, c, ids, corners, n_corners, candidate, plane_normal, worst_corner, moments,
                                 coplanar_slack, weights, witness, computed);
}

double depth_upper_bound_among(const SignedDistance& sdf, const Vec3& c, std::vector<std::uint32_t>& ids,
                               const Vec3* corners, int n_corners, Vec3* candidate, const Vec3* plane_normal,
                               int* worst_corner, TranslatedDepthBound* moments, double coplanar_slack,
                               DepthWeights weights, DepthWitness* witness, CornerDistances* computed,
                               const Vec3* cover_box) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (moments) moments->n = 0;
  if (computed)
    for (auto& row : computed->d) row.fill(std::numeric_limits<double>::quiet_NaN());
  if (witness) witness->n = 0;
  if (ids.empty()) return kInf;
  const TriangleMesh& m = sdf.mesh();
  std::size_t n = ids.size();
  // Per-thread scratch: this runs for every deep cell of every branch and bound.
  thread_local std::vector<Vec3> g, nearest, points;
  thread_local std::vector<std::pair<double, std::uint32_t>> order;
  g.resize(n);
  nearest.resize(n);
  points.resize(n);
  order.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    const Face& f = m.faces[ids[j]];
    points[j] = closest_point_on_triangle(c, m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]]);
    order[j] = {(c - points[j]).squaredNorm(), static_cast<std::uint32_t>(j)};
  }
  // Nearest first (ties by id): the search below then prefers, among triangles of one face, the one
  // holding the projection, whose gradient is the exact face normal.
  std::sort(order.begin(), order.end(), [&](const auto& x, const auto& y) {
    return x.first < y.first || (x.first == y.first && ids[x.second] < ids[y.second]);
  });
  n = std::min(n, max_triangles(weights));
  g.resize(n);
  for (std::size_t j = 0; j < n; ++j) nearest[j] = points[order[j].second];
  for (std::size_t j = 0; j < n; ++j) order[j].second = ids[order[j].second];
  ids.resize(n);
  for (std::size_t j = 0; j < n; ++j) ids[j] = order[j].second;
  for (std::size_t j = 0; j < n; ++j) {
    const Vec3 v = c - nearest[j];
    const double len = v.norm();
    const Face& f = m.faces[ids[j]];
    const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &cc = m.vertices[f[2]];
    if (len > closest_point_error(a, b, cc) + 4e-16 * c.cwiseAbs().maxCoeff()) {
      g[j] = v / len;
      continue;
    }
    // c lies on this triangle up to the nearest point's rounding, where its distance has no
    // gradient (or only rounding's): the triangle's normal stands in (either way round; the weights
    // only steer, any weights give a valid bound). A cell lying on F (a mover resting face-on on a
    // face that does not support F, or coinciding with F) thus keeps the bound of the triangle it
    // lies on, and of the planar patch beyond its edges (below); it had none (exactly on F) or one
    // weighted by rounding noise, and was split towards the tolerance (doc/poses.md, "Cells lying
    // on F"). The stored plane's unit normal (make_triangle_plane; a degenerate triangle has none).
    const TrianglePlane& plane = sdf.planes()[ids[j]];
    if (!(plane.eps < kInf)) return kInf;
    g[j] = plane.n;
  }
  // Weights near the min-norm point of conv{g_j} (heuristic: only tightness depends on them).
  thread_local std::vector<double> lambda;
  if (plane_normal)
    for (Vec3& x : g) x -= x.dot(*plane_normal) * *plane_normal;
  min_norm_combination(g, lambda, 100, weights_gap(weights));
  keep_witness(ids, lambda, n, witness);
  if (candidate) {
    *candidate = Vec3::Zero();
    for (std::size_t j = 0; j < n; ++j) *candidate += lambda[j] * nearest[j];
  }
  double worst = 0.0;
  if (moments) moments->err = 0.0;
  const bool with_moments = moments && n_corners <= static_cast<int>(moments->corners.size());
  for (int corner = 0; corner < n_corners; ++corner) {
    const Vec3& v = corners[corner];
    double sum = 0.0, weights = 0.0;
    CornerMoments cm;
    for (std::size_t j = 0; j < n; ++j) {
      if (lambda[j] <= 0.0) continue;
      const Face& f = m.faces[ids[j]];
      const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &cc = m.vertices[f[2]];
      Vec3 q;  // the point of the triangle behind dj, for the moments too
      const double dj = point_triangle_distance_upper_near(v, a, b, cc, &q);
      if (computed && j < 4 && corner < 8) computed->d[static_cast<std::size_t>(corner)][j] = dj;
      sum += lambda[j] * dj;
      weights += lambda[j];
      if (with_moments) {
        const Vec3 w = v - q;
        cm.a += lambda[j] * w.squaredNorm();
        cm.w += lambda[j] * w;
        // q's distance to the triangle, and fl(v - q) within 2 u |w| (norm) of v - q.
        moments->err = std::max(moments->err, closest_point_error(a, b, cc) + 1e-15 * w.norm());
      }
    }
    if (with_moments && weights > 0.0) {
      cm.a /= weights;
      cm.w /= weights;
      moments->corners[moments->n++] = cm;
    }
    const double bound = weighted_mean_up(sum, weights);
    if (bound > worst || corner == 0) {
      worst = std::max(worst, bound);
      if (worst_corner) *worst_corner = corner;
    }
  }
  if (moments && moments->n != n_corners) moments->n = 0;  // every corner or none
  if (coplanar_slack > 0.0 && (cover_box || n_corners <= 3 || n_corners == 8) && n >= 2) {
    int corner = 0;
    const double patched = patched_depth_bound(sdf, c, ids, nearest, corners, n_corners, plane_normal, coplanar_slack,
                                               &corner, weights, cover_box);
    if (patched < worst) {
      if (worst_corner) *worst_corner = corner;
      return patched;
    }
  }
  return round_up(worst);
}

}  // namespace cdbench
