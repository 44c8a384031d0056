#include "offset/certify_band.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "distance/point_triangle_distance.h"
#include "util/timer.h"

namespace cdbench {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Upper bound of dist(x, F) over triangle abc: each d_j is convex, so max over the triangle of
// d_j is at a vertex; j = the triangle nearest to the centroid (any j gives a valid bound; the
// nearest gives the tightest). `hint`: a triangle near the last piece's, which prunes the search
// from its start. Where that is not tight enough the triangle is split into 4 (midpoints in
// doubles; the caller adds the slack for rounding).
double upper_bound(const SignedDistance& sdf, const Vec3& a, const Vec3& b, const Vec3& c, double target, int depth,
                   std::size_t& pieces, std::int64_t& hint) {
  ++pieces;
  const TriangleMesh& m = sdf.mesh();
  std::uint32_t t = 0;
  sdf.unsigned_distance((a + b + c) / 3.0, &t, hint);
  hint = t;
  double hi = 0.0;
  for (const Vec3* v : {&a, &b, &c}) hi = std::max(hi, point_triangle_distance_upper(*v, m, t));
  if (hi <= target || depth == 0) return hi;
  const Vec3 ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
  return std::max({upper_bound(sdf, a, ab, ca, target, depth - 1, pieces, hint),
                   upper_bound(sdf, ab, b, bc, target, depth - 1, pieces, hint),
                   upper_bound(sdf, ca, bc, c, target, depth - 1, pieces, hint),
                   upper_bound(sdf, ab, bc, ca, target, depth - 1, pieces, hint)});
}

}  // namespace

void set_band_maximum(BandResult& band) {
  band.epsilon = 0.0;
  band.worst_face = 0;
  for (std::size_t i = 0; i < band.face_epsilon.size(); ++i)
    if (band.face_epsilon[i] > band.epsilon) {
      band.epsilon = band.face_epsilon[i];
      band.worst_face = i;
    }
}

BandResult certify_band(const SignedDistance& sdf, const TriangleMesh& offset, double d, const BandOptions& options) {
  Timer timer;
  BandResult result;
  const std::size_t n = offset.faces.size();
  result.face_epsilon.assign(n, kInf);
  std::vector<std::size_t> pieces(n, 0), touching(n, 0);
  const double ad = std::abs(d);
  // Per face: the certified lower end of dist(T, F), the upper end, and the side of F.
  std::vector<double> lo(n, 0.0), hi(n, kInf), slack(n, 0.0);
  std::vector<int> side(n, 0);
  auto epsilon_of = [&](std::size_t i) {
    if (!(lo[i] > 0.0)) return round_up(ad + hi[i]);  // not proved disjoint from F: may cross it
    // Disjoint from F: the whole face is on one side, that of any of its points (exact test).
    const double s_lo = side[i] > 0 ? lo[i] : -hi[i], s_hi = side[i] > 0 ? hi[i] : -lo[i];
    return round_up(std::max(s_hi - d, d - s_lo));
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 16), [&](const auto& range) {
    std::int64_t hint = -1;  // consecutive faces are mostly neighbours
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const Face& f = offset.faces[i];
      const Vec3 &a = offset.vertices[f[0]], &b = offset.vertices[f[1]], &c = offset.vertices[f[2]];
      const double d2lo = sdf.triangle_squared_distance_lower({a, b, c});
      lo[i] = sqrt_interval({d2lo, d2lo}).lo;
      // Split points are rounded: every point of the face is within `slack` of a piece, and s is
      // 1-Lipschitz, so the slack widens the upper bound.
      const double scale = std::max({a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff(), c.cwiseAbs().maxCoeff()});
      slack[i] = 8.0 * std::numeric_limits<double>::epsilon() * scale;
      hi[i] = round_up(upper_bound(sdf, a, b, c, ad + options.target, options.max_split_depth, pieces[i], hint) +
                       slack[i]);
      if (lo[i] > 0.0) side[i] = sdf.side(a, Interval{lo[i], kInf});  // a is off F: no on-surface test
      else touching[i] = 1;
      result.face_epsilon[i] = epsilon_of(i);
    }
  });
  // A deeper second pass where only a few faces miss: a loose bound should not force a re-mesh;
  // many misses mean the mesh is too coarse, and the caller re-meshes anyway.
  if (options.second_pass_above > 0.0) {
    std::vector<std::size_t> wide;
    for (std::size_t i = 0; i < n; ++i)
      if (lo[i] > 0.0 && result.face_epsilon[i] > options.second_pass_above) wide.push_back(i);
    if (!wide.empty() && wide.size() <= std::max<std::size_t>(200, n / 100)) {
      tbb::parallel_for(std::size_t{0}, wide.size(), [&](std::size_t k) {
        const std::size_t i = wide[k];
        const Face& f = offset.faces[i];
        std::int64_t hint = -1;
        const double deeper = round_up(upper_bound(sdf, offset.vertices[f[0]], offset.vertices[f[1]],
                                                   offset.vertices[f[2]], ad + 0.5 * options.target,
                                                   options.max_split_depth + 2, pieces[i], hint) + slack[i]);
        hi[i] = std::min(hi[i], deeper);  // both are valid upper bounds
        result.face_epsilon[i] = epsilon_of(i);
      });
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    result.pieces += pieces[i];
    result.faces_touching += touching[i];
  }
  set_band_maximum(result);
  result.seconds = timer.seconds();
  return result;
}

}  // namespace cdbench
