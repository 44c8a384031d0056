// An independent check of a pose set's certificates: nothing of cdbench's distance code is used.
// For sampled poses, the mover's surface is sampled densely (a grid of n x n barycentric points
// per triangle, spacing h at most the longest edge / n); each sample's signed distance to the
// fixed surface comes from CGAL's AABB tree (closest point) and Side_of_triangle_mesh (sign), in
// doubles. The sampled minimum m is (up to double rounding) an upper bound of the clearance c, and
// m - h a lower bound (s is 1-Lipschitz, every surface point is within h of a sample). A
// certificate [lo, hi] is confirmed when it meets [m - h - e, m + e], e = 1e-9 x diagonal for
// rounding. With --intervals VALIDATION.csv (written by `cdbench validate`), the intervals checked
// are that file's (matched by pose id) instead of the pose set's own: float or other uncertified
// sets, certified by validate.
//
// m is the minimum over every sample, found without evaluating every sample (by default; the
// literal evaluation of all of them is --exhaustive, and the two give the same m): s(x) >= s(v) -
// |x - v| (1-Lipschitz), so a ball about a group of the mover's vertices is bounded by its centre's
// value less its radius and a triangle by its corners' bounds less its edges; a triangle whose
// bound is not below the smallest sample value found so far cannot hold the minimum. Signs come
// without a side query where a segment cannot meet F: if d(p) + d(q) > |p - q| the balls free of F
// about p and q cover the segment, so p and q are on the same side (a ball that misses F is on
// its centre's side; a sample takes a corner's side the same way).
// Usage: check_poses POSESET_DIR [--poses K] [--grid n] [--intervals CSV] [--exhaustive] [--verbose]
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <optional>
#include <tuple>
#include <utility>
#include <sstream>
#include <string>
#include <vector>

#include "guarded_main.h"
#include "mesh/read_mesh.h"
#include "mesh/validate_mesh.h"
#include "poseset/pose_csv.h"
#include "poseset/poseset_manifest.h"
#include "tool_options.h"

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_face_graph_triangle_primitive<Mesh>>>;
using Side = CGAL::Side_of_triangle_mesh<Mesh, K, CGAL::Default, Tree>;  // on our tree, not a second one

cdbench::TriangleMesh load(const std::string& path) {
  return cdbench::validate_mesh(cdbench::read_polygon_soup(path)).mesh;
}

Mesh to_cgal(const cdbench::TriangleMesh& m) {
  Mesh out;
  std::vector<Mesh::Vertex_index> v;
  for (const auto& p : m.vertices) v.push_back(out.add_vertex(Point(p.x(), p.y(), p.z())));
  for (const auto& f : m.faces) out.add_face(v[f[0]], v[f[1]], v[f[2]]);
  return out;
}

double dist(const Point& a, const Point& b) { return std::sqrt(CGAL::squared_distance(a, b)); }

void lower(std::atomic<double>& a, double v) {
  for (double c = a.load(std::memory_order_relaxed); v < c && !a.compare_exchange_weak(c, v);) {
  }
}

// The sampled minimum of one pose: m, the spacing h, and what it took.
struct Sampled {
  double m = HUGE_VAL, h = 0.0;
  std::size_t triangles = 0;   // triangles whose grid was evaluated
  std::uint64_t sides = 0;     // side queries
};

// The mover's vertices in groups of about 128 that are near each other (sorted along a Morton
// curve of their rest positions), each group with a ball about its centre holding it, one face at
// each vertex, made once per mover: per pose a ball's centre costs one distance query and bounds
// the signed distance on its whole ball, so far groups are set aside without a query per vertex.
struct MoverChunks {
  std::vector<std::uint32_t> members;     // vertex indices, group by group
  std::vector<std::size_t> first;         // group j: members[first[j] .. first[j + 1])
  std::vector<std::uint32_t> chunk_of;    // each vertex's group
  std::vector<Eigen::Vector3d> centre;    // in the mover's frame
  std::vector<double> radius;
  std::vector<std::size_t> face_of;       // a face at each vertex (SIZE_MAX: none)

