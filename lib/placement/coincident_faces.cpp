#include "placement/coincident_faces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "core/interval.h"

#include "distance/exact_predicates.h"

namespace cdbench {

namespace {

std::uint64_t mix(std::uint64_t h) {  // splitmix64's finaliser
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  return h ^ (h >> 31);
}

constexpr std::uint32_t kNone = 0xffffffffu;

// floor(y) as an integer, false beyond 2^62 (and for NaN).
bool floor_index(double y, std::int64_t* q) {
  if (!(std::abs(y) < 0x1p62)) return false;
  *q = static_cast<std::int64_t>(y);
  if (y < static_cast<double>(*q)) --*q;
  return true;
}

// An upper bound of |p - q| in any rounding mode: each computed difference is within 2u of the
// exact one (exact where it is subnormal, and 0 only where the coordinates are equal), sqrt(3)
// times the largest bounds the norm, and the two products' roundings (2u each) are covered with
// margin by the factor (45 u) and the last step up.
double distance_bound(const Vec3& p, const Vec3& q) {
  const double m = (p - q).cwiseAbs().maxCoeff();
  return m == 0.0 ? 0.0 : round_up(kSqrt3Up * m * (1.0 + 1e-14));
}

}  // namespace

std::size_t CoincidentFaces::KeyHash::operator()(const Key& k) const {
  return static_cast<std::size_t>(mix(k.x ^ mix(k.y ^ mix(k.z))));
}

bool CoincidentFaces::cell_of(const Vec3& p, Key* k) const {
  std::int64_t c[3];
  for (int i = 0; i < 3; ++i)
    if (!floor_index(p[i] * inv_side_, &c[i])) return false;
  *k = {static_cast<std::uint64_t>(c[0]), static_cast<std::uint64_t>(c[1]), static_cast<std::uint64_t>(c[2])};
  return true;
}

std::array<std::size_t, 2> CoincidentFaces::filter_slots(const Key& k) const {
  const std::uint64_t h = KeyHash()(k);
  return {static_cast<std::size_t>(h) & filter_mask_, static_cast<std::size_t>(h >> 32) & filter_mask_};
}

bool CoincidentFaces::in_filter(const Key& k) const {
  const std::array<std::size_t, 2> b = filter_slots(k);
  return (filter_[b[0] / 64] >> (b[0] % 64) & 1) && (filter_[b[1] / 64] >> (b[1] % 64) & 1);
}

CoincidentFaces::CoincidentFaces(const TriangleMesh& fixed, double radius) : vertices_(&fixed.vertices) {
  const std::vector<Vec3>& V = fixed.vertices;
  if (radius >= 0.0) {
    radius_ = radius;
  } else {
    double scale = 0.0;
    for (const Vec3& v : V) scale = std::max(scale, v.cwiseAbs().maxCoeff());
    radius_ = std::ldexp(scale, -40);
  }
  const double side = 64.0 * radius_;  // most vertices in one cell, each cell far smaller than an edge
  // All of F at the origin (or no F): one cell about it, exact matches only.
  if (side > 0.0 && std::isfinite(1.0 / side)) inv_side_ = 1.0 / side;
  // A cube a sixteenth wider than radius() about each vertex: a placed corner within radius()
  // falls in one of its cells whatever the products' rounding (matching only steers).
  const double reach = radius_ * 1.0625;
  head_.reserve(V.size() + V.size() / 2);  // about 1.1 cells a vertex
  entries_.reserve(V.size() + V.size() / 2);
  // Vertices sharing coordinates (-0 as +0) numbered by the first of them: sorted, not hashed by
  // cell, so that a radius near F's extent (all of F in a few cells) costs no scan a vertex.
  std::vector<std::uint32_t> id(V.size()), order;
  order.reserve(V.size());
  for (std::size_t v = 0; v < V.size(); ++v) {
    id[v] = static_cast<std::uint32_t>(v);
    if (V[v].allFinite()) order.push_back(static_cast<std::uint32_t>(v));  // others match nothing
  }
  const auto less = [&V](std::uint32_t a, std::uint32_t b) {
    const Vec3 &p = V[a], &q = V[b];
    if (p[0] != q[0]) return p[0] < q[0];
    if (p[1] != q[1]) return p[1] < q[1];
    if (p[2] != q[2]) return p[2] < q[2];
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  for (std::size_t i = 1; i < order.size(); ++i)
    if (V[order[i]] == V[order[i - 1]]) id[order[i]] = id[order[i - 1]];
  for (const std::uint32_t v : order) {
    const Vec3& p = V[v];
    if (id[v] != v) continue;
    // The cells about it (|p| is at most 2^37 sides, so these are numbered too).
    std::int64_t lo[3], hi[3];
    for (int i = 0; i < 3; ++i)
      if (!floor_index((p[i] - reach) * inv_side_, &lo[i]) || !floor_index((p[i] + reach) * inv_side_, &hi[i]))
        lo[i] = 1, hi[i] = 0;
    for (std::int64_t x = lo[0]; x <= hi[0]; ++x)
      for (std::int64_t y = lo[1]; y <= hi[1]; ++y)
        for (std::int64_t z = lo[2]; z <= hi[2]; ++z) {
          const Key k{static_cast<std::uint64_t>(x), static_cast<std::uint64_t>(y), static_cast<std::uint64_t>(z)};
          auto [it, fresh] = head_.emplace(k, static_cast<std::uint32_t>(entries_.size()));
          entries_.push_back({static_cast<std::uint32_t>(v), fresh ? kNone : it->second});
          it->second = static_cast<std::uint32_t>(entries_.size() - 1);
        }
  }
  std::size_t bits = 64;
  while (bits < 16 * head_.size()) bits *= 2;
  filter_.assign(bits / 64, 0);
  filter_mask_ = bits - 1;
  for (const auto& [k, first] : head_)
    for (const std::size_t b : filter_slots(k)) filter_[b / 64] |= std::uint64_t(1) << (b % 64);
  corners_.resize(fixed.faces.size());
  about_first_.assign(V.size() + 1, 0);
  for (std::size_t f = 0; f < fixed.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) ++about_first_[(corners_[f][k] = id[fixed.faces[f][k]]) + 1];
  for (std::size_t v = 0; v < V.size(); ++v) about_first_[v + 1] += about_first_[v];
  about_.resize(3 * fixed.faces.size());
  std::vector<std::uint32_t> fill(about_first_.begin(), about_first_.end() - 1);
  for (std::size_t f = 0; f < fixed.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) about_[fill[corners_[f][k]]++] = static_cast<std::uint32_t>(f);
}

bool CoincidentFaces::has_face(std::uint32_t a, std::uint32_t b, std::uint32_t c) const {
  std::array<std::uint32_t, 3> want{a, b, c};
  std::sort(want.begin(), want.end());
  for (std::uint32_t i = about_first_[a]; i < about_first_[a + 1]; ++i) {
    std::array<std::uint32_t, 3> k = corners_[about_[i]];
    std::sort(k.begin(), k.end());
    if (k == want) return true;
  }
  return false;
}

int CoincidentFaces::near_vertices(const Vec3& p, std::uint32_t* out, int max) const {
  Key k;
  if (!cell_of(p, &k) || !in_filter(k)) return 0;
  const auto it = head_.find(k);
  if (it == head_.end()) return 0;
  // At most 64 entries: a cell holds about one vertex, but a radius near F's extent (a retry at a
  // tolerance of several per cent of the diagonal) would put all of F in a few cells and make each
  // lookup a scan of F. Matching only steers, so a long chain's tail may go unseen.
  int n = 0, seen = 0;
  for (std::uint32_t e = it->second; e != kNone && n < max && seen < 64; e = entries_[e].next, ++seen) {
    const std::uint32_t v = entries_[e].vertex;
    if (((*vertices_)[v] - p).cwiseAbs().maxCoeff() <= radius_) out[n++] = v;
  }
  return n;
}

double CoincidentFaces::match(const Vec3& a, const Vec3& b, const Vec3& c) const {
  constexpr int kMax = 4;  // more of F's vertices within radius() of one point: F is degenerate there
  const Vec3* p[3] = {&a, &b, &c};
  std::uint32_t near[3][kMax];
  int count[3];
  for (int i = 0; i < 3; ++i)
    if ((count[i] = near_vertices(*p[i], near[i], kMax)) == 0) return -1.0;
  double best = -1.0;
  for (int i = 0; i < count[0]; ++i)
    for (int j = 0; j < count[1]; ++j)
      for (int l = 0; l < count[2]; ++l) {
        if (!has_face(near[0][i], near[1][j], near[2][l])) continue;
        const std::vector<Vec3>& V = *vertices_;
        const double e = std::max({distance_bound(a, V[near[0][i]]), distance_bound(b, V[near[1][j]]),
                                   distance_bound(c, V[near[2][l]])});
        if (best < 0.0 || e < best) best = e;
      }
  return best;
}

bool CoincidentFaces::any_vertex(const PlacedView& P, std::size_t n) const {
  std::uint32_t v;
  for (std::size_t i = 0; i < n; ++i)
    if (near_vertices(P[i], &v, 1)) return true;
  return false;
}

const CoincidentFaces& LazyCoincidentFaces::get() const {
  std::call_once(once_, [this] { index_ = std::make_unique<CoincidentFaces>(fixed_, radius_); });
  return *index_;
}

PlacedMatches::PlacedMatches(const CoincidentFaces& index, const Bvh<Aabb>& boxes, const std::vector<Face>& faces,
                             const PlacedView& P)
    : index_(index), boxes_(boxes), faces_(faces), P_(P),
      node_(boxes.nodes.size(), std::numeric_limits<double>::quiet_NaN()),
      face_(faces.size(), std::numeric_limits<double>::quiet_NaN()) {}

double PlacedMatches::face(std::uint32_t f) {
  double& e = face_[f];
  if (std::isnan(e)) {
    const Face& x = faces_[f];
    e = index_.match(P_[x[0]], P_[x[1]], P_[x[2]]);
  }
  return e;
}

double PlacedMatches::node(std::uint32_t n) {
  if (!std::isnan(node_[n])) return node_[n];
  const auto& nd = boxes_.nodes[n];
  double worst = 0.0;
  if (nd.count == 0) {
    for (std::uint32_t child = nd.first; child < nd.first + 2 && worst >= 0.0; ++child) {
      const double e = node(child);
      worst = e < 0.0 ? e : std::max(worst, e);
    }
  } else {
    for (std::uint32_t i = 0; i < nd.count && worst >= 0.0; ++i) {
      const double e = face(boxes_.order[nd.first + i]);
      worst = e < 0.0 ? e : std::max(worst, e);
    }
  }
  return node_[n] = worst;
}

namespace {

// Whether the plane of pqr (not degenerate) has the corners of abc on one closed side, and those in
// it all among `allowed` (null: any, but not all three): then it meets abc at most in a corner or
// an edge in it.
bool supports(const Vec3& p, const Vec3& q, const Vec3& r, const std::array<const Vec3*, 3>& abc,
              const std::array<const Vec3*, 3>* allowed) {
  bool above = false, below = false;
  int in_plane = 0;
  for (const Vec3* x : abc) {
    const int o = orientation_sign(p, q, r, *x);
    above |= o > 0;
    below |= o < 0;
    if (o == 0) {
      ++in_plane;
      if (allowed && *x != *(*allowed)[0] && *x != *(*allowed)[1] && *x != *(*allowed)[2]) return false;
    }
  }
  return !(above && below) && in_plane < 3;
}

}  // namespace

bool triangles_meeting_interior(const SignedDistance& fixed, const Vec3& a, const Vec3& b, const Vec3& c,
                                std::size_t max_count, std::vector<std::uint32_t>& out) {
  out.clear();
  if (corners_collinear(a, b, c)) return false;
  Aabb box;
  box.extend(a);
  box.extend(b);
  box.extend(c);
  std::vector<std::uint32_t> near;
  if (!fixed.triangles_meeting_box(box, 4 * max_count, near)) return false;
  const std::array<const Vec3*, 3> abc{&a, &b, &c};
  const auto& V = fixed.mesh().vertices;
  for (const std::uint32_t id : near) {
    const Face& f = fixed.mesh().faces[id];
    const Vec3 &p = V[f[0]], &q = V[f[1]], &r = V[f[2]];
    if (!triangles_intersect(p, q, r, a, b, c)) continue;
    const std::array<const Vec3*, 3> pqr{&p, &q, &r};
    if (!corners_collinear(p, q, r) && supports(p, q, r, abc, nullptr)) continue;
    if (supports(a, b, c, pqr, &abc)) continue;
    out.push_back(id);
    if (out.size() > max_count) return false;
  }
  return true;
}

}  // namespace cdbench
