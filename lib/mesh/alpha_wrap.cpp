// CGAL's alpha wrapping lives in this translation unit only.
#include "mesh/alpha_wrap.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/alpha_wrap_3.h>

#include "mesh/cgal_surface_mesh.h"
#include "util/error.h"
#include "util/number_format.h"
#include "util/timer.h"

namespace cdbench {

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
  std::vector<Point> points;
  points.reserve(soup.points.size());
  for (const Vec3& p : soup.points) points.emplace_back(p.x(), p.y(), p.z());
  // Alpha wrapping accepts triangles only; polygons are fanned (the wrap only needs their area covered).
  std::vector<std::array<std::size_t, 3>> faces;
  for (const auto& poly : soup.polygons)
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) faces.push_back({poly[0], poly[k], poly[k + 1]});
  Timer timer;
  CGAL::Surface_mesh<Point> wrap;
  CGAL::alpha_wrap_3(points, faces, result.alpha, result.offset, wrap);
  result.seconds = timer.seconds();
  result.mesh = triangle_mesh_from(wrap);
  return result;
}

}  // namespace cdbench