  explicit MoverChunks(const cdbench::TriangleMesh& mover, std::size_t size = 128) {
    const std::size_t V = mover.vertices.size();
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(HUGE_VAL), hi = -lo;
    for (const auto& v : mover.vertices) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
    const Eigen::Vector3d extent = (hi - lo).cwiseMax(Eigen::Vector3d::Constant(1e-300));
    const auto spread = [](std::uint64_t x) {  // 21 bits to every third of 63
      x &= 0x1fffff;
      x = (x | x << 32) & 0x1f00000000ffffULL;
      x = (x | x << 16) & 0x1f0000ff0000ffULL;
      x = (x | x << 8) & 0x100f00f00f00f00fULL;
      x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
      x = (x | x << 2) & 0x1249249249249249ULL;
      return x;
    };
    std::vector<std::uint64_t> code(V);
    for (std::size_t v = 0; v < V; ++v) {
      const Eigen::Vector3d u = ((mover.vertices[v] - lo).array() / extent.array() * 2097151.0).matrix();
      code[v] = spread(std::uint64_t(u.x())) | spread(std::uint64_t(u.y())) << 1 | spread(std::uint64_t(u.z())) << 2;
    }
    members.resize(V);
    std::iota(members.begin(), members.end(), 0u);
    std::sort(members.begin(), members.end(),
              [&](std::uint32_t a, std::uint32_t b) { return code[a] < code[b] || (code[a] == code[b] && a < b); });
    chunk_of.resize(V);
    for (std::size_t begin = 0; begin < V; begin += size) {
      const std::size_t end = std::min(V, begin + size);
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (std::size_t m = begin; m < end; ++m) c += mover.vertices[members[m]];
      c /= double(end - begin);
      double r = 0.0;
      for (std::size_t m = begin; m < end; ++m) {
        r = std::max(r, (mover.vertices[members[m]] - c).norm());
        chunk_of[members[m]] = static_cast<std::uint32_t>(centre.size());
      }
      first.push_back(begin);
      centre.push_back(c);
      radius.push_back(r * (1.0 + 1e-12));
    }
    first.push_back(V);
    face_of.assign(V, SIZE_MAX);
    for (std::size_t i = 0; i < mover.faces.size(); ++i)
      for (const std::uint32_t v : mover.faces[i]) face_of[v] = i;
  }
};

class Sampler {
 public:
  Sampler(const Tree& tree, const Side& side, int n, double e) : tree_(tree), side_(side), n_(n), e_(e) {}

  // Every sample of every triangle, each with its own side query: the reference.
  Sampled exhaustive(const std::vector<Point>& P, const std::vector<cdbench::Face>& faces) const {
    Sampled r;
    r.h = spacing(P, faces);
    std::atomic<double> best{HUGE_VAL};
    std::atomic<std::uint64_t> sides{0};
    tbb::parallel_for(std::size_t{0}, faces.size(), [&](std::size_t t) {
      const auto& f = faces[t];
      const double m =
          grid_minimum(P[f[0]], P[f[1]], P[f[2]], std::nullopt, [&](const Point& x, double) { return side(x, sides); });
      lower(best, m);
    });
    r.m = best;
    r.triangles = faces.size();
    r.sides = sides;
    return r;
  }

