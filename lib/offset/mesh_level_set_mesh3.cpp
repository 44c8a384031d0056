// The parallel candidate mesher: CGAL's Mesh_3 in parallel mode (TBB) on the implicit domain
// {f < 0}, seeded with our points (never Mesh_3's random initial rays), facets only (no cell
// criteria, no perturbation or exudation), manifold output. Only the boundary facets are kept.
#ifndef CGAL_LINKED_WITH_TBB
#define CGAL_LINKED_WITH_TBB
#endif
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_3/Dump_c3t3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/facets_in_complex_3_to_triangle_mesh.h>
#include <CGAL/make_mesh_3.h>
#include <tbb/enumerable_thread_specific.h>

#include "mesh/cgal_surface_mesh.h"
#include "offset/level_set_evaluator.h"
#include "offset/mesh_level_set.h"

namespace cdbench {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using BaseDomain = CGAL::Labeled_mesh_domain_3<K>;

// Mesh_3's own initial points are random rays from the sphere's centre, which loop without bound
// on an empty level and miss small components: the domain hands out our seeds instead (make_mesh_3
// asks the domain's static type for them).
class SeededDomain : public BaseDomain {
 public:
  SeededDomain(BaseDomain&& base, std::vector<Point> seeds) : BaseDomain(std::move(base)), seeds_(std::move(seeds)) {}
  struct Construct_initial_points {
    const SeededDomain* domain;
    template <class OutputIterator>
    OutputIterator operator()(OutputIterator out, int = 0) const {
      const Index index = domain->index_from_surface_patch_index(domain->make_surface_index(0, 1));
      for (const Point& p : domain->seeds_) *out++ = std::make_pair(p, index);
      return out;
    }
  };
  Construct_initial_points construct_initial_points_object() const { return Construct_initial_points{this}; }

 private:
  std::vector<Point> seeds_;
};

using Tr = CGAL::Mesh_triangulation_3<SeededDomain, CGAL::Default, CGAL::Parallel_tag>::type;
using C3t3 = CGAL::Mesh_complex_3_in_triangulation_3<Tr>;
using Criteria = CGAL::Mesh_criteria_3<Tr>;

}  // namespace
}  // namespace cdbench

// Mesh_3 writes its whole triangulation to dump-bug.* in the working directory before it raises
// some errors: a library must not leave files behind, and the error reaches the caller anyway.
template <>
struct CGAL::Dump_c3t3<cdbench::C3t3, true> {
  void dump_c3t3(const cdbench::C3t3&, const std::string&) const {}
};
template <>
struct CGAL::Dump_c3t3<cdbench::C3t3, false> {
  void dump_c3t3(const cdbench::C3t3&, const std::string&) const {}
};

namespace cdbench {

TriangleMesh mesh_level_set_parallel(const std::function<double(const Vec3&)>& f, const Vec3& center, double radius,
                                     const std::vector<Vec3>& seeds, const LevelSetMeshOptions& options,
                                     LevelSetMeshStats* stats) {
  // One evaluator (cache, recent values) per thread: a bisection runs on one thread, so the
  // Lipschitz signs still come from the same segment's ends.
  tbb::enumerable_thread_specific<detail::Evaluator> evaluators(f, options.lipschitz, 1e-9 * radius);
  const std::function<double(const Point&)> function = [&](const Point& p) {
    return evaluators.local()(Vec3(p.x(), p.y(), p.z()));
  };
  std::vector<Point> points;
  for (const Vec3& s : detail::distinct_seeds(seeds, options.distance_bound))
    points.emplace_back(s.x(), s.y(), s.z());
  namespace params = CGAL::parameters;
  SeededDomain domain(BaseDomain::create_implicit_mesh_domain(
                          function, K::Sphere_3(Point(center.x(), center.y(), center.z()), radius * radius),
                          params::relative_error_bound = options.bisection_relative_error),
                      std::move(points));
  const Criteria criteria(params::facet_angle = options.angle_bound, params::facet_size = options.radius_bound,
                          params::facet_distance = options.distance_bound);
  const C3t3 c3t3 =
      CGAL::make_mesh_3<C3t3>(domain, criteria, params::no_perturb(), params::no_exude(), params::manifold());
  CGAL::Surface_mesh<Point> sm;
  CGAL::facets_in_complex_3_to_triangle_mesh(c3t3, sm);
  if (stats != nullptr) {
    *stats = LevelSetMeshStats{};
    for (const detail::Evaluator& e : evaluators) {
      stats->calls += e.stats.calls;
      stats->evaluations += e.stats.evaluations;
      stats->lipschitz += e.stats.lipschitz;
    }
  }
  return triangle_mesh_from(sm);
}

}  // namespace cdbench
