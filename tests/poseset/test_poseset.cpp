// The pose-set module: poses.csv rows, user pose files (both header forms, every error names its
// line), the journal (a cut tail is dropped; a resumed run must be the same run), poseset.json,
// the merge of shards (byte-identical to one run; every bad set of shards named).
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "distance/signed_distance.h"
#include "mesh/shapes.h"
#include "mesh/write_mesh.h"
#include "poseset/build_poseset.h"
#include "poseset/journal.h"
#include "poseset/level_summary.h"
#include "poseset/merge_shards.h"
#include "poseset/pose_csv.h"
#include "poseset/poseset_manifest.h"
#include "poseset/user_poses.h"
#include "util/error.h"
#include "util/sha256.h"

namespace cdbench {
namespace {

UserPoseFile parse(const std::string& text) {
  std::istringstream in(text);
  return read_user_poses(in, "p.csv");
}

// The message of the InputError thrown by f ("" if none).
template <class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(UserPoses, MatrixFormWithExtraColumnsAndBlankLines) {
  const UserPoseFile f = parse(
      "pose,r00,r01,r02,r10,r11,r12,r20,r21,r22,tx,ty,tz,comment\n"
      "7,1,0,0,0,1,0,0,0,1,0.5,-1,2,first\n"
      "\n"
      "3, 0,-1,0, 1,0,0, 0,0,1, 1e-3,0,0 ,x\r\n");
  ASSERT_EQ(f.poses.size(), 2u);
  EXPECT_EQ(f.form, RotationForm::Matrix);
  EXPECT_EQ(f.poses[0].pose, 7u);
  EXPECT_EQ(f.poses[1].pose, 3u);
  EXPECT_EQ(f.poses[1].line, 4u);
  EXPECT_EQ(f.poses[1].R(0, 1), -1.0);
  EXPECT_EQ(f.poses[1].t.x(), 1e-3);
  EXPECT_TRUE(std::isnan(f.poses[0].target));
  ASSERT_EQ(f.ignored_columns.size(), 1u);
  EXPECT_EQ(f.ignored_columns[0], "comment");
}

TEST(UserPoses, QuaternionFormInAnyColumnOrderWithTargets) {
  const UserPoseFile f = parse("tz,ty,tx,qz,qy,qx,qw,target,pose\n0,0,1,0,0,0,2,-0.5,0\n3,2,1,0.3,0.2,0.1,0.9,,1\n");
  ASSERT_EQ(f.poses.size(), 2u);
  EXPECT_EQ(f.form, RotationForm::Quaternion);
  EXPECT_TRUE(f.has_target);
  EXPECT_EQ(f.poses[0].target, -0.5);
  EXPECT_TRUE(std::isnan(f.poses[1].target));                 // an empty target
  EXPECT_TRUE(f.poses[0].R.isApprox(Eigen::Matrix3d::Identity()));  // (2, 0, 0, 0) normalized
  EXPECT_EQ(f.poses[1].t, Eigen::Vector3d(1, 2, 3));
  const Eigen::Matrix3d& R = f.poses[1].R;
  EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-15);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-15);
}

