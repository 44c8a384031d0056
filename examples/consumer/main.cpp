// Using cdbench as a C++ library (find_package(cdbench)): read two closed meshes, certify the
// clearance of one pose, and judge a collision answer against the certificate.
//   consumer FIXED MOVER
#include <cstdio>
#include <exception>

#include "distance/signed_distance.h"
#include "mesh/read_mesh.h"
#include "mesh/validate_mesh.h"
#include "placement/clearance.h"
#include "score/verdict.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: consumer FIXED MOVER\n");
    return 2;
  }
  try {
    using namespace cdbench;
    const ValidatedMesh fixed = validate_mesh(read_polygon_soup(argv[1]));
    const ValidatedMesh mover = validate_mesh(read_polygon_soup(argv[2]));
    if (!fixed.report.valid() || !mover.report.valid()) {
      std::fprintf(stderr, "not closed solids\n");
      return 1;
    }
    const SignedDistance sdf(fixed.mesh);
    // The mover turned by 0.3 rad about z and moved along x: x_world = R x + t.
    Eigen::Matrix3d R = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    for (double tx : {0.0, 3.0, 5.0}) {
      const Vec3 t(tx, 0.0, 0.0);
      const ClearanceResult c = certify_clearance(sdf, mover.mesh, R, t, 1e-6 * sdf.bbox().diagonal());
      // Someone's answer for this pose: "collides" whenever the mover's centre is within 4 of the origin.
      const bool answer = tx < 4.0;
      std::printf("t = (%g, 0, 0): clearance in [%.17g, %.17g]; answer %s: %s\n", tx, c.clearance.lo, c.clearance.hi,
                  answer ? "collides" : "free", to_string(classify(c.clearance.lo, c.clearance.hi, answer, true)));
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
