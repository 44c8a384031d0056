// `validate` on a hand-made pose set with known wrong-sign and missed-contact poses: a small ball
// (the mover) placed against a thin plate (the fixed solid), coming from +z.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <nlohmann/json.hpp>

#include "mesh/shapes.h"
#include "mesh/write_mesh.h"
#include "poseset/pose_csv.h"
#include "poseset/poseset_manifest.h"
#include "validate/validate_run.h"

namespace cdbench {
namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Case {
  std::uint64_t pose;
  double target, z;  // the ball's centre at (0, 0, z); NaN: no pose
};

// Writes a bundle of poses (R = I, dir = +z) and a one-level-per-target manifest.
// R and base: every pose's rotation, and its translation less (0, 0, z).
void write_bundle(const std::string& dir, const std::vector<Case>& cases, const std::vector<double>& targets,
                  const TriangleMesh& fixed, const TriangleMesh& mover, PoseStatus status,
                  const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity(), const Vec3& base = Vec3::Zero()) {
  std::filesystem::create_directories(dir);
  std::ofstream csv(dir + "/poses.csv");
  csv << kPoseCsvHeader << "\n";
  for (const Case& c : cases) {
    PoseRow r;
    r.pose = c.pose;
    r.level = static_cast<int>(std::find(targets.begin(), targets.end(), c.target) - targets.begin());
    r.target = c.target;
    r.R = R;
    r.t = std::isnan(c.z) ? Vec3::Constant(kNaN) : Vec3(base + Vec3(0, 0, c.z));
    r.dir = Vec3(0, 0, 1);
    r.clearance_lo = r.clearance_hi = r.raw_clearance_lo = r.raw_clearance_hi = kNaN;
    r.status = std::isnan(c.z) ? PoseStatus::NoContact : status;
    csv << format_pose_row(r);
  }
  const auto record = [](const TriangleMesh& m, const std::string& name) {
    MeshRecord r;
    r.path = name;
    r.sha256 = "0";
    r.vertices = m.vertices.size();
    r.faces = m.faces.size();
    r.diagonal = m.bbox().diagonal();
    return to_json(r);
  };
  nlohmann::json j;
  j["format"] = "cdbench-poseset";
  j["format_version"] = 1;
  j["pipeline"] = "test";
  j["fixed"] = record(fixed, "plate");
  j["mover"] = record(mover, "ball");
  j["mover_is_fixed"] = false;
  j["max_penetration"] = {{"interval", {0.05, 0.05}}};
  j["levels"] = nlohmann::json::array();
  for (double t : targets) j["levels"].push_back({{"spec", std::to_string(t)}, {"target", t}});
  j["certification"] = {{"tolerance", 1e-6}, {"diagonal", fixed.bbox().diagonal()}};
  std::ofstream(dir + "/poseset.json") << j.dump(2);
}

TEST(Validate, CountsWrongSignsAndMissedContacts) {
  const std::string dir = testing::TempDir() + "/validate_test";
  std::filesystem::remove_all(dir);
  const TriangleMesh plate = make_box(Vec3(-1, -1, -0.05), Vec3(1, 1, 0.05));
  const TriangleMesh ball = make_icosphere(0.1, 3);  // inscribed: its lowest point is a vertex at -0.1
  const std::vector<double> targets = {-0.03, 0.1, 0.0};
  // Plate top at z = 0.05, bottom at -0.05; the ball's lowest point at z - 0.1 (a vertex), highest z + 0.1.
  const std::vector<Case> cases = {
      {0, 0.1, 0.25},    // right: 0.1 above the plate
      {1, 0.1, 0.10},    // wrong sign: penetrates by 0.05
      {2, 0.1, -0.25},   // missed contact: 0.1 below the plate, having come from +z through it
      {3, -0.03, 0.12},  // right: 0.03 deep from the top
      {4, -0.03, 0.30},  // wrong sign: separated
      {5, -0.03, -0.14}, // past the reference (pose 5 there at z = 0.11, 0.04 deep) and only 0.01 deep: missed
      {6, -0.03, kNaN},  // no pose
      {7, 0.0, -0.13},   // touching target, but below the plate after passing through it (0.02 deep, 0.05 before)
      {8, 0.0, 0.1499},  // touching target, 1e-4 deep on its first contact: not missed
  };
  write_bundle(dir + "/set", cases, targets, plate, ball, PoseStatus::Float);
  std::vector<Case> ref_cases = cases;
  for (Case& c : ref_cases) c.z = c.target < 0 ? 0.11 : 0.25;  // the reference's (certified) placements
  write_bundle(dir + "/ref", ref_cases, targets, plate, ball, PoseStatus::Certified);
  // The reference's certificates: validate it first (its rows carry no clearance).
  ValidateRequest rq;
  rq.poseset = dir + "/ref";
  rq.fixed = &plate;
  rq.mover = &ball;
  rq.out = dir + "/ref-validation";
  const ValidateResult ref = run_validate(rq);
  for (const PoseValidation& p : ref.poses) EXPECT_FALSE(p.wrong_sign) << p.pose;
  {  // the reference with its certified clearances, as a certified pose set has them
    std::ifstream in(dir + "/ref/poses.csv");
    std::vector<PoseRow> rows = read_pose_csv(in, "ref");
    std::ofstream out(dir + "/ref/poses.csv");
    out << kPoseCsvHeader << "\n";
    for (std::size_t i = 0; i < rows.size(); ++i) {
      rows[i].clearance_lo = ref.poses[i].clearance.lo;
      rows[i].clearance_hi = ref.poses[i].clearance.hi;
      out << format_pose_row(rows[i]);
    }
  }

  rq.poseset = dir + "/set";
  rq.reference = dir + "/ref";
  rq.out = dir + "/out";
  const ValidateResult v = run_validate(rq);
  ASSERT_EQ(v.poses.size(), cases.size());
  const auto& p = v.poses;
  EXPECT_NEAR(p[0].clearance.lo, 0.1, 1e-9);
  EXPECT_FALSE(p[0].wrong_sign);
  EXPECT_EQ(p[0].missed_contact, Tristate::No);
  EXPECT_TRUE(p[1].wrong_sign);
  EXPECT_EQ(p[1].missed_contact, Tristate::No);
  EXPECT_FALSE(p[2].wrong_sign);
  EXPECT_NEAR(p[2].clearance.lo, 0.1, 1e-9);
  EXPECT_EQ(p[2].missed_contact, Tristate::Yes);
  // The ball first touches the plate at z = 0.15 coming from above: pose 2 lies 0.4 past it,
  // pose 1 0.05, pose 0 not at all.
  EXPECT_NEAR(p[2].past_first_contact, 0.4, 1e-9);
  EXPECT_NEAR(p[1].past_first_contact, 0.05, 1e-9);
  EXPECT_EQ(p[0].past_first_contact, 0.0);
  EXPECT_TRUE(std::isnan(p[3].past_first_contact));
  EXPECT_EQ(v.levels[1].past_first_contact, 2u);
  EXPECT_NEAR(p[3].clearance.lo, -0.03, 1e-5);
  EXPECT_FALSE(p[3].wrong_sign);
  EXPECT_EQ(p[3].missed_contact, Tristate::No);
  EXPECT_TRUE(p[4].wrong_sign);
  EXPECT_NEAR(p[5].clearance.hi, -0.01, 1e-5);
  EXPECT_EQ(p[5].missed_contact, Tristate::Yes);
  EXPECT_FALSE(p[6].placed);
  // Pose 7 lies 0.28 past its first contact (z = 0.15); at z = 0.01 on the way the ball was 0.05
  // deep, deeper than its 0.02 at the pose: a witness that it skipped the first contact.
  EXPECT_NEAR(p[7].clearance.hi, -0.02, 1e-5);
  EXPECT_NEAR(p[7].past_first_contact, 0.28, 1e-9);
  EXPECT_EQ(p[7].missed_contact, Tristate::Yes);
  EXPECT_EQ(p[8].missed_contact, Tristate::No);
  EXPECT_NEAR(p[8].past_first_contact, 1e-4, 1e-9);
  EXPECT_EQ(v.levels[0].wrong_sign, 1u);
  EXPECT_EQ(v.levels[0].missed_contact, 1u);
  EXPECT_EQ(v.levels[1].wrong_sign, 1u);
  EXPECT_EQ(v.levels[1].missed_contact, 1u);
  EXPECT_EQ(v.levels[0].placed, 3u);
  EXPECT_NEAR(v.levels[1].error_max, 0.15, 1e-5);  // pose 1: c = -0.05 for a target of 0.1
  // Without a reference, penetrating poses' missed contacts are undecided, not guessed.
  rq.reference.clear();
  rq.out = dir + "/out2";
  const ValidateResult w = run_validate(rq);
  EXPECT_EQ(w.poses[5].missed_contact, Tristate::Unknown);
  EXPECT_EQ(w.levels[0].missed_undecided, 3u);
  EXPECT_EQ(w.levels[1].missed_contact, 1u);
  // The CSV: one row per pose, the columns.
  std::ifstream csv(dir + "/out/validation.csv");
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header, "pose,level,target,clearance_lo,clearance_hi,error,wrong_sign,missed_contact,past_first_contact");
  int n = 0;
  while (std::getline(csv, line)) ++n;
  EXPECT_EQ(n, 9);
}

