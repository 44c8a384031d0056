// CGAL's alpha wrapping lives in this translation unit only.
#include "mesh/alpha_wrap.h"

#include <cmath>
#include <functional>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/alpha_wrap_3.h>

#include "mesh/cgal_surface_mesh.h"
#include "util/error.h"
#include "util/progress.h"
#include "util/number_format.h"
#include "util/timer.h"

namespace cdbench {
namespace {

// Shows the wrap's progress (CGAL's wrapper inserts one Steiner point per refinement step) and
// stops it once the Steiner points pass the face limit: every wrap measured had 1.5-1.8 output
// faces per Steiner point (doc/mesh-intake.md), so one that ends under the limit is not stopped.
// An InputError thrown from here unwinds out of alpha_wrap_3, whose triangulation is its local.
class WrapVisitor : public CGAL::Alpha_wraps_3::internal::Wrapping_default_visitor {
 public:
  WrapVisitor(std::size_t max_faces, double estimate, double relative_alpha)
      : progress_("alpha wrap, Steiner points", 0), max_faces_(max_faces), relative_alpha_(relative_alpha) {
    progress_.set_detail("(about " + number_text(estimate / 1.5, 2) + " estimated)");
  }
  template <typename Wrapper, typename Point>
  void before_Steiner_point_insertion(const Wrapper&, const Point&) {
    ++steiner_;
    progress_.advance();
    if (steiner_ <= max_faces_) return;
    throw InputError("alpha wrap: stopped after " + number_text(static_cast<double>(steiner_)) +
                     " Steiner points (1.5-1.8 output faces each where measured), more than the limit of " +
                     number_text(static_cast<double>(max_faces_)) +
                     " (--max-faces); alpha is too fine for this input: use a coarser --relative-alpha (now " +
                     number_text(relative_alpha_, 6) + ") or raise --max-faces");
  }

 private:
  Progress progress_;
  std::size_t max_faces_;
  double relative_alpha_;
  std::size_t steiner_ = 0;
};

double soup_area(const PolygonSoup& soup) {
  double area = 0.0;
  for (const auto& poly : soup.polygons)
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
      const Vec3& a = soup.points[poly[0]];
      area += 0.5 * (soup.points[poly[k]] - a).cross(soup.points[poly[k + 1]] - a).norm();
    }
  return area;
}

}  // namespace

double estimated_wrap_faces(double area, double alpha) { return 1.2 * area / (alpha * alpha); }

AlphaWrapResult alpha_wrap(const PolygonSoup& soup, const AlphaWrapOptions& options) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Point = Kernel::Point_3;
  Aabb box;
  for (const Vec3& p : soup.points) box.extend(p);
  const double diag = box.diagonal();
  if (!(diag > 0.0)) throw InputError("alpha wrap: the input has no extent (all points coincide)");
  AlphaWrapResult result;
  result.alpha = options.alpha > 0 ? options.alpha : diag / options.relative_alpha;
  result.offset = options.offset > 0 ? options.offset : diag / options.relative_offset;
  const auto finest = [&](const char* name, double value, double most, const char* relative) {
    if (diag / value <= most) return;
    throw InputError(std::string("alpha wrap: ") + name + " " + number_text(value, 6) + " is " +
                     number_text(diag / value, 3) + " times finer than the input's diagonal " + number_text(diag, 6) +
                     "; at most " + number_text(most) + " (" + relative + "): the wrap would be too fine to finish");
  };
  finest("--alpha", result.alpha, kMaxRelativeAlpha, "--relative-alpha's range");
  finest("--offset", result.offset, kMaxRelativeOffset, "--relative-offset's range");
  const double estimate = estimated_wrap_faces(soup_area(soup), result.alpha);
  const double limit = static_cast<double>(options.max_faces);
  // The estimate grows like 1 / alpha^2: the coarsest relative alpha that fits scales by sqrt.
  if (estimate > limit)
    throw InputError("alpha wrap: alpha " + number_text(result.alpha, 6) + " (the diagonal / " +
                     number_text(diag / result.alpha, 3) + ") would give about " + number_text(estimate, 2) +
                     " faces (estimated from the input's area), more than the limit of " + number_text(limit) +
                     " (--max-faces); use a coarser --relative-alpha, about " +
                     number_text(diag / result.alpha * std::sqrt(limit / estimate), 2) +
                     " at most, or raise --max-faces");
  std::vector<Point> points;
  points.reserve(soup.points.size());
  for (const Vec3& p : soup.points) points.emplace_back(p.x(), p.y(), p.z());
  // Alpha wrapping accepts triangles only; polygons are fanned (the wrap only needs their area covered).
  std::vector<std::array<std::size_t, 3>> faces;
  for (const auto& poly : soup.polygons)
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) faces.push_back({poly[0], poly[k], poly[k + 1]});
  Timer timer;
  CGAL::Surface_mesh<Point> wrap;
  WrapVisitor visitor(options.max_faces, estimate, diag / result.alpha);
  CGAL::alpha_wrap_3(points, faces, result.alpha, result.offset, wrap, CGAL::parameters::default_values(),
                     CGAL::parameters::visitor(std::ref(visitor)));
  result.seconds = timer.seconds();
  result.mesh = triangle_mesh_from(wrap);
  return result;
}

}  // namespace cdbench
