// Would a grid be a faster candidate mesher for certified offsets? For each level, OpenVDB's
// signed-distance grid and volume-to-mesh (the float pipeline's GridSdf) make a candidate, which is
// validated (closed, manifold, no self-intersection: exact) and, when valid, gets its certified band
// (certify_band, as `cdbench offset` does), as it comes and with its vertices moved onto the level
// set by the fast distance (point_on_level_near). One row per level and voxel; compare with the
// Surface_mesher levels of doc/offsets.md. Figures and the conclusion in doc/offsets.md.
//
// Usage: grid_offset_candidate MESH FRACTION[,FRACTION...] CELLS_PER_DIAGONAL[,CELLS...]
//   FRACTION: the level as a signed fraction of the certified max penetration (-0.1 = -10 %).
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
#include "offset/certify_band.h"
#include "offset/fast_signed_distance.h"
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
    std::fprintf(stderr, "usage: grid_offset_candidate MESH FRACTION[,FRACTION...] CELLS_PER_DIAGONAL[,CELLS...]\n");
    return 2;
  }
  const ValidatedMesh in = validate_mesh(read_triangle_mesh(argv[1]));
  if (!in.report.valid()) throw std::runtime_error(std::string(argv[1]) + ": not a valid closed solid");
  const TriangleMesh& mesh = in.mesh;
  const SignedDistance sdf(mesh);
  const FastSignedDistance fast(sdf);
  const MaxPenetrationResult mp = certified_max_penetration(sdf, {});
  const double diag = mesh.bbox().diagonal(), tol = 1e-3 * diag;
  std::printf("| level | cells / diagonal | grid + mesh s | faces | valid as is | band / diag | faces above 1e-3 | band s | "
              "projected: valid | band / diag | faces above 1e-3 |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (double frac : numbers(argv[2]))
    for (double cells : numbers(argv[3])) {
      const double d = frac * mp.depth.lo, h = diag / cells;
      Timer t_grid;
      const GridSdf grid(mesh, {h, std::max(d, 0.0) + 3.0 * h, std::max(-d, 0.0) + 3.0 * h});
      const TriangleMesh candidate = grid.isosurface(d);
      const double s_grid = t_grid.seconds();
      BandOptions bo;  // as compute_offset_level
      bo.target = 0.75 * tol;
      bo.second_pass_above = tol;
      const auto band_of = [&](const TriangleMesh& m, double* seconds) {
        Timer t;
        const BandResult b = certify_band(sdf, m, d, bo);
        *seconds = t.seconds();
        std::size_t wide = 0;
        for (double e : b.face_epsilon) wide += e > tol;
        return std::make_pair(b.epsilon / diag, 100.0 * static_cast<double>(wide) / static_cast<double>(m.faces.size()));
      };
      const ValidatedMesh v = validate_mesh(candidate);
      double s_band = 0.0;
      std::string as_is = "no", projected = "no";
      if (v.report.valid()) {
        const auto [eps, wide] = band_of(v.mesh, &s_band);
        as_is = "yes | " + std::to_string(eps) + " | " + std::to_string(wide) + " %";
      } else {
        as_is += " | | ";
      }
      TriangleMesh moved = candidate;
      tbb::parallel_for(std::size_t{0}, moved.vertices.size(), [&](std::size_t i) {
        Vec3 on;
        if (point_on_level_near(fast, d, candidate.vertices[i], on)) moved.vertices[i] = on;
      });
      const ValidatedMesh pv = validate_mesh(moved);
      if (pv.report.valid()) {
        double s = 0.0;
        const auto [eps, wide] = band_of(pv.mesh, &s);
        projected = "yes | " + std::to_string(eps) + " | " + std::to_string(wide) + " %";
      } else {
        projected += " (" + pv.report.errors[0].message.substr(0, 60) + ") | |";
      }
      std::printf("| %g %% | %g | %.2f | %zu | %s | %.2f | %s |\n", 100.0 * frac, cells, s_grid, candidate.faces.size(),
                  as_is.c_str(), s_band, projected.c_str());
      std::fflush(stdout);
    }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return guarded_main("grid_offset_candidate", run, argc, argv); }
