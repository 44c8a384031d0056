// An independent check of a pose set's certificates: nothing of cdbench's distance code is used.
// For sampled poses, the mover's surface is sampled densely (a grid of n x n barycentric points
// per triangle, spacing h at most the longest edge / n); each sample's signed distance to the
// fixed surface comes from CGAL's AABB tree (closest point) and Side_of_triangle_mesh (sign), in
// doubles. The sampled minimum m is (up to double rounding) an upper bound of the clearance c, and
// m - h a lower bound (s is 1-Lipschitz, every surface point is within h of a sample). A
// certificate [lo, hi] is confirmed when it meets [m - h - e, m + e], e = 1e-9 x diagonal for
// rounding. With --intervals VALIDATION.csv (written by `cdbench validate`), the intervals checked
// are that file's (matched by pose id) instead of the pose set's own: float or other uncertified
// sets, certified by validate. Usage: check_poses POSESET_DIR [--poses K] [--grid n] [--intervals CSV]
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/read_mesh.h"
#include "mesh/validate_mesh.h"
#include "poseset/poseset_manifest.h"
#include "poseset/pose_csv.h"
#include "guarded_main.h"

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_face_graph_triangle_primitive<Mesh>>>;

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

}  // namespace

static int run(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: check_poses POSESET_DIR [--poses K] [--grid n] [--intervals VALIDATION.csv]\n");
    return 2;
  }
  const std::string dir = argv[1];
  std::size_t wanted = 30;
  int n = 16;
  std::string intervals;
  for (int i = 2; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--intervals") == 0) intervals = argv[i + 1];
    if (std::strcmp(argv[i], "--poses") == 0) wanted = std::stoul(argv[i + 1]);
    if (std::strcmp(argv[i], "--grid") == 0) n = std::stoi(argv[i + 1]);
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
  const CGAL::Side_of_triangle_mesh<Mesh, K> side(F);
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
  std::vector<const cdbench::PoseRow*> placed;
  for (const auto& r : rows)
    if (!std::isnan(r.clearance_lo)) placed.push_back(&r);
  const std::size_t M = std::min(wanted, placed.size());
  const double e = 1e-9 * diag;
  std::size_t confirmed = 0;
  double worst_gap = 0.0;
  for (std::size_t k = 0; k < M; ++k) {
    const cdbench::PoseRow& r = *placed[k * placed.size() / M];  // spread over the set
    std::vector<Point> P;
    for (const auto& x : mover.vertices) {
      const Eigen::Vector3d y = r.R * x + r.t;
      P.emplace_back(y.x(), y.y(), y.z());
    }
    double best = HUGE_VAL, h = 0.0;
    for (const auto& f : mover.faces) {
      const Point &a = P[f[0]], &b = P[f[1]], &c = P[f[2]];
      const double edge = std::sqrt(std::max({CGAL::squared_distance(a, b), CGAL::squared_distance(b, c),
                                              CGAL::squared_distance(c, a)}));
      h = std::max(h, edge / n);
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
          const double u = double(i) / n, v = double(j) / n;
          const Point x(a.x() + u * (b.x() - a.x()) + v * (c.x() - a.x()), a.y() + u * (b.y() - a.y()) + v * (c.y() - a.y()),
                        a.z() + u * (b.z() - a.z()) + v * (c.z() - a.z()));
          const double d = std::sqrt(tree.squared_distance(x));
          const double s = side(x) == CGAL::ON_BOUNDED_SIDE ? -d : d;
          best = std::min(best, s);
        }
    }
    const double lo = best - h - e, hi = best + e;
    const bool ok = r.clearance_lo <= hi && r.clearance_hi >= lo;
    confirmed += ok;
    worst_gap = std::max(worst_gap, std::max(r.clearance_lo - hi, lo - r.clearance_hi));
    if (!ok)
      std::printf("NOT CONFIRMED pose %llu level %d: certificate [%.17g, %.17g], sampled enclosure [%.17g, %.17g]\n",
                  static_cast<unsigned long long>(r.pose), r.level, r.clearance_lo, r.clearance_hi, lo, hi);
  }
  std::printf("%s: %zu of %zu sampled certificates confirmed by dense sampling with CGAL (grid %d per triangle)\n",
              dir.c_str(), confirmed, M, n);
  return confirmed == M ? 0 : 1;
}

int main(int argc, char** argv) { return guarded_main("check_poses", run, argc, argv); }
