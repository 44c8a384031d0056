// Certified signed distance and maximum penetration, timed against CGAL's uncertified signed distance
// (AABB_tree closest point + Side_of_triangle_mesh) on the same query points in the same run.
//
// Usage: bench_distance [--queries N] MESH...   (prints a Markdown table on stdout)
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <tbb/global_control.h>

#include <cstdio>
#include <iostream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "distance/max_penetration.h"
#include "distance/signed_distance.h"
#include "mesh/read_mesh.h"
#include "mesh/validate_mesh.h"
#include "util/timer.h"
#include "guarded_main.h"

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using SM = CGAL::Surface_mesh<K::Point_3>;
using Tri = K::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<K, std::vector<Tri>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

}  // namespace

static int run(int argc, char** argv) {
  using namespace cdbench;
  std::size_t queries = 20000;
  std::vector<std::string> meshes;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--queries" && i + 1 < argc) queries = std::stoul(argv[++i]);
    else meshes.push_back(a);
  }
  if (meshes.empty()) {
    std::cerr << "usage: bench_distance [--queries N] MESH...\n";
    return 2;
  }
  std::printf("| mesh | faces | ours: certified sd, us/query | CGAL: sd (uncertified), us/query | ratio ours/CGAL | "
              "mean width / diag | max penetration %% diag | width / diag | cells | time 1 thread s | time 2 threads s |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& path : meshes) {
    const ValidatedMesh v = validate_mesh(read_polygon_soup(path));
    if (!v.report.valid()) {
      std::fprintf(stderr, "%s: not a valid solid, skipped\n", path.c_str());
      continue;
    }
    const TriangleMesh& m = v.mesh;
    const Aabb box = m.bbox();
    const double diag = box.diagonal();
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Vec3> pts(queries);
    for (Vec3& p : pts) p = box.lo + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(box.extent());

    // Queries are timed on one thread (a global_control limits TBB while it lives; the most
    // restrictive live one wins, so each is scoped).
    auto one = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, 1);
    const SignedDistance sdf(m);
    double width = 0, checksum = 0;
    Timer t_ours;
    for (const Vec3& p : pts) {
      const Interval s = sdf.signed_distance(p);
      width += s.width();
      checksum += s.lo;
    }
    const double ours = t_ours.seconds();

    std::vector<Tri> tris;
    SM sm;
    for (const Vec3& p : m.vertices) sm.add_vertex(K::Point_3(p.x(), p.y(), p.z()));
    for (const Face& f : m.faces) {
      const auto P = [&](std::uint32_t i) { return K::Point_3(m.vertices[i].x(), m.vertices[i].y(), m.vertices[i].z()); };
      tris.emplace_back(P(f[0]), P(f[1]), P(f[2]));
      sm.add_face(SM::Vertex_index(f[0]), SM::Vertex_index(f[1]), SM::Vertex_index(f[2]));
    }
    Tree tree(tris.begin(), tris.end());
    tree.accelerate_distance_queries();
    CGAL::Side_of_triangle_mesh<SM, K> side(sm);
    double cgal_checksum = 0;
    Timer t_cgal;
    for (const Vec3& p : pts) {
      const K::Point_3 q(p.x(), p.y(), p.z());
      const double d = std::sqrt(tree.squared_distance(q));
      cgal_checksum += side(q) == CGAL::ON_BOUNDED_SIDE ? -d : d;
    }
    const double cgal = t_cgal.seconds();
    if (std::abs(checksum - cgal_checksum) > 1e-6 * diag * queries)
      std::fprintf(stderr, "%s: checksums differ: %.17g vs %.17g\n", path.c_str(), checksum, cgal_checksum);

    MaxPenetrationOptions mo;
    mo.progress = false;
    const MaxPenetrationResult r1 = certified_max_penetration(sdf, mo);
    one.reset();
    MaxPenetrationResult r2;
    {
      tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
      r2 = certified_max_penetration(sdf, mo);
    }
    if (r1.depth.lo != r2.depth.lo || r1.depth.hi != r2.depth.hi)
      std::fprintf(stderr, "%s: results differ between 1 and 2 threads\n", path.c_str());
    const std::string name = path.substr(path.find_last_of('/') + 1);
    std::printf("| %s | %zu | %.2f | %.2f | %.2f | %.1e | %.4f | %.1e | %llu | %.2f | %.2f |\n", name.c_str(),
                m.faces.size(), 1e6 * ours / queries, 1e6 * cgal / queries, ours / cgal, width / queries / diag,
                100 * r2.depth.lo / diag, r2.depth.width() / diag, static_cast<unsigned long long>(r2.cells),
                r1.seconds, r2.seconds);
    std::fflush(stdout);
  }
  return 0;
}

int main(int argc, char** argv) { return guarded_main("bench_distance", run, argc, argv); }
