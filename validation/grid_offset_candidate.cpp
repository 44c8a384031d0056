// Would a grid be a faster candidate mesher for certified offsets? For each level, OpenVDB's
// signed-distance grid and volume-to-mesh (the float pipeline's GridSdf) make a candidate, which is
// validated (closed, manifold, no self-intersection: exact) and, when valid, gets its certified band
// (certify_band, as `cdbench offset` does), as it comes and with its vertices moved onto the level
// set by the fast distance (point_on_level_near). One row per level and voxel; compare with the
// Surface_mesher levels of doc/offsets.md. Figures and the conclusion in doc/offsets.md.
//
// Usage: grid_offset_candidate MESH LEVELS CELLS_PER_DIAGONAL[,CELLS...]
//   LEVELS: as `cdbench offset --levels` (e.g. -10%,10%; percentages of the certified max penetration).
#include <tbb/parallel_for.h>

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "distance/max_penetration.h"
#include "floatpipe/grid_offsets.h"
#include "guarded_main.h"
#include "mesh/read_mesh.h"
#include "mesh/validate_mesh.h"
#include "offset/fast_signed_distance.h"
#include "offset/level_list.h"
#include "offset/offset_level.h"
#include "util/timer.h"

namespace {

using namespace cdbench;

std::vector<double> numbers(const std::string& list) {
  std::vector<double> out;
  std::stringstream ss(list);
  for (std::string item; std::getline(ss, item, ',');) out.push_back(std::stod(item));
  return out;
}

int run(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: grid_offset_candidate MESH LEVELS CELLS_PER_DIAGONAL[,CELLS...]\n");
    return 2;
  }
  const std::vector<LevelSpec> levels = parse_level_list(argv[2]);
  const ValidatedMesh in = validate_mesh(read_triangle_mesh(argv[1]));
  if (!in.report.valid()) throw std::runtime_error(std::string(argv[1]) + ": not a valid closed solid");
  const TriangleMesh& mesh = in.mesh;
  const SignedDistance sdf(mesh);
  const FastSignedDistance fast(sdf);
  const MaxPenetrationResult mp = certified_max_penetration(sdf, {});
  const double diag = mesh.bbox().diagonal(), tol = 1e-3 * diag;
  const BandOptions bo = offset_band_options(tol);  // as `cdbench offset`
  // "yes | band / diag | faces above the tolerance", or "no (first error) | |"; band seconds in *seconds.
  const auto certified = [&](const TriangleMesh& candidate, double d, double* seconds) {
    const ValidatedMesh v = validate_mesh(candidate);
    if (!v.report.valid()) return "no (" + v.report.errors[0].message.substr(0, 60) + ") | |";
    Timer t;
    const BandResult b = certify_band(sdf, v.mesh, d, bo);
    *seconds = t.seconds();
    std::size_t wide = 0;
    for (double e : b.face_epsilon) wide += e > tol;
    return "yes | " + std::to_string(b.epsilon / diag) + " | " +
           std::to_string(100.0 * static_cast<double>(wide) / static_cast<double>(v.mesh.faces.size())) + " %";
  };
  std::printf("| level | cells / diagonal | grid + mesh s | faces | valid as is | band / diag | faces above 1e-3 | band s | "
              "projected: valid | band / diag | faces above 1e-3 |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const LevelSpec& level : levels)
    for (double cells : numbers(argv[3])) {
      const double d = level_distance(level, mp.depth.lo), h = diag / cells;
      Timer t_grid;
      const GridSdf grid(mesh, {h, std::max(d, 0.0) + 3.0 * h, std::max(-d, 0.0) + 3.0 * h});
      const TriangleMesh candidate = grid.isosurface(d);
      const double s_grid = t_grid.seconds();
      double s_band = 0.0, s_unused = 0.0;
      const std::string as_is = certified(candidate, d, &s_band);
      TriangleMesh moved = candidate;
      tbb::parallel_for(std::size_t{0}, moved.vertices.size(), [&](std::size_t i) {
        Vec3 on;
        if (point_on_level_near(fast, d, candidate.vertices[i], on)) moved.vertices[i] = on;
      });
      const std::string projected = certified(moved, d, &s_unused);
      std::printf("| %s | %g | %.2f | %zu | %s | %.2f | %s |\n", level.text.c_str(), cells, s_grid, candidate.faces.size(),
                  as_is.c_str(), s_band, projected.c_str());
      std::fflush(stdout);
    }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return guarded_main("grid_offset_candidate", run, argc, argv); }