TEST(UserPoses, EveryErrorNamesItsLine) {
  const std::string m = "pose,r00,r01,r02,r10,r11,r12,r20,r21,r22,tx,ty,tz\n";
  const std::string ok = "0,1,0,0,0,1,0,0,0,1,0,0,0\n";
  struct Case {
    std::string text, expected;
  };
  const std::vector<Case> cases = {
      {"", "empty file"},
      {"pose,qw,qx,qy,tx,ty,tz\n", "p.csv:1: quaternion columns missing: qz"},
      {"pose,tx,ty,tz\n", "p.csv:1: no rotation columns"},
      {"r00,r01,r02,r10,r11,r12,r20,r21,r22,tx,ty,tz\n", "p.csv:1: no 'pose' column"},
      {"pose,pose,qw,qx,qy,qz,tx,ty,tz\n", "names column 'pose' twice"},
      {m, "p.csv: no poses after the header"},
      {m + ok + "1,1,0,0,0,1,0,0,0,1,0,0\n", "p.csv:3: expected 13 columns (as the header), found 12"},
      {m + ok + "1,1,0,0,0,1,0,0,0,1,0,nan,0\n", "p.csv:3: column ty is not finite"},
      {m + ok + "1,1,0,0,0,1,0,0,0,1,0,1e999,0\n", "p.csv:3: column ty is not finite"},
      {m + ok + "1,1,0,0,0,1,0,0,0,1,0,x,0\n", "p.csv:3: column ty is not a number: 'x'"},
      {m + ok + "0,1,0,0,0,1,0,0,0,1,0,0,0\n", "p.csv:3: pose 0 again (first at line 2)"},
      {m + ok + "-1,1,0,0,0,1,0,0,0,1,0,0,0\n", "p.csv:3: column pose is not a non-negative integer"},
      {m + ok + "1,1,0,0,2,0,0,0,0,1,0,0,0\n", "p.csv:3: the rotation matrix is singular"},
      {"pose,qw,qx,qy,qz,tx,ty,tz\n0,0,0,0,0,1,2,3\n", "p.csv:2: the quaternion (qw,qx,qy,qz) is zero"},
      {m + ok + "1,1,0,0,0,1,0,0,0,1,0,-2e40,0\n", "p.csv:3: the translation (0, -2e+40, 0) is outside the supported range"},
  };
  for (const Case& c : cases) {
    const std::string e = error_of([&] { parse(c.text); });
    EXPECT_NE(e.find(c.expected), std::string::npos) << "input:\n" << c.text << "message: " << e;
  }
}

TEST(UserPoses, NonOrthonormalButInvertibleMatricesAreKeptAsStored) {
  const UserPoseFile f = parse("pose,r00,r01,r02,r10,r11,r12,r20,r21,r22,tx,ty,tz\n0,2,0.1,0,0,1,0,0,0,0.5,0,0,0\n");
  EXPECT_EQ(f.poses[0].R(0, 0), 2.0);
  EXPECT_EQ(f.poses[0].R(0, 1), 0.1);
}

PoseRow row(std::uint64_t id) {
  PoseRow r;
  r.pose = id;
  r.status = PoseStatus::Certified;
  r.clearance_lo = 0.25;
  r.clearance_hi = 0.5;
  return r;
}

TEST(Journal, KeepsCompleteRowsDropsACutTailAndRefusesAnotherRun) {
  const std::string dir = testing::TempDir() + "/journal_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const nlohmann::json key = {{"run", 1}};
  {
    PoseJournal j(dir, "x", key, false, "test");
    EXPECT_TRUE(j.done().empty());
    j.append({format_pose_row(row(4)), format_pose_row(row(2))});
  }
  {  // An interruption cut the last line.
    std::ofstream out(dir + "/x.journal", std::ios::app);
    const std::string cut = format_pose_row(row(9));
    out << cut.substr(0, cut.size() / 2);
  }
  EXPECT_NE(error_of([&] { PoseJournal j(dir, "x", key, false, "test"); }).find("pass --resume"), std::string::npos);
  EXPECT_NE(error_of([&] { PoseJournal j(dir, "x", nlohmann::json{{"run", 2}}, true, "test"); }).find("other inputs"),
            std::string::npos);
  PoseJournal j(dir, "x", key, true, "test");
  ASSERT_EQ(j.done().size(), 2u);
  EXPECT_EQ(j.done().begin()->first, 2u);
  EXPECT_EQ(read_journal_rows(j.path()).count(9), 0u);
  j.remove();
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.journal"));
}