  // The same minimum, evaluating only the triangles that may hold it (see the file's comment).
  // `chunks` groups the mover's vertices in balls; `Rot`, `t` are the pose.
  Sampled pruned(const std::vector<Point>& P, const std::vector<cdbench::Face>& faces, const MoverChunks& chunks,
                 const Eigen::Matrix3d& Rot, const Eigen::Vector3d& t) const {
    Sampled r;
    r.h = spacing(P, faces);
    std::atomic<std::uint64_t> sides{0};
    const auto sign_at = [&](const Point& x) { return side(x, sides); };
    // Each chunk's ball: s >= s(centre) - radius on all of it, and one side if it misses F.
    const std::size_t C = chunks.radius.size();
    if (C == 0) return r;
    std::vector<double> centre_s(C), centre_d(C);
    tbb::parallel_for(std::size_t{0}, C, [&](std::size_t j) {
      const Eigen::Vector3d c = Rot * chunks.centre[j] + t;
      const Point x(c.x(), c.y(), c.z());
      centre_d[j] = std::sqrt(tree_.squared_distance(x));
      centre_s[j] = centre_d[j] > 0.0 ? sign_at(x) * centre_d[j] : 0.0;
    });
    const auto free_ball = [&](std::size_t j) { return centre_d[j] > chunks.radius[j] + e_; };
    // A vertex's signed distance and sign, computed when a triangle needs them.
    const std::size_t V = P.size();
    std::vector<double> d(V), sign(V);
    std::vector<std::atomic<char>> state(V);  // 0: not known, 1: being written, 2: known
    const auto vertex = [&](std::uint32_t v) -> std::pair<double, double> {
      if (state[v].load(std::memory_order_acquire) == 2) return {d[v], sign[v]};
      const std::size_t j = chunks.chunk_of[v];
      const double dv = std::sqrt(tree_.squared_distance(P[v]));
      const double sv = dv == 0.0 ? 0.0 : free_ball(j) ? (centre_s[j] < 0 ? -1.0 : 1.0) : sign_at(P[v]);
      char unknown = 0;  // the first thread to finish publishes it; the others use their own copy
      if (state[v].compare_exchange_strong(unknown, 1, std::memory_order_acq_rel)) {
        d[v] = dv;
        sign[v] = sv;
        state[v].store(2, std::memory_order_release);
      }
      return {dv, sv};
    };
    const auto corner_bound = [&](const cdbench::Face& f, int k, double value) {
      const std::uint32_t a = f[k], p = f[(k + 1) % 3], q = f[(k + 2) % 3];
      return value - std::max(dist(P[a], P[p]), dist(P[a], P[q]));
    };
    // The triangles' bounds from their chunks, less e for the samples' and centres' rounding.
    std::vector<double> bound(faces.size());
    tbb::parallel_for(std::size_t{0}, faces.size(), [&](std::size_t i) {
      const auto& f = faces[i];
      double lb = -HUGE_VAL;
      for (int k = 0; k < 3; ++k) {
        const std::size_t j = chunks.chunk_of[f[k]];
        lb = std::max(lb, corner_bound(f, k, centre_s[j] - chunks.radius[j]));
      }
      bound[i] = lb - 2.0 * e_;
    });
    std::atomic<double> best{HUGE_VAL};
    std::atomic<std::size_t> evaluated{0};
    // A triangle: its corners' exact values bound it again; sampled if still below the best.
    const auto evaluate = [&](std::size_t i) {
      const auto& f = faces[i];
      double lb = -HUGE_VAL, cd[3], cs[3];
      for (int k = 0; k < 3; ++k) {
        std::tie(cd[k], cs[k]) = vertex(f[k]);
        lb = std::max(lb, corner_bound(f, k, cs[k] * cd[k]));
      }
      if (lb - e_ >= best.load(std::memory_order_relaxed)) return;
      const double m = grid_minimum(P[f[0]], P[f[1]], P[f[2]], best.load(std::memory_order_relaxed),
                                    [&](const Point& x, double dx) {
                                      for (int k = 0; k < 3; ++k)
                                        if (cs[k] != 0.0 && dx + cd[k] > dist(x, P[f[k]]) + e_) return cs[k];
                                      return sign_at(x);
                                    });
      lower(best, m);
      ++evaluated;
    };
    // A real sample value to prune with first: a triangle at the lowest vertex of the lowest chunk.
    const std::size_t low_chunk = static_cast<std::size_t>(
        std::min_element(centre_s.begin(), centre_s.end()) - centre_s.begin());
    std::size_t start = SIZE_MAX;
    double low = HUGE_VAL;
    for (std::size_t m = chunks.first[low_chunk]; m < chunks.first[low_chunk + 1]; ++m) {
      const std::uint32_t v = chunks.members[m];
      const auto [dv, sv] = vertex(v);
      if (chunks.face_of[v] != SIZE_MAX && sv * dv < low) {
        low = sv * dv;
        start = chunks.face_of[v];
      }
    }
    if (start != SIZE_MAX) evaluate(start);
    // Then the others in ascending bound, while their bound is below the smallest value found.
    std::vector<std::uint32_t> order;
    for (std::size_t i = 0; i < faces.size(); ++i)
      if (i != start && bound[i] < best.load()) order.push_back(static_cast<std::uint32_t>(i));
    std::sort(order.begin(), order.end(), [&](std::uint32_t x, std::uint32_t y) {
      return bound[x] < bound[y] || (bound[x] == bound[y] && x < y);
    });
    tbb::parallel_for(std::size_t{0}, order.size(), [&](std::size_t k) {
      if (bound[order[k]] < best.load(std::memory_order_relaxed)) evaluate(order[k]);
    });
    r.m = best;
    r.triangles = evaluated;
    r.sides = sides;
    return r;
  }

