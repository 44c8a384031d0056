// CGAL's polygon-mesh-processing code (triangulation of polygons, self-intersections, orientation)
// lives in this translation unit only.
#include "mesh/validate_mesh.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <numeric>
#include <sstream>

#include "mesh/self_intersections.h"
#include "mesh/weld.h"
#include "util/large_pages.h"
#include "util/timer.h"
#include "util/union_find.h"

namespace cdbench {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

std::string pt(const Vec3& p) {
  std::ostringstream os;
  os.precision(17);
  os << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return os.str();
}

Point to_point(const Vec3& v) { return Point(v.x(), v.y(), v.z()); }

// Triangulates one polygon; CGAL's hole triangulation handles non-convex planar and non-planar polygons.
bool triangulate_polygon(const PolygonSoup& soup, const std::vector<std::size_t>& poly, std::vector<Face>& out) {
  if (poly.size() == 3) {
    out.push_back({static_cast<std::uint32_t>(poly[0]), static_cast<std::uint32_t>(poly[1]),
                   static_cast<std::uint32_t>(poly[2])});
    return true;
  }
  std::vector<Point> ring;
  for (std::size_t id : poly) ring.push_back(to_point(soup.points[id]));
  std::vector<CGAL::Triple<int, int, int>> tris;
  PMP::triangulate_hole_polyline(ring, std::back_inserter(tris));
  if (tris.size() != poly.size() - 2) return false;
  for (const auto& t : tris)
    out.push_back({static_cast<std::uint32_t>(poly[t.first]), static_cast<std::uint32_t>(poly[t.second]),
                   static_cast<std::uint32_t>(poly[t.third])});
  return true;
}

struct HalfEdge {
  std::uint32_t lo, hi;  // undirected key
  std::uint32_t face;
  bool forward;          // the face runs lo -> hi
  bool operator<(const HalfEdge& o) const {  // a total order: any sort gives one sequence
    return lo != o.lo ? lo < o.lo : hi != o.hi ? hi < o.hi : face != o.face ? face < o.face : forward < o.forward;
  }
};

// An edge shared by exactly two faces.
struct Adjacent {
  std::uint32_t lo, hi;  // its ends, lo < hi
  std::uint32_t f1, f2;
  bool same_direction;   // both faces run it the same way (one of them must flip)
};

// CGAL's surface mesh of a closed, manifold, consistently oriented mesh (every edge in
// `adjacency`, no repeated corner, no pinched vertex), its halfedges set directly (on all threads)
// instead of face by face: Euler::add_face searches and links each face's halfedges, 0.19 s of
// serial work on 832K faces. Edge e's halfedge 2e runs lo -> hi, 2e + 1 hi -> lo; vertex, face
// and halfedge indices are ours. False (nothing usable) if the two faces at an edge run it the
// same way, which the caller has excluded.
bool build_closed_surface_mesh(const TriangleMesh& mesh, const std::vector<Adjacent>& adjacency, SurfaceMesh& sm) {
  using H = SurfaceMesh::Halfedge_index;
  const std::size_t F = mesh.faces.size();
  if (2 * adjacency.size() != 3 * F) return false;
  sm.clear();
  // Elements made in one resize each (what add_vertex, add_edge and add_face push back one by one
  // when nothing was removed), their points set on all threads.
  sm.resize(static_cast<SurfaceMesh::size_type>(mesh.vertices.size()),
            static_cast<SurfaceMesh::size_type>(adjacency.size()), static_cast<SurfaceMesh::size_type>(F));
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.vertices.size(), 8192), [&](const auto& r) {
    for (std::size_t v = r.begin(); v != r.end(); ++v)
      sm.point(SurfaceMesh::Vertex_index(static_cast<SurfaceMesh::size_type>(v))) = to_point(mesh.vertices[v]);
  });
  // The halfedge of each face corner k (from corner k to corner k + 1).
  std::vector<std::uint32_t> corner_halfedge(3 * F, UINT32_MAX);
  std::atomic<bool> consistent{true};
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, adjacency.size(), 4096), [&](const auto& r) {
    for (std::size_t e = r.begin(); e != r.end(); ++e) {
      const Adjacent& a = adjacency[e];
      std::uint32_t used[2] = {UINT32_MAX, UINT32_MAX};
      int n = 0;
      for (const std::uint32_t f : {a.f1, a.f2}) {
        const Face& t = mesh.faces[f];
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t from = t[k], to = t[(k + 1) % 3];
          if (std::min(from, to) != a.lo || std::max(from, to) != a.hi) continue;
          used[n++] = static_cast<std::uint32_t>(2 * e + (from == a.lo ? 0 : 1));
          corner_halfedge[3 * static_cast<std::size_t>(f) + k] = used[n - 1];
          break;
        }
        if (n == 2) break;
      }
      if (n != 2 || used[0] == used[1]) consistent = false;
    }
  });
  if (!consistent) return false;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, F, 4096), [&](const auto& r) {
    for (std::size_t f = r.begin(); f != r.end(); ++f) {
      const SurfaceMesh::Face_index fi(static_cast<SurfaceMesh::size_type>(f));
      const H h[3] = {H(corner_halfedge[3 * f]), H(corner_halfedge[3 * f + 1]), H(corner_halfedge[3 * f + 2])};
      for (int k = 0; k < 3; ++k) {
        sm.set_target(h[k], SurfaceMesh::Vertex_index(mesh.faces[f][(k + 1) % 3]));
        sm.set_face(h[k], fi);
        sm.set_next(h[k], h[(k + 1) % 3]);
      }
      sm.set_halfedge(fi, h[0]);
    }
  });
  // Each vertex's incoming halfedge: that of its first corner (one writer per vertex).
  for (std::size_t c = 0; c < 3 * F; ++c) {
    const SurfaceMesh::Vertex_index v(mesh.faces[c / 3][(c % 3 + 1) % 3]);
    if (sm.halfedge(v) == SurfaceMesh::null_halfedge()) sm.set_halfedge(v, H(corner_halfedge[c]));
  }
  return true;
}