TEST(Journal, ALineDamagedOnDiskIsRecomputedEvenWhenItStillParses) {
  const std::string dir = testing::TempDir() + "/journal_damage";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const nlohmann::json key = {{"run", 1}};
  {
    PoseJournal j(dir, "x", key, false, "test");
    j.append({format_pose_row(row(1)), format_pose_row(row(2)), format_pose_row(row(3))});
  }
  std::string bytes;
  {
    std::ifstream in(dir + "/x.journal", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  // Row 2's clearance 0.25 becomes 0.75: still a valid row, but not what was certified.
  const std::size_t second = bytes.find('\n') + 1;
  const std::size_t at = bytes.find("0.25", second);
  ASSERT_NE(at, std::string::npos);
  bytes[at + 2] = '7';
  std::ofstream(dir + "/x.journal", std::ios::binary | std::ios::trunc) << bytes;
  const auto rows = read_journal_rows(dir + "/x.journal");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows.count(2), 0u);
  EXPECT_EQ(rows.at(3), format_pose_row(row(3)));
}

TEST(PoseSetManifest, WrongTypesAndCountsAreNamedNotCast) {
  const std::string dir = testing::TempDir() + "/manifest_test";
  std::filesystem::create_directories(dir);
  const nlohmann::json mesh = {{"path", "m.off"}, {"sha256", "00"}, {"vertices", 8}, {"faces", 12}, {"diagonal", 1.7},
                               {"reference_point", {0, 0, 0}}};
  const nlohmann::json good = {{"format", "cdbench-poseset"}, {"format_version", 1}, {"fixed", mesh}, {"mover", mesh},
                               {"mover_is_fixed", true}, {"max_penetration", {{"interval", {0.5, 0.5000001}}}},
                               {"levels", {{{"spec", "0"}, {"target", 0.0}}}},
                               {"certification", {{"tolerance", 1e-6}, {"diagonal", 1.7}}}};
  std::ofstream(dir + "/poseset.json") << good.dump();
  EXPECT_EQ(read_poseset_manifest(dir).fixed.faces, 12u);
  const std::vector<std::pair<nlohmann::json::json_pointer, nlohmann::json>> cases = {
      {nlohmann::json::json_pointer("/fixed/faces"), -1},
      {nlohmann::json::json_pointer("/fixed/vertices"), 1e300},
      {nlohmann::json::json_pointer("/format"), 3},
      {nlohmann::json::json_pointer("/mover_is_fixed"), "yes"},
      {nlohmann::json::json_pointer("/max_penetration/interval/0"), -1.0},
      {nlohmann::json::json_pointer("/certification/tolerance"), 0.0}};
  for (const auto& [where, value] : cases) {
    nlohmann::json bad = good;
    bad[where] = value;
    std::ofstream(dir + "/poseset.json") << bad.dump();
    EXPECT_NE(error_of([&] { read_poseset_manifest(dir); }).find("poseset.json"), std::string::npos) << where;
  }
}

TEST(PoseCsv, StatusesRoundTripAndUnknownOnesAreNamed) {
  for (PoseStatus s : {PoseStatus::Certified, PoseStatus::NoContact, PoseStatus::OffsetEmpty, PoseStatus::OffsetFailed,
                       PoseStatus::ToleranceNotReached, PoseStatus::PolishStalled, PoseStatus::Float}) {
    PoseRow r = row(3);
    r.status = s;
    EXPECT_EQ(parse_pose_row(format_pose_row(r), "x").status, s);
  }
  EXPECT_NE(error_of([] { parse_pose_status("uncertified:tired", "f:4"); }).find("f:4: unknown status 'uncertified:tired'"),
            std::string::npos);
}

// Poses left tolerance-not-reached are explained: how many and how wide; far from the origin (the
// doubles' rounding an eighth of the tolerance or more), the coordinates and a tolerance that would
// do (twice the widest interval or the rounding, 1.5e-6 here, one digit, rounded up); elsewhere the
// caller's hint.
TEST(LevelSummary, ToleranceNotReachedNoteNamesTheRoundingFarFromTheOrigin) {
  std::vector<PoseRow> rows(3);
  for (PoseRow& r : rows) r.status = PoseStatus::Certified;
  // Unit-sized boxes whose largest coordinate is 3e7 (x, far out) and 100.
  Aabb far_box, near_box;
  far_box.lo = Vec3(3e7 - 1.0, 2.0, -1.0);
  far_box.hi = Vec3(3e7, 3.0, 0.0);
  near_box.lo = Vec3(99.0, 0.0, 0.0);
  near_box.hi = Vec3(100.0, 1.0, 1.0);
  EXPECT_EQ(tolerance_not_reached_note(rows, 1e-6, 1.0, far_box, "limit"), "");
  rows[1].status = rows[2].status = PoseStatus::ToleranceNotReached;
  rows[1].clearance_lo = -0.1;
  rows[1].clearance_hi = -0.1 + 1.2e-6;
  rows[2].clearance_lo = -0.2;
  rows[2].clearance_hi = -0.2 + 0.9e-6;
  const std::string far = tolerance_not_reached_note(rows, 1e-6, 1.0, far_box, "limit");
  EXPECT_EQ(far.rfind("2 poses are uncertified:tolerance-not-reached (rigorous intervals up to 1.2e-06 wide", 0), 0u)
      << far;
  EXPECT_NE(far.find("reach 3e+07"), std::string::npos) << far;
  EXPECT_NE(far.find("--tolerance 3e-06 or more"), std::string::npos) << far;
  EXPECT_EQ(far.find("limit"), std::string::npos) << far;
  const std::string near = tolerance_not_reached_note(rows, 1e-6, 1.0, near_box, "limit");
  EXPECT_EQ(near.substr(near.size() - 5), "limit") << near;
  EXPECT_EQ(near.find("origin"), std::string::npos) << near;
}

TEST(PoseSetManifest, NamesTheMissingKey) {
  const std::string dir = testing::TempDir() + "/manifest_test";
  std::filesystem::create_directories(dir);
  const auto write = [&](const std::string& text) { std::ofstream(dir + "/poseset.json") << text; };
  write("{\"format\": \"cdbench-poseset\", \"format_version\": 1}");
  EXPECT_NE(error_of([&] { read_poseset_manifest(dir); }).find("missing key 'fixed'"), std::string::npos);
  write("[1, 2");
  EXPECT_NE(error_of([&] { read_poseset_manifest(dir); }).find("not valid JSON"), std::string::npos);
  write("{\"format\": \"other\"}");
  EXPECT_NE(error_of([&] { read_poseset_manifest(dir); }).find("not a cdbench pose set"), std::string::npos);
  MeshRecord m{"a.off", "00", 4, 4, 1.0, Eigen::Vector3d::Zero()};
  nlohmann::json j = {{"format", "cdbench-poseset"},
                      {"format_version", 1},
                      {"fixed", to_json(m)},
                      {"mover", to_json(m)},
                      {"mover_is_fixed", true},
                      {"max_penetration", {{"interval", {0.5, 0.5}}}},
                      {"levels", {{{"spec", "all"}, {"target", nullptr}}}},
                      {"certification", {{"tolerance", 1e-6}, {"diagonal", 2.0}}}};
  write(j.dump());
  const PoseSetManifest p = read_poseset_manifest(dir);
  EXPECT_EQ(p.levels.size(), 1u);
  EXPECT_TRUE(std::isnan(p.levels[0].target));
  EXPECT_EQ(p.fixed.path, "a.off");
  j["levels"][0].erase("spec");
  write(j.dump());
  EXPECT_NE(error_of([&] { read_poseset_manifest(dir); }).find("missing key 'levels[0].spec'"), std::string::npos);
}

// A pose set made as `cdbench poses locate_mesh_data/m.off -o runs/ps` from ROOT, read from elsewhere:
// the mesh is found from the pose set's parent directories, and only with the recorded content.
TEST(PoseSetManifest, LocatesARelativeMeshFromThePoseSetsParents) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(testing::TempDir()) / "locate_root";
  fs::remove_all(root);
  fs::create_directories(root / "locate_mesh_data");
  fs::create_directories(root / "runs" / "ps");
  const std::string mesh_file = (root / "locate_mesh_data" / "m.off").string();
  std::ofstream(mesh_file) << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  ASSERT_FALSE(fs::exists("locate_mesh_data/m.off"));  // not found from the current directory
  MeshRecord m{"locate_mesh_data/m.off", sha256_file(mesh_file), 3, 1, 1.0, Eigen::Vector3d::Zero()};
  const std::string ps = (root / "runs" / "ps").string();
  EXPECT_EQ(fs::canonical(locate_mesh(m, ps)), fs::canonical(mesh_file));
  // A path that exists as recorded is taken as it is (absolute here).
  MeshRecord absolute = m;
  absolute.path = mesh_file;
  EXPECT_EQ(locate_mesh(absolute, ps), mesh_file);
  // Another content under the same name: named, never used.
  MeshRecord other = m;
  other.sha256 = std::string(64, '0');
  EXPECT_NE(error_of([&] { locate_mesh(other, ps); }).find("SHA-256 mismatch"), std::string::npos);
  MeshRecord missing = m;
  missing.path = "locate_mesh_data/none.off";
  const std::string e = error_of([&] { locate_mesh(missing, ps); });
  EXPECT_NE(e.find("mesh locate_mesh_data/none.off not found"), std::string::npos) << e;
  EXPECT_NE(e.find("parent directories"), std::string::npos) << e;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh directory under the test's temporary directory, holding the torus the pose sets below use.
struct TorusDir {
  explicit TorusDir(const std::string& name) : dir(testing::TempDir() + "/" + name) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    write_off(torus, dir + "/torus.off");
  }
  std::string dir;
  TriangleMesh torus = make_torus(1.0, 0.35, 24, 12);
};