 private:
  // The sign of s at x by CGAL's side test, counted.
  double side(const Point& x, std::atomic<std::uint64_t>& count) const {
    ++count;
    return side_(x) == CGAL::ON_BOUNDED_SIDE ? -1.0 : 1.0;
  }

  // h: every point of the mover's surface is within h of a sample.
  double spacing(const std::vector<Point>& P, const std::vector<cdbench::Face>& faces) const {
    return tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, faces.size()), 0.0,
        [&](const tbb::blocked_range<std::size_t>& range, double h) {
          for (std::size_t t = range.begin(); t != range.end(); ++t) {
            const auto& f = faces[t];
            const double edge = std::max({dist(P[f[0]], P[f[1]]), dist(P[f[1]], P[f[2]]), dist(P[f[2]], P[f[0]])});
            h = std::max(h, edge / n_);
          }
          return h;
        },
        [](double a, double b) { return std::max(a, b); });
  }

  // The smallest signed distance over the triangle's grid samples. With `below`, a sample whose
  // value cannot be below it or below the triangle's smallest so far (-d >= that) is not signed;
  // without, every sample is. sign_of(x, d) gives the sign of s at x.
  template <class SignOf>
  double grid_minimum(const Point& a, const Point& b, const Point& c, std::optional<double> below,
                      const SignOf& sign_of) const {
    double best = HUGE_VAL;
    for (int i = 0; i <= n_; ++i)
      for (int j = 0; i + j <= n_; ++j) {
        const double u = double(i) / n_, v = double(j) / n_;
        const Point x(a.x() + u * (b.x() - a.x()) + v * (c.x() - a.x()), a.y() + u * (b.y() - a.y()) + v * (c.y() - a.y()),
                      a.z() + u * (b.z() - a.z()) + v * (c.z() - a.z()));
        const double d = std::sqrt(tree_.squared_distance(x));
        if (below && -d >= std::min(best, *below)) continue;
        best = std::min(best, sign_of(x, d) * d);
      }
    return best;
  }

  const Tree& tree_;
  const Side& side_;
  int n_;
  double e_;
};

}  // namespace

