#include "mesh/shapes.h"

#include <cmath>
#include <map>
#include <utility>

namespace cdbench {

TriangleMesh make_icosphere(double radius, int subdivisions, const Vec3& center) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& p : v) p.normalize();
  std::vector<Face> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                         {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                         {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      const auto id = static_cast<std::uint32_t>(v.size() - 1);
      mid.emplace(key, id);
      return id;
    };
    std::vector<Face> next;
    for (const Face& q : f) {
      const std::uint32_t a = midpoint(q[0], q[1]), b = midpoint(q[1], q[2]), c = midpoint(q[2], q[0]);
      next.push_back({q[0], a, c});
      next.push_back({q[1], b, a});
      next.push_back({q[2], c, b});
      next.push_back({a, b, c});
    }
    f = std::move(next);
  }
  TriangleMesh m;
  for (const Vec3& p : v) m.vertices.push_back(center + radius * p);
  m.faces = std::move(f);
  return m;
}

TriangleMesh make_torus(double R, double r, int nu, int nv) {
  TriangleMesh m;
  const double pi = std::acos(-1.0);
  for (int i = 0; i < nu; ++i) {
    const double u = 2 * pi * i / nu;
    for (int j = 0; j < nv; ++j) {
      const double w = 2 * pi * j / nv;
      m.vertices.emplace_back((R + r * std::cos(w)) * std::cos(u), (R + r * std::cos(w)) * std::sin(u), r * std::sin(w));
    }
  }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(((i + nu) % nu) * nv + (j + nv) % nv); };
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return m;
}

TriangleMesh make_box(const Vec3& lo, const Vec3& hi) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z());
  m.faces = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
             {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

TriangleMesh make_tube(double r_in, double r_out, double length, int n) {
  TriangleMesh m;
  const double pi = std::acos(-1.0);
  // Rings: outer bottom, outer top, inner bottom, inner top.
  for (const auto& [r, z] : {std::pair{r_out, 0.0}, {r_out, length}, {r_in, 0.0}, {r_in, length}})
    for (int i = 0; i < n; ++i)
      m.vertices.emplace_back(r * std::cos(2 * pi * i / n), r * std::sin(2 * pi * i / n), z);
  const auto id = [&](int ring, int i) { return static_cast<std::uint32_t>(ring * n + (i + n) % n); };
  for (int i = 0; i < n; ++i) {
    const std::uint32_t ob = id(0, i), ob1 = id(0, i + 1), ot = id(1, i), ot1 = id(1, i + 1);
    const std::uint32_t ib = id(2, i), ib1 = id(2, i + 1), it = id(3, i), it1 = id(3, i + 1);
    m.faces.push_back({ob, ob1, ot1});  // outer wall, facing away from the axis
    m.faces.push_back({ob, ot1, ot});
    m.faces.push_back({ib, it1, ib1});  // inner wall, facing the axis
    m.faces.push_back({ib, it, it1});
    m.faces.push_back({ob, ib, ib1});   // bottom, facing -z
    m.faces.push_back({ob, ib1, ob1});
    m.faces.push_back({ot, ot1, it1});  // top, facing +z
    m.faces.push_back({ot, it1, it});
  }
  return m;
}

TriangleMesh make_cylinder(double r, double length, int n) {
  TriangleMesh m;
  const double pi = std::acos(-1.0);
  for (const double z : {0.0, length})
    for (int i = 0; i < n; ++i) m.vertices.emplace_back(r * std::cos(2 * pi * i / n), r * std::sin(2 * pi * i / n), z);
  const auto id = [&](int ring, int i) { return static_cast<std::uint32_t>(ring * n + (i + n) % n); };
  for (int i = 0; i < n; ++i) {
    m.faces.push_back({id(0, i), id(0, i + 1), id(1, i + 1)});  // side, facing away from the axis
    m.faces.push_back({id(0, i), id(1, i + 1), id(1, i)});
  }
  for (int i = 1; i + 1 < n; ++i) {
    m.faces.push_back({id(0, 0), id(0, i + 1), id(0, i)});  // bottom, facing -z
    m.faces.push_back({id(1, 0), id(1, i), id(1, i + 1)});  // top, facing +z
  }
  return m;
}

TriangleMesh merge_meshes(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh m = a;
  const auto offset = static_cast<std::uint32_t>(a.vertices.size());
  m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const Face& f : b.faces) m.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
  return m;
}

}  // namespace cdbench
