#include "mesh/self_intersections.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "util/large_pages.h"

namespace cdbench {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
K::Point_3 P(const Vec3& v) { return K::Point_3(v.x(), v.y(), v.z()); }

bool overlap(const Aabb& a, const Aabb& b) {
  for (int k = 0; k < 3; ++k)
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
  return true;
}

// A uniform grid over the mesh's box: cell coordinates by a monotone map, so that a box's cells
// are those between its corners' cells and the least corner of two boxes' overlap lies in a cell
// both are listed in.
struct Grid {
  double origin[3] = {0, 0, 0};
  double inv = 1.0;
  std::uint32_t cells[3] = {1, 1, 1};
  static constexpr int kBits = 21;
  static constexpr std::uint32_t kMaxCells = 1u << 20;

  std::uint32_t cell(double x, int k) const {
    const double t = (x - origin[k]) * inv;
    if (!(t > 0.0)) return 0;
    if (t >= static_cast<double>(cells[k] - 1)) return cells[k] - 1;
    return static_cast<std::uint32_t>(t);
  }
  // The cells a box spans (at most 2^60).
  std::uint64_t span(const Aabb& b) const {
    std::uint64_t n = 1;
    for (int k = 0; k < 3; ++k) n *= cell(b.hi[k], k) - cell(b.lo[k], k) + 1;
    return n;
  }
  static std::uint64_t key(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
    return (static_cast<std::uint64_t>(x) << (2 * kBits)) | (static_cast<std::uint64_t>(y) << kBits) | z;
  }
};

// Cells of about twice the median face's largest extent; coarser while the faces' cells (their
// listings) would exceed kListingsPerFace per face (long faces of CAD parts span many cells).
Grid make_grid(const std::vector<Aabb, LargePageAllocator<Aabb>>& boxes) {
  const std::size_t n = boxes.size();
  const Aabb all = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, n), Aabb(),
      [&](const tbb::blocked_range<std::size_t>& r, Aabb b) {
        for (std::size_t i = r.begin(); i < r.end(); ++i) b.extend(boxes[i]);
        return b;
      },
      [](Aabb a, const Aabb& b) {
        a.extend(b);
        return a;
      });
  // The median of a sample (every step-th face) sizes the cells: only the work depends on it.
  const std::size_t step = std::max<std::size_t>(1, n / 65536);
  std::vector<double> extent;
  for (std::size_t i = 0; i < n; i += step) extent.push_back(boxes[i].extent().maxCoeff());
  const auto mid = extent.begin() + static_cast<std::ptrdiff_t>(extent.size() / 2);
  std::nth_element(extent.begin(), mid, extent.end());
  double h = std::max({2.0 * *mid, all.extent().maxCoeff() / (Grid::kMaxCells - 1), std::numeric_limits<double>::min()});
  constexpr std::uint64_t kListingsPerFace = 8;
  const std::uint64_t budget = kListingsPerFace * n + 4096;
  Grid g;
  for (int k = 0; k < 3; ++k) g.origin[k] = all.lo[k];
  for (;;) {
    g.inv = 1.0 / h;
    for (int k = 0; k < 3; ++k)
      g.cells[k] = static_cast<std::uint32_t>(std::min<double>(std::ceil(all.extent()[k] * g.inv) + 1.0, Grid::kMaxCells));
    const std::uint64_t listings = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, n), std::uint64_t(0),
        [&](const tbb::blocked_range<std::size_t>& r, std::uint64_t s) {
          for (std::size_t i = r.begin(); i < r.end() && s <= budget; ++i) s += g.span(boxes[i]);
          return s;  // at most budget + 2^60
        },
        [&](std::uint64_t a, std::uint64_t b) { return std::min(a, budget + 1) + std::min(b, budget + 1); });
    if (listings <= budget) return g;
    h *= 1.5;
  }
}

}  // namespace