static int run(int argc, char** argv) {
  const char* usage =
      "usage: check_poses POSESET_DIR [--poses K] [--grid n] [--intervals VALIDATION.csv] [--exhaustive] [--verbose]\n"
      "  Confirms K certificates (default 30; as many from each level, spread over its approaches) by dense\n"
      "  sampling of the placed mover (n x n points per triangle, default 16) with CGAL's AABB tree and\n"
      "  side-of-mesh test. --intervals: check cdbench validate's intervals instead; --exhaustive: evaluate\n"
      "  every sample (slow; the same minimum); --verbose: a line per pose. Exit 0: all confirmed, 1: some\n"
      "  not, 2: bad input.\n";
  std::map<std::string, std::string> o;
  if (const auto exit = parse_tool_options("check_poses", usage, argc, argv, 2, {"--exhaustive", "--verbose"},
                                           {"--poses", "--grid", "--intervals"}, o))
    return *exit;
  const std::string dir = argv[1];
  const std::size_t wanted = o.count("--poses") ? std::stoul(o["--poses"]) : 30;
  const int n = o.count("--grid") ? std::stoi(o["--grid"]) : 16;
  const std::string intervals = o.count("--intervals") ? o["--intervals"] : "";
  const bool exhaustive = o.count("--exhaustive") > 0, verbose = o.count("--verbose") > 0;
  if (n < 1) {
    std::fprintf(stderr, "check_poses: --grid must be at least 1\n");
    return 2;
  }
  // The manifest reader names the file and key of any problem; a mesh the pose set was made
  // from is found and checked by its SHA-256 (locate_mesh), and read once when it is also the mover.
  const cdbench::PoseSetManifest manifest = cdbench::read_poseset_manifest(dir);
  const nlohmann::json& ps = manifest.json;
  const cdbench::TriangleMesh fixed = load(cdbench::locate_mesh(manifest.fixed, dir));
  const cdbench::TriangleMesh mover = manifest.mover_is_fixed ? fixed : load(cdbench::locate_mesh(manifest.mover, dir));
  const double diag = ps["certification"]["diagonal"].get<double>();
  const Mesh F = to_cgal(fixed);
  Tree tree(faces(F).first, faces(F).second, F);
  tree.accelerate_distance_queries();
  // Built now, before queries from several threads.
  tree.build();
  (void)tree.squared_distance(Point(0, 0, 0));
  const Side side(tree);
  std::ifstream csv(dir + "/poses.csv");
  std::vector<cdbench::PoseRow> rows = cdbench::read_pose_csv(csv, dir + "/poses.csv");
  if (!intervals.empty()) {
    // validation.csv: pose,level,target,clearance_lo,clearance_hi,...
    std::ifstream v(intervals);
    std::string line;
    if (!v || !std::getline(v, line) || line.rfind("pose,level,target,clearance_lo,clearance_hi", 0) != 0) {
      std::fprintf(stderr, "%s: not a validation.csv of cdbench validate\n", intervals.c_str());
      return 2;
    }
    std::map<std::uint64_t, std::pair<double, double>> by_pose;
    while (std::getline(v, line)) {
      std::stringstream ss(line);
      std::string f[5];
      for (auto& x : f) std::getline(ss, x, ',');
      by_pose[std::stoull(f[0])] = {std::stod(f[3]), std::stod(f[4])};
    }
    for (auto& r : rows) {
      const auto it = by_pose.find(r.pose);
      r.clearance_lo = it == by_pose.end() ? NAN : it->second.first;
      r.clearance_hi = it == by_pose.end() ? NAN : it->second.second;
    }
  }
  // The poses checked: as many from each level as can be (a level with fewer placed poses gives
  // all it has and the others share the rest), each level's spread over its approaches. A stride
  // over the whole file could land on one level only (the rows of an approach are its levels).
  std::map<int, std::vector<const cdbench::PoseRow*>> by_level;
  std::size_t total = 0;
  for (const auto& r : rows)
    if (!std::isnan(r.clearance_lo)) {
      by_level[r.level].push_back(&r);
      ++total;
    }
  const std::size_t M = std::min(wanted, total);
  std::map<int, std::size_t> quota;
  for (std::size_t given = 0; given < M;)
    for (const auto& [level, list] : by_level)
      if (given < M && quota[level] < list.size()) {
        ++quota[level];
        ++given;
      }
  std::vector<const cdbench::PoseRow*> placed;
  for (const auto& [level, list] : by_level)
    for (std::size_t i = 0; i < quota[level]; ++i) placed.push_back(list[i * list.size() / quota[level]]);
  std::sort(placed.begin(), placed.end(), [](const cdbench::PoseRow* a, const cdbench::PoseRow* b) { return a->pose < b->pose; });
  const double e = 1e-9 * diag;
  const Sampler sampler(tree, side, n, e);
  const MoverChunks chunks(mover);
  std::size_t confirmed = 0;
  for (std::size_t k = 0; k < M; ++k) {
    const cdbench::PoseRow& r = *placed[k];
    std::vector<Point> P;
    for (const auto& x : mover.vertices) {
      const Eigen::Vector3d y = r.R * x + r.t;
      P.emplace_back(y.x(), y.y(), y.z());
    }
    const Sampled sampled =
        exhaustive ? sampler.exhaustive(P, mover.faces) : sampler.pruned(P, mover.faces, chunks, r.R, r.t);
    const double best = sampled.m, h = sampled.h;
    const double lo = best - h - e, hi = best + e;
    const bool ok = r.clearance_lo <= hi && r.clearance_hi >= lo;
    confirmed += ok;
    if (verbose)
      std::printf("pose %llu level %d: certificate [%.17g, %.17g], sampled minimum %.17g, spacing %.17g (%zu of %zu "
                  "triangles sampled, %llu side queries)\n",
                  static_cast<unsigned long long>(r.pose), r.level, r.clearance_lo, r.clearance_hi, best, h,
                  sampled.triangles, mover.faces.size(), static_cast<unsigned long long>(sampled.sides));
    if (!ok)
      std::printf("NOT CONFIRMED pose %llu level %d: certificate [%.17g, %.17g], sampled enclosure [%.17g, %.17g]\n",
                  static_cast<unsigned long long>(r.pose), r.level, r.clearance_lo, r.clearance_hi, lo, hi);
  }
  std::printf("%s: %zu of %zu sampled certificates confirmed by dense sampling with CGAL (grid %d per triangle)\n",
              dir.c_str(), confirmed, M, n);
  return confirmed == M ? 0 : 1;
}

int main(int argc, char** argv) { return guarded_main("check_poses", run, argc, argv); }