// A thin tube of 4-long slivers, tilted, beside a finely faceted sphere with its wall 0.05-0.1
// apart: validate's certificates of these separated poses come from the pair-distance path, on the
// sweep trees where either mesh has long faces (as `cdbench certify`). They are a few ulps wide, and
// agree with the distance of the tube's outer wall from the sphere. On the box trees the path ran
// out of its budget (16 pairs a triangle) and the branch and bound's interval was the tolerance
// wide.
TEST(Validate, SeparatedSliverPosesGetTightCertificates) {
  const std::string dir = testing::TempDir() + "/validate_tube";
  std::filesystem::remove_all(dir);
  const TriangleMesh sphere = make_icosphere(0.5, 3);
  const TriangleMesh tube = make_tube(0.09, 0.1, 4.0, 48);
  // The tube's axis tilted by 0.6 rad about y (its slivers' world-aligned boxes are then wide).
  const double a = 0.6;
  Eigen::Matrix3d R;
  R << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
  const Vec3 axis = R.col(2);
  const Vec3 side = R.col(0);  // perpendicular to the axis, in the x-z plane
  std::vector<Case> cases;
  for (std::uint64_t k = 0; k < 4; ++k) cases.push_back({k, 0.1, 0.0});
  ValidateRequest rq;
  rq.fixed = &sphere;
  rq.mover = &tube;
  for (std::uint64_t k = 0; k < 4; ++k) {
    // The axis at 0.65 + 0.05 k from the centre, its middle beside it: the wall 0.05 + 0.05 k apart.
    const Vec3 base = (0.65 + 0.05 * static_cast<double>(k)) * side - 2.0 * axis;
    const std::string set = dir + "/set" + std::to_string(k);
    write_bundle(set, {cases[k]}, {0.1}, sphere, tube, PoseStatus::Float, R, base);
    rq.poseset = set;
    rq.out = dir + "/out" + std::to_string(k);
    const ValidateResult v = run_validate(rq);
    ASSERT_EQ(v.poses.size(), 1u);
    const Interval c = v.poses[0].clearance;
    EXPECT_TRUE(v.poses[0].certified);
    // The sphere's facets lie within 0.5 (1 - cos(half an edge's angle)) < 0.002 inside it.
    const double wall = 0.05 + 0.05 * static_cast<double>(k);
    EXPECT_GE(c.lo, wall - 1e-12) << k;
    EXPECT_LE(c.hi, wall + 0.002) << k;
    EXPECT_LT(c.hi - c.lo, 1e-12) << std::setprecision(17) << k << ": [" << c.lo << ", " << c.hi << "]";
  }
}

}  // namespace
}  // namespace cdbench
