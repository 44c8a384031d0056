#include "placement/coincident_faces.h"

#include <algorithm>
#include <array>
#include <cstring>

#include "distance/exact_predicates.h"

namespace cdbench {

namespace {

std::uint64_t bits(double v) {
  v += 0.0;  // -0 -> +0: equal coordinates, equal keys
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

std::uint64_t mix(std::uint64_t h) {  // splitmix64's finaliser
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  return h ^ (h >> 31);
}

}  // namespace

std::size_t CoincidentFaces::KeyHash::operator()(const Key& k) const {
  return static_cast<std::size_t>(mix(k.x ^ mix(k.y ^ mix(k.z))));
}

CoincidentFaces::Key CoincidentFaces::key_of(const Vec3& p) { return {bits(p[0]), bits(p[1]), bits(p[2])}; }

std::array<std::size_t, 2> CoincidentFaces::filter_slots(const Key& k) const {
  const std::uint64_t h = KeyHash()(k);
  return {static_cast<std::size_t>(h) & filter_mask_, static_cast<std::size_t>(h >> 32) & filter_mask_};
}

CoincidentFaces::CoincidentFaces(const TriangleMesh& fixed) {
  vertex_.reserve(fixed.vertices.size());
  std::size_t bits = 64;
  while (bits < 16 * fixed.vertices.size()) bits *= 2;
  filter_.assign(bits / 64, 0);
  filter_mask_ = bits - 1;
  std::vector<std::uint32_t> id(fixed.vertices.size());
  for (std::size_t v = 0; v < fixed.vertices.size(); ++v) {
    const Key k = key_of(fixed.vertices[v]);
    for (const std::size_t b : filter_slots(k)) filter_[b / 64] |= std::uint64_t(1) << (b % 64);
    id[v] = vertex_.emplace(k, static_cast<std::uint32_t>(v)).first->second;
  }
  faces_.reserve(fixed.faces.size());
  for (const Face& f : fixed.faces) {
    std::array<std::uint64_t, 3> k{id[f[0]], id[f[1]], id[f[2]]};
    std::sort(k.begin(), k.end());
    faces_.insert({k[0], k[1], k[2]});
  }
}

bool CoincidentFaces::contains(const Vec3& a, const Vec3& b, const Vec3& c) const {
  std::array<std::uint64_t, 3> k;
  const Vec3* p[3] = {&a, &b, &c};
  for (int i = 0; i < 3; ++i) {
    const auto it = vertex_.find(key_of(*p[i]));
    if (it == vertex_.end()) return false;
    k[i] = it->second;
  }
  std::sort(k.begin(), k.end());
  return faces_.count({k[0], k[1], k[2]}) > 0;
}

bool CoincidentFaces::any_vertex(const PlacedView& P, std::size_t n) const {
  for (std::size_t v = 0; v < n; ++v) {
    const Key k = key_of(P[v]);
    const std::array<std::size_t, 2> b = filter_slots(k);
    if ((filter_[b[0] / 64] >> (b[0] % 64) & 1) && (filter_[b[1] / 64] >> (b[1] % 64) & 1) && vertex_.count(k))
      return true;
  }
  return false;
}

bool faces_on_f(const CoincidentFaces& index, const Bvh<Aabb>& boxes, const std::vector<Face>& faces,
                const PlacedView& P, std::uint32_t n) {
  std::vector<std::uint32_t> stack{n};
  while (!stack.empty()) {
    const auto& node = boxes.nodes[stack.back()];
    stack.pop_back();
    if (node.count == 0) {
      stack.push_back(node.first + 1);
      stack.push_back(node.first);
      continue;
    }
    for (std::uint32_t i = 0; i < node.count; ++i)
      if (!face_on_f(index, faces, P, boxes.order[node.first + i])) return false;
  }
  return true;
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