// Shards of a small pose set (a torus against itself, two levels), merged: the same poses.csv as
// the unsharded run, byte for byte, and the counts of all rows; then every bad set of shards is
// refused with its reason, and nothing is written for it.
TEST(MergeShards, EqualsTheUnshardedRunAndNamesBadShards) {
  const TorusDir t("merge_test");
  const std::string& dir = t.dir;
  const TriangleMesh& torus = t.torus;
  const auto run = [&](const std::string& out, const std::string& shard, std::size_t directions) {
    PoseSetRequest rq;
    rq.fixed = {dir + "/torus.off", &torus};
    rq.levels = "-10%,0";
    rq.out = dir + "/" + out;
    rq.directions = directions;
    rq.orientations = 2;
    rq.shard = shard;
    return build_poseset(rq);
  };
  run("whole", "0/1", 3);
  run("s0", "0/3", 3);
  run("s1", "1/3", 3);
  run("s2", "2/3", 3);
  const MergeResult m = merge_poseset_shards({dir + "/s2", dir + "/s0", dir + "/s1"}, dir + "/merged");
  EXPECT_EQ(m.shards, 3u);
  EXPECT_EQ(m.poses, 12u);
  EXPECT_EQ(read_text(dir + "/merged/poses.csv"), read_text(dir + "/whole/poses.csv"));
  const PoseSetManifest merged = read_poseset_manifest(dir + "/merged");
  const PoseSetManifest whole = read_poseset_manifest(dir + "/whole");
  for (const char* key : {"poses", "certified", "on_target", "no_contact", "mean_polish_steps"})
    for (std::size_t l = 0; l < 2; ++l) EXPECT_EQ(merged.json["levels"][l][key], whole.json["levels"][l][key]) << key;
  EXPECT_EQ(merged.json["shard"]["count"], 1);
  EXPECT_EQ(merged.json["run_key"], whole.json["run_key"]);

  const auto refused = [&](const std::vector<std::string>& shards) {
    const std::string out = dir + "/refused";
    std::filesystem::remove_all(out);
    const std::string e = error_of([&] { merge_poseset_shards(shards, out); });
    EXPECT_FALSE(std::filesystem::exists(out + "/poses.csv")) << e;
    return e;
  };
  EXPECT_NE(refused({dir + "/s0", dir + "/s1"}).find("missing shard(s) 2 of 3"), std::string::npos);
  EXPECT_NE(refused({dir + "/s0", dir + "/s1", dir + "/s1"}).find("shard 1 given twice"), std::string::npos);
  run("other", "2/3", 4);  // another run: the options differ
  EXPECT_NE(refused({dir + "/s0", dir + "/s1", dir + "/other"}).find("a shard of a different run"), std::string::npos);
  EXPECT_NE(refused({dir + "/s0", dir + "/whole"}).find("shard count differs"), std::string::npos);
  EXPECT_NE(refused({dir + "/torus.off"}).find("poseset.json"), std::string::npos);
  // A row of one shard copied into another: the pose appears twice.
  std::filesystem::copy(dir + "/s1", dir + "/s1dup", std::filesystem::copy_options::recursive);
  const std::string s0 = read_text(dir + "/s0/poses.csv");
  const std::string first_row = s0.substr(s0.find('\n') + 1, s0.find('\n', s0.find('\n') + 1) - s0.find('\n'));
  std::ofstream(dir + "/s1dup/poses.csv", std::ios::app) << first_row;
  EXPECT_NE(refused({dir + "/s0", dir + "/s1dup", dir + "/s2"}).find("appears in two shards"), std::string::npos);
}

