#include "mesh/weld.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <tuple>

#include <tbb/parallel_sort.h>

#include "util/error.h"
#include "util/union_find.h"

namespace cdbench {
namespace {

// Representative (smallest index) of every vertex whose coordinates equal another's exactly.
void exact_clusters(const std::vector<Vec3>& p, UnionFind& uf) {
  std::vector<std::size_t> order(p.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  const auto less = [&](std::size_t a, std::size_t b) {
    return std::tie(p[a].x(), p[a].y(), p[a].z()) < std::tie(p[b].x(), p[b].y(), p[b].z());
  };
  // Equal points are united whatever their order, so a parallel sort gives the same clusters.
  tbb::parallel_sort(order.begin(), order.end(), less);
  for (std::size_t k = 1; k < order.size(); ++k)
    if (!less(order[k - 1], order[k])) uf.unite(order[k - 1], order[k]);
}

// Pairs closer than `tol`, found through a grid of cell size tol (each pair is in adjacent cells).
void tolerance_clusters(const std::vector<Vec3>& p, double tol, UnionFind& uf) {
  using Key = std::tuple<std::int64_t, std::int64_t, std::int64_t>;
  std::map<Key, std::vector<std::size_t>> grid;
  const double limit = 9.0e15;  // cell indices stay exact integers
  const auto key_of = [&](const Vec3& v) {
    const Vec3 c = (v / tol).array().floor();
    if (!(c.cwiseAbs().maxCoeff() < limit))
      throw InputError("--weld-tolerance " + std::to_string(tol) +
                       " is too small for the coordinates of this mesh (grid cells overflow)");
    return Key{static_cast<std::int64_t>(c.x()), static_cast<std::int64_t>(c.y()), static_cast<std::int64_t>(c.z())};
  };
  for (std::size_t i = 0; i < p.size(); ++i) grid[key_of(p[i])].push_back(i);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Key k = key_of(p[i]);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find({std::get<0>(k) + dx, std::get<1>(k) + dy, std::get<2>(k) + dz});
          if (it == grid.end()) continue;
          for (std::size_t j : it->second)
            if (j < i && (p[i] - p[j]).norm() <= tol) uf.unite(i, j);
        }
  }
}

}  // namespace

WeldResult weld_vertices(PolygonSoup& soup, double tolerance) {
  if (!(tolerance >= 0.0) || !std::isfinite(tolerance))
    throw InputError("weld tolerance must be a finite number >= 0, got " + std::to_string(tolerance));
  WeldResult result;
  const std::size_t n = soup.points.size();
  result.vertices_before = result.vertices_after = n;
  UnionFind uf(n);
  exact_clusters(soup.points, uf);
  if (tolerance > 0.0) tolerance_clusters(soup.points, tolerance, uf);

  // New indices in the order of first occurrence; roots are the smallest index of their cluster.
  std::vector<std::size_t> index(n);
  std::vector<Vec3> points;
  points.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t r = uf.find(i);
    if (r == i) {
      index[i] = points.size();
      points.push_back(soup.points[i]);
    } else {
      index[i] = index[r];
      result.max_displacement = std::max(result.max_displacement, (soup.points[i] - soup.points[r]).norm());
    }
  }
  result.vertices_after = points.size();
  if (result.vertices_after == n) return result;
  soup.points = std::move(points);

  std::vector<std::vector<std::size_t>> polygons;
  polygons.reserve(soup.polygons.size());
  for (auto& poly : soup.polygons) {
    for (std::size_t& id : poly) id = index[id];
    if (tolerance > 0.0) {
      std::vector<std::size_t> kept;
      for (std::size_t k = 0; k < poly.size(); ++k)
        if (poly[k] != poly[(k + 1) % poly.size()]) kept.push_back(poly[k]);
      if (kept.size() < 3) {
        ++result.polygons_dropped;
        continue;
      }
      poly = std::move(kept);
    }
    polygons.push_back(std::move(poly));
  }
  soup.polygons = std::move(polygons);
  return result;
}

}  // namespace cdbench