// The same, face by face through CGAL (any manifold mesh, open ones too); false if CGAL rejects it.
bool build_surface_mesh_by_faces(const TriangleMesh& mesh, SurfaceMesh& sm) {
  sm.clear();
  sm.reserve(static_cast<SurfaceMesh::size_type>(mesh.vertices.size()),
             static_cast<SurfaceMesh::size_type>(3 * mesh.faces.size() / 2),
             static_cast<SurfaceMesh::size_type>(mesh.faces.size()));
  for (const Vec3& v : mesh.vertices) sm.add_vertex(to_point(v));
  for (const Face& f : mesh.faces) {
    const auto added = sm.add_face(SurfaceMesh::Vertex_index(f[0]), SurfaceMesh::Vertex_index(f[1]),
                                   SurfaceMesh::Vertex_index(f[2]));
    if (added == SurfaceMesh::null_face()) return false;
  }
  return true;
}

// The signed volume by the divergence theorem in interval arithmetic (a rigorous enclosure),
// summed in blocks of fixed size on all threads, then in block order: the same bits for any
// thread count.
CGAL::Interval_nt<false> signed_volume(const TriangleMesh& mesh) {
  using I = CGAL::Interval_nt<false>;
  constexpr std::size_t kBlock = 8192;
  const std::size_t blocks = (mesh.faces.size() + kBlock - 1) / kBlock;
  std::vector<I> partial(blocks, I(0.0));
  tbb::parallel_for(std::size_t(0), blocks, [&](std::size_t b) {
    CGAL::Protect_FPU_rounding<true> guard;
    I vol(0.0);
    for (std::size_t i = b * kBlock; i < std::min(mesh.faces.size(), (b + 1) * kBlock); ++i) {
      const Face& f = mesh.faces[i];
      const Vec3 &a = mesh.vertices[f[0]], &bb = mesh.vertices[f[1]], &c = mesh.vertices[f[2]];
      const I ax(a.x()), ay(a.y()), az(a.z()), bx(bb.x()), by(bb.y()), bz(bb.z()), cx(c.x()), cy(c.y()), cz(c.z());
      vol += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
    }
    partial[b] = vol;
  });
  CGAL::Protect_FPU_rounding<true> guard;
  I vol(0.0);
  for (const I& p : partial) vol += p;
  return vol / I(6.0);
}