// --start offset where a level's swept offset (target + 2 bands) lies within one band of the
// surface (or on it): that offset is the surface itself, so the level starts at the exact first
// contact with the surface and no offset is meshed; every pose certified all the same.
TEST(BuildPoseset, TargetsNearTheSurfaceStartAtTheSurfaceWithoutAnOffset) {
  const TorusDir t("near_band_test");
  const std::string& dir = t.dir;
  const TriangleMesh& torus = t.torus;
  const double diag = SignedDistance(torus).bbox().diagonal(), band = 1e-3 * diag;
  // Swept offsets (target + 2 band) at 1.5 band outside, band / 2 outside, 0 exactly (the builder's
  // 2.0 * 1e-3 * diag) and 1.5 band inside: none is meshed, every level starts at the surface.
  std::ostringstream levels;
  levels << std::setprecision(17) << -0.5 * band << "," << -1.5 * band << "," << -(2.0 * 1e-3 * diag) << ","
         << -3.5 * band;
  PoseSetRequest rq;
  rq.fixed = {dir + "/torus.off", &torus};
  rq.levels = levels.str();
  rq.out = dir + "/out";
  rq.directions = 3;
  rq.orientations = 1;
  rq.band_tolerance = 1e-3;
  rq.start = StartPolicy::Offsets;
  const PoseSetResult r = build_poseset(rq);
  ASSERT_EQ(r.poseset["levels"].size(), 4u);
  EXPECT_EQ(r.poseset["run_key"]["near_surface_start_bands"], kNearSurfaceBands);  // never resumed with the old start
  for (const auto& level : r.poseset["levels"]) {
    EXPECT_EQ(level["start"], "surface") << level.dump();
    EXPECT_TRUE(level["swept_offset"].is_null()) << level.dump();
    EXPECT_NE(level["start_note"].get<std::string>().find("within 4 bands of the surface"), std::string::npos)
        << level.dump();
    EXPECT_EQ(level["certified"], level["poses"]) << level.dump();
    EXPECT_EQ(level["poses"], 3);
  }
  if (std::filesystem::is_directory(dir + "/out/offsets")) {
    for (const auto& entry : std::filesystem::directory_iterator(dir + "/out/offsets"))
      EXPECT_NE(entry.path().extension(), ".off") << entry.path();
  }
}


// A request whose rows could not be held in memory is refused before any work, per shard.
TEST(BuildPoseset, RequestsBeyondAMemoryOfRowsAreRefusedPerShard) {
  PoseSetRequest r;
  r.levels = "-10%,0,10%";
  r.directions = 10000000;
  r.orientations = 10;
  try {
    check_poseset_request(r);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("3e+08 poses per shard"), std::string::npos) << m;
    EXPECT_NE(m.find("--shard"), std::string::npos) << m;
  }
  r.shard = "3/31";  // at most 3,225,807 approaches, 9,677,421 poses in a shard
  EXPECT_NO_THROW(check_poseset_request(r));
  r.shard = "3/30";  // up to 3,333,334 approaches: 10,000,002 poses
  EXPECT_THROW(check_poseset_request(r), InputError);
  r.shard = "0/1";
  r.directions = 1000;
  EXPECT_NO_THROW(check_poseset_request(r));
}

}  // namespace
}  // namespace cdbench

