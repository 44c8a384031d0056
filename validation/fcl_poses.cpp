// FCL's conservative advancement as a second float placement, written as a pose-set bundle for
// `cdbench validate`: for every approach of a pose set made by `cdbench poses` (the same
// orientations, directions and reference placement), the time of contact of
// fcl::detail::conservativeAdvancementMeshOriented (OBBRSS, TranslationMotion) from the far start
// to the mirrored far end gives a touching pose (level 0; CA has no offset, so it places touching
// poses only). Status uncertified:float, "pipeline": "fcl-ca" in poseset.json, timings per pose.
// Usage: fcl_poses POSESET_DIR -o OUT_DIR
#include <cstdio>
#include <cstring>
#include <iomanip>
#include <limits>
#include <string>
#include <vector>

#include "collide/fcl_model.h"
#include "fcl_ca.h"
#include "mesh/read_mesh.h"
#include "mesh/validate_mesh.h"
#include "placement/place_pose.h"
#include "poseset/pose_csv.h"
#include "poseset/poseset_manifest.h"
#include "sampling/sampling.h"
#include "util/atomic_file.h"

using namespace cdbench;

int main(int argc, char** argv) {
  if (argc != 4 || std::strcmp(argv[2], "-o") != 0) {
    std::fprintf(stderr, "usage: fcl_poses POSESET_DIR -o OUT_DIR\n");
    return 2;
  }
  try {
    const std::string dir = argv[1], out = argv[3];
    const PoseSetManifest man = read_poseset_manifest(dir);
    const nlohmann::json& ps = man.json;
    const auto load = [](const std::string& p) { return validate_mesh(read_polygon_soup(p)).mesh; };
    const TriangleMesh fixed_mesh = load(locate_mesh(man.fixed, man.dir));
    const TriangleMesh mover = man.mover_is_fixed ? fixed_mesh : load(locate_mesh(man.mover, man.dir));
    const SignedDistance fixed(fixed_mesh);  // reference points and radii only
    const ApproachSetup setup = make_approach_setup(fixed, mover);
    const auto& s = ps.at("sampling");
    const std::size_t N = s.at("directions").at("count"), K = s.at("orientations").at("count");
    const std::vector<Vec3> dirs = sample_directions(s.at("directions").at("kind"), N);
    const std::vector<Eigen::Quaterniond> rots =
        sample_orientations(s.at("orientations").at("kind"), K, s.at("orientations").value("seed", 1ull));
    auto fcl_fixed = fcl_model<fcl::OBBRSS<double>>(fixed_mesh);
    auto fcl_mover = fcl_model<fcl::OBBRSS<double>>(mover);
    const double far = setup.fixed_radius + setup.mover_radius + 1e-3 * man.diagonal;
    prepare_output_directory(out);
    std::string csv = std::string(kPoseCsvHeader) + "\n";
    double seconds = 0.0;
    std::size_t placed = 0;
    for (std::size_t o = 0; o < K; ++o) {
      const OrientationFrame frame = make_orientation_frame(setup, rots[o].toRotationMatrix());
      for (std::size_t d = 0; d < N; ++d) {
        const Vec3& dir = dirs[d];
        double lambda = 0.0, t = 0.0;
        const bool hit = fcl_ca_contact(*fcl_fixed, *fcl_mover, frame, dir, far, &lambda, &t);
        seconds += t;
        PoseRow r;
        const double nan = std::numeric_limits<double>::quiet_NaN();
        r.pose = o * N + d;
        r.level = 0;
        r.target = 0.0;
        r.R = frame.orientation.R;
        r.dir = dir;
        r.orientation = o;
        r.direction = d;
        r.clearance_lo = r.clearance_hi = r.raw_clearance_lo = r.raw_clearance_hi = nan;
        if (hit) {
          r.lambda = lambda;
          r.t = pose_translation(frame, dir, r.lambda);
          r.status = PoseStatus::Float;
          ++placed;
        } else {
          r.lambda = nan;
          r.t = Vec3::Constant(nan);
          r.status = PoseStatus::NoContact;
        }
        csv += format_pose_row(r);
      }
    }
    nlohmann::json j;
    j["format"] = "cdbench-poseset";
    j["format_version"] = 1;
    j["pipeline"] = "fcl-ca";
    j["fixed"] = to_json(man.fixed);
    j["mover"] = to_json(man.mover);
    j["mover_is_fixed"] = man.mover_is_fixed;
    j["max_penetration"] = ps.at("max_penetration");
    j["levels"] = {{{"index", 0}, {"spec", "0"}, {"target", 0.0}, {"poses", N * K}, {"placed", placed}, {"thread_seconds", seconds}}};
    j["sampling"] = s;
    j["certification"] = {{"certified", false}, {"tolerance", man.tolerance}, {"diagonal", man.diagonal}};
    j["placement"] = {{"approach", "FCL conservativeAdvancementMeshOriented (OBBRSS, TranslationMotion) from the far "
                                    "start to the mirrored far end; the pose at its time of contact"},
                      {"source_poseset", dir}};
    write_file_atomically(out + "/poses.csv", [&](std::ostream& os) { os << csv; });
    write_file_atomically(out + "/poseset.json", [&](std::ostream& os) { os << std::setw(2) << j << "\n"; });
    std::printf("fcl_poses: %zu approaches, %zu placed, %.3f ms per approach (one thread): %s\n", N * K, placed,
                1e3 * seconds / (N * K), out.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fcl_poses: error: %s\n", e.what());
    return 2;
  }
}