bool faces_intersect(const TriangleMesh& mesh, std::uint32_t f, std::uint32_t g) {
  const Face& a = mesh.faces[f];
  const Face& b = mesh.faces[g];
  int shared = 0, ia[3] = {0, 0, 0}, ib[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a[i] == b[j] && shared < 3) ia[shared] = i, ib[shared] = j, ++shared;
  const auto at = [&](const Face& x, int i) { return P(mesh.vertices[x[i]]); };
  if (shared >= 3) return true;  // the same corners: the faces coincide
  if (shared == 2) {
    // An edge uv: they meet beyond it when coplanar with the third corners r and w on one side.
    const K::Point_3 u = at(a, ia[0]), v = at(a, ia[1]), r = at(a, 3 - ia[0] - ia[1]), w = at(b, 3 - ib[0] - ib[1]);
    return CGAL::coplanar(u, v, r, w) && CGAL::coplanar_orientation(u, v, r, w) == CGAL::POSITIVE;
  }
  const K::Triangle_3 ta(at(a, 0), at(a, 1), at(a, 2)), tb(at(b, 0), at(b, 1), at(b, 2));
  if (shared == 1) {
    // A corner: they meet elsewhere exactly when the edge opposite it in one face meets the other.
    const int i = ia[0], j = ib[0];
    return CGAL::do_intersect(ta, K::Segment_3(at(b, (j + 1) % 3), at(b, (j + 2) % 3))) ||
           CGAL::do_intersect(tb, K::Segment_3(at(a, (i + 1) % 3), at(a, (i + 2) % 3)));
  }
  return CGAL::do_intersect(ta, tb);
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> self_intersecting_faces(const TriangleMesh& mesh) {
  using Pairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;
  const std::size_t n = mesh.faces.size();
  if (n < 2) return {};
  // Large arrays with their pages first touched on all threads (util/large_pages.h).
  std::vector<Aabb, LargePageAllocator<Aabb>> boxes(n);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
    boxes[i] = bounding_box(3, [&](int k) { return mesh.vertices[mesh.faces[i][k]]; });
  });
  const Grid grid = make_grid(boxes);

  // Every face listed in each cell its box spans, sorted by cell.
  std::vector<std::uint64_t, LargePageAllocator<std::uint64_t>> first(n + 1, 0);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) { first[i + 1] = grid.span(boxes[i]); });
  for (std::size_t i = 0; i < n; ++i) first[i + 1] += first[i];
  struct Listing {
    std::uint64_t key;
    std::uint32_t face;
  };
  const std::size_t count = first[n];
  std::vector<Listing, LargePageAllocator<Listing>> listings(count);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
    const Aabb& b = boxes[i];
    std::uint64_t at = first[i];
    const auto face = static_cast<std::uint32_t>(i);
    for (std::uint32_t x = grid.cell(b.lo[0], 0); x <= grid.cell(b.hi[0], 0); ++x)
      for (std::uint32_t y = grid.cell(b.lo[1], 1); y <= grid.cell(b.hi[1], 1); ++y)
        for (std::uint32_t z = grid.cell(b.lo[2], 2); z <= grid.cell(b.hi[2], 2); ++z)
          listings[at++] = {Grid::key(x, y, z), face};
  });
  tbb::parallel_sort(listings.begin(), listings.end(), [](const Listing& p, const Listing& q) {
    return p.key != q.key ? p.key < q.key : p.face < q.face;
  });
  std::vector<std::size_t> starts;  // of the cells with two faces or more
  for (std::size_t i = 0; i + 1 < count;) {
    std::size_t j = i + 1;
    while (j < count && listings[j].key == listings[i].key) ++j;
    if (j - i >= 2) starts.push_back(i);
    i = j;
  }

  tbb::enumerable_thread_specific<Pairs> found;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, starts.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    Pairs& out = found.local();
    std::vector<std::uint32_t> faces;
    for (std::size_t s = r.begin(); s < r.end(); ++s) {
      const std::uint64_t key = listings[starts[s]].key;
      faces.clear();
      for (std::size_t i = starts[s]; i < count && listings[i].key == key; ++i) faces.push_back(listings[i].face);
      const std::uint32_t cell[3] = {static_cast<std::uint32_t>(key >> (2 * Grid::kBits)),
                                     static_cast<std::uint32_t>(key >> Grid::kBits) & (Grid::kMaxCells * 2 - 1),
                                     static_cast<std::uint32_t>(key) & (Grid::kMaxCells * 2 - 1)};
      const auto visit = [&](std::uint32_t f, std::uint32_t g) {
        const Aabb &a = boxes[f], &b = boxes[g];
        if (!overlap(a, b)) return;
        // Once: in the cell of the overlap's least corner.
        for (int k = 0; k < 3; ++k)
          if (grid.cell(std::max(a.lo[k], b.lo[k]), k) != cell[k]) return;
        if (faces_intersect(mesh, f, g)) out.emplace_back(std::min(f, g), std::max(f, g));
      };
      // A crowded cell (a finely faceted detail beside long faces) is swept along x.
      constexpr std::size_t kSweepFrom = 32;
      if (faces.size() < kSweepFrom) {
        for (std::size_t i = 0; i < faces.size(); ++i)
          for (std::size_t j = i + 1; j < faces.size(); ++j) visit(faces[i], faces[j]);
      } else {
        std::sort(faces.begin(), faces.end(), [&](std::uint32_t p, std::uint32_t q) {
          return boxes[p].lo[0] != boxes[q].lo[0] ? boxes[p].lo[0] < boxes[q].lo[0] : p < q;
        });
        for (std::size_t i = 0; i < faces.size(); ++i)
          for (std::size_t j = i + 1; j < faces.size() && boxes[faces[j]].lo[0] <= boxes[faces[i]].hi[0]; ++j)
            visit(faces[i], faces[j]);
      }
    }
  });
  Pairs pairs;
  for (const Pairs& p : found) pairs.insert(pairs.end(), p.begin(), p.end());
  tbb::parallel_sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace cdbench