void add_problem(MeshReport& r, const std::string& kind, std::size_t count, const std::string& message) {
  r.errors.push_back({kind, count, message});
}

}  // namespace

bool MeshReport::has(const std::string& kind) const {
  return std::any_of(errors.begin(), errors.end(), [&](const MeshProblem& p) { return p.kind == kind; });
}

ValidatedMesh validate_mesh(const TriangleMesh& mesh, const ValidateOptions& options) {
  PolygonSoup soup;
  soup.points = mesh.vertices;
  soup.polygons.reserve(mesh.faces.size());
  for (const Face& f : mesh.faces) soup.polygons.push_back({f[0], f[1], f[2]});
  return validate_mesh(std::move(soup), options);
}

ValidatedMesh validate_mesh(PolygonSoup soup, const ValidateOptions& options) {
  ValidatedMesh out;
  MeshReport& report = out.report;
  report.input_vertices = soup.points.size();
  report.input_polygons = soup.polygons.size();
  report.notices = soup.notices;

  // Scale: the certified kernels form products of several lengths (squared norms of cross products,
  // the terms of the triangle distances and depth bounds), which must stay within the normal double
  // range (1.8e308 down to 2.2e-308). Measured (doc/mesh-intake.md): cubes and spheres at 1e+-40
  // get correct certificates; at 1e55 the max penetration loses every digit, at 1e150 and 1e-150 it
  // never ends, at 1e200 intervals turn infinite. Outside 1e+-40: an error with the numbers.
  {
    double largest = 0.0;
    Vec3 lo = Vec3::Constant(HUGE_VAL), hi = Vec3::Constant(-HUGE_VAL);
    for (const Vec3& p : soup.points) {
      largest = std::max(largest, p.cwiseAbs().maxCoeff());
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const double diagonal = soup.points.empty() ? 0.0 : (hi - lo).norm();
    std::ostringstream os;
    os.precision(3);
    if (largest > kMaxCoordinate) {
      os << "coordinates up to " << largest << " are outside the supported range |x| <= " << kMaxCoordinate
         << " (products of lengths must stay finite in doubles): scale the mesh down";
      add_problem(report, "coordinate-range", 1, os.str());
    } else if (diagonal > 0.0 && diagonal < kMinDiagonal) {
      os << "the mesh is " << diagonal << " across, below the supported " << kMinDiagonal
         << " (products of lengths would underflow in doubles): scale the mesh up";
      add_problem(report, "coordinate-range", 1, os.str());
    }
    if (!report.errors.empty()) return out;
  }

  // 0. Weld vertices at equal positions (seams of textured exports, soups); nothing moves by default.
  if (options.weld) {
    const WeldResult w = weld_vertices(soup, options.weld_tolerance);
    if (w.merged() > 0 && options.weld_tolerance == 0.0) {
      report.notices.push_back("welded " + std::to_string(w.merged()) + " vertices with exactly equal coordinates (" +
                               std::to_string(w.vertices_before) + " -> " + std::to_string(w.vertices_after) +
                               " vertices)");
    } else if (options.weld_tolerance > 0.0) {
      std::ostringstream os;
      os.precision(17);
      os << "welded " << w.merged() << " vertices within tolerance " << options.weld_tolerance << " ("
         << w.vertices_before << " -> " << w.vertices_after << " vertices; the farthest moved by "
         << w.max_displacement << "; " << w.polygons_dropped << " polygons collapsed and were dropped)";
      report.notices.push_back(os.str());
    }
  }

  // 1. Triangulate.
  std::vector<Face> faces;
  std::size_t polygons_split = 0, failed = 0, first_failed = 0;
  if (std::all_of(soup.polygons.begin(), soup.polygons.end(), [](const auto& p) { return p.size() == 3; })) {
    faces.resize(soup.polygons.size());  // triangles only (the usual case): copied on all threads
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces.size(), 8192), [&](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
        for (int k = 0; k < 3; ++k) faces[i][k] = static_cast<std::uint32_t>(soup.polygons[i][k]);
    });
  } else {
    faces.reserve(soup.polygons.size());
    for (std::size_t i = 0; i < soup.polygons.size(); ++i) {
      const auto& poly = soup.polygons[i];
      if (poly.size() > 3) ++polygons_split;
      if (!triangulate_polygon(soup, poly, faces) && failed++ == 0) first_failed = i;
    }
  }
  if (polygons_split > 0)
    report.notices.push_back(std::to_string(polygons_split) + " polygons with more than 3 corners were triangulated");
  if (failed > 0)
    add_problem(report, "untriangulable-polygon", failed,
                std::to_string(failed) + " polygons could not be triangulated, e.g. face " + std::to_string(first_failed));

  // 2. Drop unreferenced vertices (CGAL's orientation code requires none), keeping the order.
  std::vector<std::uint32_t> remap(soup.points.size(), UINT32_MAX);
  std::uint32_t referenced = 0;
  {
    std::vector<std::atomic<char>> used(soup.points.size());  // value-initialised: all 0
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces.size(), 8192), [&](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
        for (std::uint32_t v : faces[i]) used[v].store(1, std::memory_order_relaxed);
    });
    for (std::size_t i = 0; i < soup.points.size(); ++i)
      if (used[i].load(std::memory_order_relaxed)) remap[i] = referenced++;
  }
  TriangleMesh& mesh = out.mesh;
  if (referenced == soup.points.size()) {
    mesh.vertices = std::move(soup.points);  // every vertex used (the usual case): the order is kept
  } else {
    for (std::size_t i = 0; i < soup.points.size(); ++i)
      if (remap[i] != UINT32_MAX) mesh.vertices.push_back(soup.points[i]);
    const std::size_t unreferenced = soup.points.size() - mesh.vertices.size();
    report.notices.push_back(std::to_string(unreferenced) + " unreferenced vertices were removed");
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces.size(), 8192), [&](const auto& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i)
        for (std::uint32_t& v : faces[i]) v = remap[v];
    });
  }

  // 3. Degenerate faces: a repeated corner or three collinear corners (exact predicate). On all
  // threads: the count and the first such face, whatever the split.
  using CountFirst = std::pair<std::size_t, std::size_t>;
  const auto [degenerate, first_degenerate] = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, faces.size(), 4096), CountFirst{0, SIZE_MAX},
      [&](const tbb::blocked_range<std::size_t>& r, CountFirst acc) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          const Face& f = faces[i];
          const bool repeated = f[0] == f[1] || f[1] == f[2] || f[0] == f[2];
          if (repeated || CGAL::collinear(to_point(mesh.vertices[f[0]]), to_point(mesh.vertices[f[1]]),
                                          to_point(mesh.vertices[f[2]]))) {
            ++acc.first;
            acc.second = std::min(acc.second, i);
          }
        }
        return acc;
      },
      [](CountFirst a, CountFirst b) { return CountFirst{a.first + b.first, std::min(a.second, b.second)}; });
  std::string degenerate_example;
  if (degenerate > 0) {
    const Face& f = faces[first_degenerate];
    degenerate_example = "face " + std::to_string(first_degenerate) + " with vertices " + std::to_string(f[0]) + " " +
                         pt(mesh.vertices[f[0]]) + ", " + std::to_string(f[1]) + " " + pt(mesh.vertices[f[1]]) + ", " +
                         std::to_string(f[2]) + " " + pt(mesh.vertices[f[2]]);
  }
  if (degenerate > 0)
    add_problem(report, "degenerate-face", degenerate,
                std::to_string(degenerate) + " degenerate (zero-area) faces, e.g. " + degenerate_example);
  mesh.faces = faces;

  // Step 8's self-intersection test, started here beside steps 4-7 when step 8 may run it: it
  // reads only the triangles (its own copy: step 7 may flip faces, which changes no intersecting
  // pair), and steps 4-7 hardly use a second thread on their own (armadillo, 52,000 faces: 0.04 s
  // on one and on two; doc/mesh-intake.md). Its result is used only where step 8 would have run
  // the test, and waited for on every way out (an exception it throws is rethrown at its use).
  struct EarlySelfIntersections {
    TriangleMesh triangles;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    double seconds = 0.0;
    std::exception_ptr error;
  } early;
  tbb::task_group early_group;
  struct Join {
    tbb::task_group& group;
    ~Join() { group.wait(); }  // the task catches its own exceptions
  } join{early_group};
  const bool early_started = options.check_self_intersections && degenerate == 0 && failed == 0 && !faces.empty();
  if (early_started) {
    // The vertices copied here: `out` may be returned (moved) before the task has finished.
    early.triangles.vertices = mesh.vertices;
    early_group.run([&early, &faces] {
      try {
        Timer timer;
        early.triangles.faces = faces;  // step 7 flips mesh.faces, never these
        early.pairs = self_intersecting_faces(early.triangles);
        early.seconds = timer.seconds();
      } catch (...) {
        early.error = std::current_exception();
      }
    });
  }

  // 4. Edges: boundary (1 face), non-manifold (> 2 faces), orientation consistency (2 faces).
  // Sorted by (lo, hi, face, forward): bucketed by lo (a counting sort, linear), then each bucket,
  // a vertex's few edges, sorted (a comparison sort of 2.5 million edges took 0.6 s at 832K faces).
  std::vector<HalfEdge, LargePageAllocator<HalfEdge>> edges;  // first touched on every thread when large
  std::vector<std::uint32_t> start(mesh.vertices.size() + 1, 0);  // vertex v's edges (lo = v) from start[v]
  {
    // On all threads: each bucket's count, then each edge placed at its bucket's next free slot (an
    // order within the bucket that varies from run to run, fixed by the bucket's sort below).
    const auto for_each_edge = [&](const auto& emit) {
      tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(faces.size()), 8192),
                        [&](const auto& r) {
                          for (std::uint32_t i = r.begin(); i != r.end(); ++i)
                            for (int k = 0; k < 3; ++k) {
                              const std::uint32_t a = faces[i][k], b = faces[i][(k + 1) % 3];
                              if (a != b) emit(HalfEdge{std::min(a, b), std::max(a, b), i, a < b});
                            }
                        });
    };
    {
      std::vector<std::atomic<std::uint32_t>> count(mesh.vertices.size());  // value-initialised: all 0
      for_each_edge([&](const HalfEdge& e) { count[e.lo].fetch_add(1, std::memory_order_relaxed); });
      for (std::size_t v = 0; v < mesh.vertices.size(); ++v)
        start[v + 1] = start[v] + count[v].load(std::memory_order_relaxed);
    }
    edges.resize(start.back());
    std::vector<std::atomic<std::uint32_t>> next(mesh.vertices.size());
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) next[v].store(start[v], std::memory_order_relaxed);
    for_each_edge([&](const HalfEdge& e) { edges[next[e.lo].fetch_add(1, std::memory_order_relaxed)] = e; });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.vertices.size(), 2048), [&](const auto& r) {
      for (std::size_t v = r.begin(); v != r.end(); ++v) std::sort(edges.begin() + start[v], edges.begin() + start[v + 1]);
    });
  }
  // The edges of fixed blocks of vertices (by lo) on all threads, each block's results merged in
  // block order: the counts, the first examples and the adjacency list are those of a serial scan,
  // and the union-finds' sets and roots do not depend on the order of unions.
  UnionFind components(faces.size());
  UnionFind corners(3 * faces.size());  // one entry per (face, corner); united across manifold edges
  auto corner_of = [&](std::uint32_t face, std::uint32_t vertex) {
    for (int k = 0; k < 3; ++k)
      if (faces[face][k] == vertex) return 3 * static_cast<std::size_t>(face) + k;
    return 3 * static_cast<std::size_t>(face);
  };
  struct EdgeBlock {
    std::size_t boundary = 0, nonmanifold = 0;
    std::size_t first_boundary = SIZE_MAX, first_nonmanifold = SIZE_MAX, nonmanifold_faces = 0;  // edge indices
    std::vector<Adjacent> adjacency;
  };
  constexpr std::size_t kBlock = 8192;
  std::vector<EdgeBlock> blocks((mesh.vertices.size() + kBlock - 1) / kBlock);
  tbb::parallel_for(std::size_t{0}, blocks.size(), [&](std::size_t b) {
    EdgeBlock& out = blocks[b];
    const std::size_t end = start[std::min(mesh.vertices.size(), (b + 1) * kBlock)];
    for (std::size_t i = start[b * kBlock]; i < end;) {
      std::size_t j = i;
      while (j < end && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
      const std::size_t n = j - i;
      for (std::size_t k = i + 1; k < j; ++k) components.unite_concurrent(edges[i].face, edges[k].face);
      if (n == 1) {
        if (out.boundary++ == 0) out.first_boundary = i;
      } else if (n > 2) {
        if (out.nonmanifold++ == 0) {
          out.first_nonmanifold = i;
          out.nonmanifold_faces = n;
        }
      } else {
        const HalfEdge &e = edges[i], &f = edges[i + 1];
        out.adjacency.push_back({e.lo, e.hi, e.face, f.face, e.forward == f.forward});
        corners.unite_concurrent(corner_of(e.face, e.lo), corner_of(f.face, e.lo));
        corners.unite_concurrent(corner_of(e.face, e.hi), corner_of(f.face, e.hi));
      }
      i = j;
    }
  });
  std::size_t boundary = 0, nonmanifold = 0;
  std::string boundary_example, nonmanifold_example;
  std::vector<Adjacent> adjacency;
  // Described only for the first example (formatting every edge cost seconds on 832K faces).
  const auto where = [&](std::size_t i) {
    return "edge (" + std::to_string(edges[i].lo) + ", " + std::to_string(edges[i].hi) + ") from " +
           pt(mesh.vertices[edges[i].lo]) + " to " + pt(mesh.vertices[edges[i].hi]);
  };
  std::vector<std::size_t> offset(blocks.size() + 1, 0);
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const EdgeBlock& b = blocks[k];
    if (boundary == 0 && b.boundary > 0)
      boundary_example = where(b.first_boundary) + " of face " + std::to_string(edges[b.first_boundary].face);
    if (nonmanifold == 0 && b.nonmanifold > 0)
      nonmanifold_example = where(b.first_nonmanifold) + ", shared by " + std::to_string(b.nonmanifold_faces) + " faces";
    boundary += b.boundary;
    nonmanifold += b.nonmanifold;
    offset[k + 1] = offset[k] + b.adjacency.size();
  }
  adjacency.resize(offset.back());
  tbb::parallel_for(std::size_t{0}, blocks.size(), [&](std::size_t k) {
    std::copy(blocks[k].adjacency.begin(), blocks[k].adjacency.end(), adjacency.begin() + static_cast<std::ptrdiff_t>(offset[k]));
    std::vector<Adjacent>().swap(blocks[k].adjacency);
  });
  report.closed = boundary == 0;
  if (boundary > 0)
    add_problem(report, "boundary", boundary,
                std::to_string(boundary) + " boundary edges (the surface is not closed), e.g. " + boundary_example);
  if (nonmanifold > 0)
    add_problem(report, "non-manifold-edge", nonmanifold,
                std::to_string(nonmanifold) + " non-manifold edges, e.g. " + nonmanifold_example);

  // 5. Non-manifold vertices: the faces around a vertex must form a single fan.
  {
    // Corners are united only around one vertex, so each root corner is one fan of its vertex:
    // a vertex is pinched when it is the vertex of more than one root (counted on all threads).
    std::vector<std::atomic<std::uint32_t>> fans(mesh.vertices.size());  // value-initialised: all 0
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, 3 * faces.size(), 8192), [&](const auto& r) {
      for (std::size_t c = r.begin(); c != r.end(); ++c)
        if (corners.find_concurrent(c) == c) fans[faces[c / 3][c % 3]].fetch_add(1, std::memory_order_relaxed);
    });
    std::size_t count = 0, v = SIZE_MAX;
    for (std::size_t u = 0; u < mesh.vertices.size(); ++u)
      if (fans[u].load(std::memory_order_relaxed) > 1 && count++ == 0) v = u;
    if (count > 0) {
      add_problem(report, "non-manifold-vertex", count,
                  std::to_string(count) + " non-manifold vertices (faces around them form several fans), e.g. vertex " +
                      std::to_string(v) + " " + pt(mesh.vertices[v]));
    }
  }

  // 6. Components (a root is its set's smallest face).
  std::vector<std::uint32_t> component_of(faces.size());
  {
    report.components = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, faces.size(), 8192), std::size_t{0},
        [&](const tbb::blocked_range<std::size_t>& r, std::size_t roots) {
          for (std::size_t f = r.begin(); f != r.end(); ++f) {
            component_of[f] = static_cast<std::uint32_t>(components.find_concurrent(f));
            roots += component_of[f] == f;
          }
          return roots;
        },
        std::plus<>());
    if (report.components > 1)
      report.notices.push_back("the mesh has " + std::to_string(report.components) + " connected components");
  }

  const bool manifold = !report.has("non-manifold-edge") && !report.has("non-manifold-vertex") &&
                        !report.has("untriangulable-polygon");
  // 7. Orientability: make the two faces at every edge run it in opposite directions (flip by BFS).
  // Nothing to do when they all do already (the usual case): no flip is then consistent. (The
  // search's random reads were a third of validation's serial time on 832K faces.)
  const bool consistent = std::none_of(adjacency.begin(), adjacency.end(),
                                       [](const Adjacent& a) { return a.same_direction; });
  if (manifold && !faces.empty() && !consistent) {
    // Neighbours in one array (at most three per face here: every edge is manifold), in the order
    // of `adjacency`, as separate lists per face had them.
    std::vector<std::uint32_t> first(faces.size() + 1, 0);
    for (const Adjacent& a : adjacency) ++first[a.f1 + 1], ++first[a.f2 + 1];
    for (std::size_t f = 0; f < faces.size(); ++f) first[f + 1] += first[f];
    std::vector<std::pair<std::uint32_t, bool>> neighbour(first.back());
    {
      std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
      for (const Adjacent& a : adjacency) {
        neighbour[fill[a.f1]++] = {a.f2, a.same_direction};
        neighbour[fill[a.f2]++] = {a.f1, a.same_direction};
      }
    }
    std::vector<signed char> flip(faces.size(), -1);
    std::size_t flipped = 0;
    bool orientable = true;
    std::uint32_t bad_face = 0;
    for (std::uint32_t seed = 0; seed < faces.size() && orientable; ++seed) {
      if (flip[seed] >= 0) continue;
      flip[seed] = 0;
      std::vector<std::uint32_t> queue{seed};
      while (!queue.empty() && orientable) {
        const std::uint32_t f = queue.back();
        queue.pop_back();
        for (std::uint32_t j = first[f]; j < first[f + 1]; ++j) {
          const auto [g, same] = neighbour[j];
          const signed char want = static_cast<signed char>(flip[f] ^ (same ? 1 : 0));
          if (flip[g] < 0) {
            flip[g] = want;
            flipped += want;
            queue.push_back(g);
          } else if (flip[g] != want) {
            orientable = false;
            bad_face = g;
            break;
          }
        }
      }
    }
    if (!orientable) {
      add_problem(report, "non-orientable", 1,
                  "the surface is not orientable (a Moebius-like loop of faces), e.g. around face " +
                      std::to_string(bad_face));
    } else if (flipped > 0) {
      for (std::size_t f = 0; f < faces.size(); ++f)
        if (flip[f] == 1) std::swap(mesh.faces[f][1], mesh.faces[f][2]);
      report.notices.push_back(std::to_string(flipped) + " faces were flipped to make the orientation consistent");
    }
  }

  // 8. Self-intersections (exact; mesh/self_intersections.h) and outward orientation.
  const bool polygon_mesh = manifold && !report.has("non-orientable") && !mesh.faces.empty();
  if (!polygon_mesh) {
    report.notices.push_back("self-intersections were not checked: the faces do not form a manifold surface");
    return out;
  }
  for (const Face& f : mesh.faces)
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) {
      report.notices.push_back("self-intersections were not checked: faces with repeated corners");
      return out;
    }
  if (options.check_self_intersections && !report.has("degenerate-face")) {
    if (!early_started) throw std::logic_error("validate_mesh: the self-intersection test was not started");
    early_group.wait();
    if (early.error) std::rethrow_exception(early.error);
    const std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs = std::move(early.pairs);
    report.seconds_self_intersections = early.seconds;
    report.self_intersections_checked = true;
    if (!pairs.empty()) {
      std::vector<std::pair<std::size_t, std::size_t>> ids(pairs.begin(), pairs.end());  // sorted
      const auto [a, b] = ids.front();
      add_problem(report, "self-intersection", ids.size(),
                  std::to_string(ids.size()) + " pairs of faces intersect (exact test), e.g. faces " + std::to_string(a) +
                      " and " + std::to_string(b) + " with first vertices " + pt(mesh.vertices[mesh.faces[a][0]]) +
                      " and " + pt(mesh.vertices[mesh.faces[b][0]]));
      report.intersecting_faces = std::move(ids);
    }
  } else if (report.has("degenerate-face")) {
    report.notices.push_back("self-intersections were not checked: the mesh has degenerate faces");
  }

  if (!report.closed || !report.valid()) return out;

  // Outward orientation of every component. One shell (the usual case): outward exactly when its
  // signed volume is positive (a closed, consistently oriented surface without self-intersections
  // bounds its interior with the volume's sign), decided by the rigorous enclosure; otherwise
  // (nested shells, or an enclosure that straddles 0) CGAL's orient_to_bound_a_volume.
  CGAL::Interval_nt<false> volume = signed_volume(mesh);
  if (options.fix_orientation) {
    std::size_t reversed = 0;
    if (report.components == 1 && (volume.inf() > 0.0 || volume.sup() < 0.0)) {
      if (volume.sup() < 0.0) {
        for (Face& f : mesh.faces) std::swap(f[1], f[2]);
        reversed = mesh.faces.size();
        volume = -volume;
      }
    } else {
      // CGAL's surface mesh, made only here (several shells, or an enclosure that straddles 0).
      SurfaceMesh sm;
      if (!build_closed_surface_mesh(mesh, adjacency, sm) && !build_surface_mesh_by_faces(mesh, sm))
        throw std::logic_error("validate_mesh: a valid closed mesh CGAL cannot represent");
      PMP::orient_to_bound_a_volume(sm);
      for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
        const SurfaceMesh::Face_index fi(static_cast<SurfaceMesh::size_type>(i));
        std::uint32_t vs[3];
        int k = 0;
        for (auto v : CGAL::vertices_around_face(sm.halfedge(fi), sm)) vs[k++] = static_cast<std::uint32_t>(v);
        Face& f = mesh.faces[i];
        // Same cyclic order as ours, or the reverse?
        const int r = (vs[0] == f[0]) ? 0 : (vs[0] == f[1]) ? 1 : 2;
        if (vs[1] != f[(r + 1) % 3]) {
          std::swap(f[1], f[2]);
          ++reversed;
        }
      }
      if (reversed > 0) volume = signed_volume(mesh);
    }
    if (reversed > 0)
      report.notices.push_back("orientation: " + std::to_string(reversed) +
                               " faces were inward-oriented and have been reversed to face outwards");
  }

  // Genus from the Euler characteristic of each component: chi = V - E + F = 2 - 2g. One component
  // (the usual case): every vertex, edge and face is its own (no vertex is unreferenced, step 2).
  if (report.components == 1) {
    const long chi = static_cast<long>(mesh.vertices.size()) - static_cast<long>(edges.size() / 2) +
                     static_cast<long>(mesh.faces.size());
    report.genus = (2 - chi) / 2;
  } else {
    std::vector<long> v(faces.size(), 0), e(faces.size(), 0), f(faces.size(), 0);
    std::vector<std::uint32_t> vertex_component(mesh.vertices.size(), 0);
    for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
      const std::uint32_t c = component_of[i];
      ++f[c];
      for (std::uint32_t vid : mesh.faces[i]) vertex_component[vid] = c;
    }
    for (std::uint32_t c : vertex_component) ++v[c];
    // In a closed manifold every undirected edge appears exactly twice in `edges`.
    for (const HalfEdge& h : edges) ++e[component_of[h.face]];
    long genus = 0;
    for (std::size_t c = 0; c < faces.size(); ++c) {
      if (f[c] == 0) continue;
      const long chi = v[c] - e[c] / 2 + f[c];
      genus += (2 - chi) / 2;
    }
    report.genus = genus;
  }
  report.volume_lo = volume.inf();
  report.volume_hi = volume.sup();
  return out;
}

}  // namespace cdbench
