#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <vector>

#include "distance/signed_distance.h"
#include "mesh/shapes.h"
#include "mesh/validate_mesh.h"
#include "offset/fast_signed_distance.h"
#include "offset/level_list.h"
#include "offset/offset_manifest.h"
#include "offset/mesh_level_set.h"
#include "offset/refine_offset.h"
#include "test_scale.h"
#include "util/error.h"
#include "util/number_format.h"

namespace cdbench {
namespace {

TEST(LevelList, AbsolutePercentAndRanges) {
  const auto l = parse_level_list("-0.5, 0.2,-80%,-25%:25%:25%");
  ASSERT_EQ(l.size(), 6u);
  EXPECT_EQ(l[0].value, -0.5);
  EXPECT_FALSE(l[0].percent);
  EXPECT_EQ(l[2].value, -80.0);
  EXPECT_TRUE(l[2].percent);
  EXPECT_EQ(l[3].value, -25.0);
  EXPECT_EQ(l[4].value, 0.0);
  EXPECT_EQ(l[5].value, 25.0);
  EXPECT_DOUBLE_EQ(level_distance(l[2], 2.0), -1.6);
  EXPECT_EQ(parse_level_list("0:1:0.1").size(), 11u);  // rounding must not drop the end point
}

TEST(LevelList, MaxPenetrationToleranceFollowsTheDeepestPercentage) {
  // |p| width <= tolerance for every percentage level, never below the floor.
  EXPECT_DOUBLE_EQ(max_penetration_tolerance_for(parse_level_list("-25%,0,10%"), 1e-6, 1e-6), 4e-6);
  EXPECT_DOUBLE_EQ(max_penetration_tolerance_for(parse_level_list("-20%,5%"), 1e-6, 1e-6), 5e-6);
  EXPECT_DOUBLE_EQ(max_penetration_tolerance_for(parse_level_list("-80%:0%:10%"), 1e-6, 1e-6), 1.25e-6);
  EXPECT_DOUBLE_EQ(max_penetration_tolerance_for(parse_level_list("-200%,0"), 1e-6, 1e-6), 1e-6);
  // No percentage: no target depends on M, which is only reported, at a coarser width.
  EXPECT_DOUBLE_EQ(max_penetration_tolerance_for(parse_level_list("-0.5,0,0.2"), 1e-6, 1e-6), kReportedMaxPenetrationWidth);
  EXPECT_DOUBLE_EQ(max_penetration_tolerance_for(parse_level_list("0"), 1e-5, 1e-6), kReportedMaxPenetrationWidth);
  EXPECT_DOUBLE_EQ(max_penetration_tolerance_for(parse_level_list("0"), 1e-5, 1e-3), 1e-3);
  EXPECT_DOUBLE_EQ(max_penetration_tolerance_for(parse_level_list("-50%,0.3"), 1e-5, 1e-6), 2e-5);
  // A coarse tolerance: never wider than the reported width (0.1 at -20 % would be half the
  // diagonal, M's lower end 0 and every percentage level at d = 0), unless the floor is.
  EXPECT_DOUBLE_EQ(max_penetration_tolerance_for(parse_level_list("-20%,0,5%"), 0.1, 1e-6), kReportedMaxPenetrationWidth);
  EXPECT_DOUBLE_EQ(max_penetration_tolerance_for(parse_level_list("-20%,0,5%"), 0.1, 1e-3), 1e-3);
}

TEST(LevelList, LevelsAtOneDistanceAreRefusedByName) {
  const auto message = [](const std::string& list, double max_penetration) -> std::string {
    const std::vector<LevelSpec> l = parse_level_list(list);
    std::vector<double> d;
    for (const LevelSpec& x : l) d.push_back(level_distance(x, max_penetration));
    try {
      check_distinct_distances(l, d);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(message("-20%,0,5%", 0.4), "");
  EXPECT_EQ(message("0.1,25%", 0.5), "");
  const std::string same = message("-0.1,0,0%", 0.4);
  EXPECT_NE(same.find("levels '0' and '0%' both lie at d = 0"), std::string::npos) << same;
  EXPECT_EQ(same.find("lower end"), std::string::npos) << same;
  const std::string scaled = message("5%,0.1,20%", 0.5);  // 20 % of 0.5 is 0.1
  EXPECT_NE(scaled.find("levels '0.1' and '20%' both lie at d = 0.1"), std::string::npos) << scaled;
  const std::string unscaled = message("5%,-20%,0", 0.0);
  EXPECT_NE(unscaled.find("levels '5%' and '-20%' both lie at d = 0"), std::string::npos) << unscaled;
  EXPECT_NE(unscaled.find("certified lower end is 0"), std::string::npos) << unscaled;
  EXPECT_NE(unscaled.find("ask for a smaller --tolerance"), std::string::npos) << unscaled;
}

TEST(LevelList, MaxPenetrationScaleNoteOnlyWhenAPercentageDependsOnAWideM) {
  const std::string note = max_penetration_scale_note(parse_level_list("-20%,0"), 1.43e-4, 5.66e-4, false, 5e-6);
  EXPECT_NE(note.find("lower end 0.000143"), std::string::npos) << note;
  EXPECT_NE(note.find("up to 3.96 times"), std::string::npos) << note;
  EXPECT_EQ(max_penetration_scale_note(parse_level_list("-20%,0"), 1.43e-4, 5.66e-4, true, 5e-6), "");
  EXPECT_EQ(max_penetration_scale_note(parse_level_list("-0.001,0,0%"), 1.43e-4, 5.66e-4, false, 5e-6), "");
}

// A percentage level within twice the tolerance of the surface (a solid thinner than the tolerance)
// is named with a tolerance that resolves it to a tenth; absolute levels and resolved ones are not.
TEST(LevelList, PercentageResolutionNoteForSolidsThinnerThanTheTolerance) {
  const std::vector<LevelSpec> l = parse_level_list("-20%,0,5%");
  const double m = 5e-6;  // a sheet 1e-5 thick, diagonal 1.4
  std::vector<double> d;
  for (const LevelSpec& x : l) d.push_back(level_distance(x, m));
  const std::string note = percentage_resolution_note(l, d, 1.4e-6, 1.4);
  EXPECT_NE(note.find("level '5%' lies 2.5e-07 from the surface"), std::string::npos) << note;
  EXPECT_NE(note.find("--tolerance 2e-08 resolves it"), std::string::npos) << note;
  EXPECT_EQ(percentage_resolution_note(l, d, 1e-7, 1.4), "");  // 2.5e-7 > 2 x 1e-7
  const std::vector<LevelSpec> a = parse_level_list("-1e-6,0,1e-7");
  EXPECT_EQ(percentage_resolution_note(a, {-1e-6, 0.0, 1e-7}, 1.4e-6, 1.4), "");
}

TEST(LevelList, ErrorsNameTheItem) {
  for (const char* bad : {"", "abc", "1,,2", "1:2", "1%:2:1", "2:1:0.5", "0:1:0", "0:1e9:1", "nan", "5%%"}) {
    try {
      parse_level_list(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--levels"), std::string::npos);
    }
  }
}

TEST(LevelList, AtMost10000LevelsInAll) {
  std::string ten = "0:1:0.001";
  EXPECT_EQ(parse_level_list(ten).size(), 1001u);
  for (int i = 0; i < 9; ++i) ten += ",0:1:0.001";
  EXPECT_THROW(parse_level_list(ten), InputError);  // 10,010 levels
}

TEST(LevelList, FarLevelsAreRefusedWithTheLimitNamed) {
  const LevelSpec near{5.0, false, "5"}, far{1e12, false, "1e12"};
  EXPECT_NO_THROW(check_level_reach(near, 5.0, 2.0));
  EXPECT_NO_THROW(check_level_reach(near, -0.99 * kMaxLevelDiagonals * 2.0, 2.0));
  try {
    check_level_reach(far, 1e12, 2.0);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'1e12' lies 5e+11 diagonals"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("|d| <= 20000 here"), std::string::npos) << e.what();
  }
  // The offset's face estimate: a sphere of radius R + d covered by facets of radius r.
  EXPECT_NEAR(estimated_offset_faces(1.0, 2.0, 0.01), 4.0 * M_PI * 4.0 / 4e-4, 1e-6);
  EXPECT_NEAR(estimated_offset_faces(-1.0, 2.0, 0.01), 4.0 * M_PI * 1.0 / 4e-4, 1e-6);
  EXPECT_NO_THROW(check_offset_level_size("1", 1.0, 2.0, 0.01));
  EXPECT_NO_THROW(check_offset_level_size("-1", -1.0, 2.0, 1e-4));  // inward: not estimated
  try {
    check_offset_level_size("100", 100.0, 2.0, 0.01);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("level '100'"), std::string::npos) << m;
    EXPECT_NE(m.find("--mesher-radius"), std::string::npos) << m;
    // The farthest level that fits, and it does fit.
    const double farthest = 0.02 * std::sqrt(kMaxOffsetFaces / (4.0 * M_PI)) - 1.0;
    EXPECT_NE(m.find("up to d = " + number_text(farthest, 4)), std::string::npos) << m;
    EXPECT_NO_THROW(check_offset_level_size("f", farthest * (1 - 1e-9), 2.0, 0.01));
    EXPECT_THROW(check_offset_level_size("f", farthest * (1 + 1e-6), 2.0, 0.01), InputError);
  }
}

TEST(OffsetManifest, ReusableEntriesOnlyFromAWellFormedManifest) {
  const std::string path = testing::TempDir() + "/manifest.json";
  const nlohmann::json good = {{"levels",
                                {{{"key", "k1"}, {"d", 0.1}, {"message", ""}, {"epsilon", 1e-3}, {"epsilon_over_diagonal", 1e-4},
                                  {"faces", 12}, {"status", "certified"}, {"file", "a.off"}, {"sha256", "00"}},
                                 {{"key", "k2"}, {"d", -5.0}, {"message", "empty"}, {"epsilon", nullptr},
                                  {"epsilon_over_diagonal", nullptr}, {"faces", 0}, {"status", "empty"},
                                  {"file", nullptr}, {"sha256", nullptr}}}}};
  std::ofstream(path) << good.dump();
  PreviousOffsets p = read_offset_manifest(path);
  EXPECT_TRUE(p.ignored_because.empty()) << p.ignored_because;
  ASSERT_EQ(p.by_key.size(), 2u);
  EXPECT_EQ(*p.by_key.at("k1").file, "a.off");
  EXPECT_FALSE(p.by_key.at("k2").file.has_value());
  // Typed as the builder uses them.
  EXPECT_EQ(p.by_key.at("k1").status, OffsetStatus::Certified);
  EXPECT_EQ(p.by_key.at("k1").epsilon, 1e-3);
  EXPECT_EQ(p.by_key.at("k1").faces, 12u);
  EXPECT_EQ(p.by_key.at("k2").status, OffsetStatus::Empty);
  EXPECT_TRUE(std::isnan(p.by_key.at("k2").epsilon));
  for (OffsetStatus s : {OffsetStatus::Certified, OffsetStatus::Empty, OffsetStatus::Original, OffsetStatus::Failed}) {
    OffsetStatus back = s == OffsetStatus::Failed ? OffsetStatus::Certified : OffsetStatus::Failed;
    EXPECT_TRUE(offset_status_from_string(to_string(s), &back));
    EXPECT_EQ(back, s);
  }
  OffsetStatus untouched = OffsetStatus::Original;
  EXPECT_FALSE(offset_status_from_string("Certified", &untouched));
  EXPECT_EQ(untouched, OffsetStatus::Original);
  for (const auto& [key, value] : std::vector<std::pair<std::string, nlohmann::json>>{
           {"faces", -1}, {"status", "maybe"}, {"file", "../x.off"}, {"file", nullptr}, {"d", "0.1"}}) {
    nlohmann::json bad = good;
    bad["levels"][0][key] = value;
    std::ofstream(path) << bad.dump();
    p = read_offset_manifest(path);
    EXPECT_TRUE(p.by_key.empty()) << key;
    EXPECT_NE(p.ignored_because.find("levels[0]." + key), std::string::npos) << p.ignored_because;
  }
  std::ofstream(path) << "{ not json";
  EXPECT_NE(read_offset_manifest(path).ignored_because.find("not valid JSON"), std::string::npos);
  EXPECT_TRUE(read_offset_manifest(path + ".missing").ignored_because.empty());
}

TEST(FastSignedDistance, AgreesWithTheCertifiedOne) {
  for (const TriangleMesh& m : {make_icosphere(1.0, 3), make_torus(2.0, 0.5, 32, 16)}) {
    const SignedDistance sdf(m);
    const FastSignedDistance fast(sdf);
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> u(-3, 3);
    for (int k = 0; k < 3000; ++k) {
      const Vec3 p{u(rng), u(rng), u(rng)};
      const Interval s = sdf.signed_distance(p);
      const double f = fast(p);
      EXPECT_GE(f, s.lo - 1e-12);
      EXPECT_LE(f, s.hi + 1e-12);
    }
  }
}

// Each query starts from the thread's previous nearest triangle: the value and gradient must still
// be the traversal's from scratch to the last bit (a fresh instance starts cold), or the mesher's
// output would depend on the order of its queries. Straight walks in small steps cross medial
// surfaces (a box's diagonal planes, a torus's core circle), where the nearest triangle switches.
// (A per-thread list of the triangles that can be nearest in a ball about an earlier query was
// tried against this test on 2026-11-26: identical output, but 30 % slower meshing.)
TEST(FastSignedDistance, NearbyQueriesGiveTheTraversalsResultExactly) {
  for (const TriangleMesh& mesh : {make_box(Vec3(-1.0, -0.5, -0.25), Vec3(1.0, 0.5, 0.25)), make_torus(1.0, 0.3, 40, 20),
                                   make_icosphere(1.0, 2)}) {
    const SignedDistance sdf(mesh);
    const FastSignedDistance warm(sdf);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int mismatches = 0;
    std::vector<Vec3> points;
    for (int walk = 0; walk < 30; ++walk) {
      Vec3 p{1.3 * u(rng), 1.3 * u(rng), 0.6 * u(rng)};
      const Vec3 dir = 0.01 * (1 + walk % 3) * Vec3{u(rng), u(rng), u(rng)}.normalized();
      for (int k = 0; k < 60; ++k) points.push_back(p += dir);
    }
    // The per-thread state belongs to one instance: the cold answers first, then the warm walk.
    std::vector<double> cold(points.size());
    std::vector<Vec3> cold_gradient(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
      cold[i] = FastSignedDistance(sdf).value_and_gradient(points[i], cold_gradient[i]);
    for (std::size_t i = 0; i < points.size(); ++i) {
      Vec3 g;
      const double a = warm.value_and_gradient(points[i], g);
      if (a != cold[i] || g != cold_gradient[i]) ++mismatches;
    }
    EXPECT_EQ(mismatches, 0);
  }
}

// Far from the mesh every triangle is nearest within rounding, and the pseudo-normal of whichever
// feature wins may point the wrong way: the mesher asks about circumcentres as far out as 1e17. A
// point outside the bounding box of a closed surface is outside it, whatever the features say.
TEST(FastSignedDistance, PointsFarOutsideArePositive) {
  for (const TriangleMesh& mesh : {make_box(Vec3(-1.0, -0.5, -0.25), Vec3(1.0, 0.5, 0.25)), make_torus(1.0, 0.3, 40, 20)}) {
    const SignedDistance sdf(mesh);
    const FastSignedDistance fast(sdf);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    int wrong = 0;
    for (int k = 0; k < 2000; ++k) {
      const Vec3 dir = Vec3{u(rng), u(rng), u(rng)}.normalized();
      const double far = std::pow(10.0, 2 + k % 16);
      // Mostly along an axis with a small offset: the ties the far query meets on flat faces.
      const Vec3 p = k % 2 == 0 ? Vec3{-far, 0.3 * u(rng), 0.2 * u(rng)} : Vec3(far * dir);
      if (!(fast(p) > 0.0)) ++wrong;
    }
    EXPECT_EQ(wrong, 0);
  }
}

// A new vertex of a repaired candidate in a sheet of the level set thinner than the band: the
// level set's nearest point is on the sheet's other side, the one along the face's normal is on the
// face's own side (boeing -20 %: placed by the gradient, new faces folded through old ones).
TEST(FastSignedDistance, PointsAlongARayReachTheSheetInFront) {
  // Slab |z| <= 0.1; the level -0.09 is the two planes z = +-0.01.
  const SignedDistance sdf(make_box(Vec3(-1.0, -1.0, -0.1), Vec3(1.0, 1.0, 0.1)));
  const FastSignedDistance fast(sdf);
  const double d = -0.09;
  const Vec3 x(0.2, -0.1, -0.003);  // inside the thin sheet, nearer its lower plane
  Vec3 near, along;
  ASSERT_TRUE(point_on_level_near(fast, d, x, near));
  EXPECT_NEAR(near.z(), -0.01, 1e-12);
  ASSERT_TRUE(point_on_level_along(fast, d, x, Vec3(0.0, 0.0, 1.0), 0.1, along));
  EXPECT_NEAR(along.z(), 0.01, 1e-12);
  EXPECT_NEAR(along.x(), x.x(), 1e-15);
  EXPECT_NEAR(fast(along), d, 1e-12);
  // Slanted rays too, from outside the sheet (the level set is then reached from above).
  const Vec3 above(0.0, 0.0, 0.05);
  const Vec3 u = Vec3(0.6, 0.0, -0.8);
  ASSERT_TRUE(point_on_level_along(fast, d, above, u, 1.0, along));
  EXPECT_NEAR(along.z(), 0.01, 1e-12);
  EXPECT_NEAR((along - above).normalized().dot(u), 1.0, 1e-9);
  // Not within the length asked for: no point.
  EXPECT_FALSE(point_on_level_along(fast, d, x, Vec3(0.0, 0.0, 1.0), 0.005, along));
}

// A new vertex of a repaired candidate beside a sharp crease of an inward level: the gradient
// points at F's nearest face, past the crease, so the Newton overshoots never change sign; the
// search all around the point finds the level (pinion -20 %: vertices left 1.1 tolerances off it).
TEST(FastSignedDistance, PointsBesideACreaseReachTheLevel) {
  const SignedDistance sdf(make_box(Vec3(-1.0, -1.0, -1.0), Vec3(1.0, 1.0, 1.0)));
  const FastSignedDistance fast(sdf);
  const double d = -0.5;  // the cube [-0.5, 0.5]^3, its edges creases
  const Vec3 x(0.6, 0.6, 0.05);  // s = -0.4, nearest to the faces x = 1 and y = 1 alike
  ASSERT_NEAR(fast(x) - d, 0.1, 1e-12);
  Vec3 on;
  EXPECT_FALSE(point_on_level_near(fast, d, x, on));
  ASSERT_TRUE(point_on_level_close(fast, d, x, on));
  EXPECT_NEAR(fast(on), d, 1e-12);
  EXPECT_LE((on - x).norm(), 0.2);  // the crease is 0.1414 away; a point on a diagonal ray 0.1732
  // Where the gradient's overshoot works, the same point as point_on_level_near.
  const Vec3 y(0.2, 0.1, 0.05);
  Vec3 near, close;
  ASSERT_TRUE(point_on_level_near(fast, d, y, near));
  ASSERT_TRUE(point_on_level_close(fast, d, y, close));
  EXPECT_EQ(near, close);
  // Nothing within reach: no point.
  EXPECT_FALSE(point_on_level_close(fast, -2.0, Vec3(0.0, 0.0, 0.0), on, 1));
}

// An edge across a crease of the level set (the cube's inward level, whose edges are creases): the
// point found is on the crease, exactly for two planes; the gradient's rule from the edge's midpoint
// lands on one face, 0.35 from it. Ends on one smooth sheet have no crease between them.
TEST(FastSignedDistance, ACreaseAcrossAnEdgeIsFound) {
  const SignedDistance sdf(make_box(Vec3(-1.0, -1.0, -1.0), Vec3(1.0, 1.0, 1.0)));
  const FastSignedDistance fast(sdf);
  const double d = -0.5;  // the cube [-0.5, 0.5]^3
  const Vec3 a(0.1, 0.5, -0.2), b(0.1, -0.1, 0.5);  // on its faces y = 0.5 and z = 0.5
  ASSERT_NEAR(fast(a) - d, 0.0, 1e-15);
  ASSERT_NEAR(fast(b) - d, 0.0, 1e-15);
  Vec3 on;
  ASSERT_TRUE(point_on_crease_across(fast, d, a, b, on));
  EXPECT_LT((on - Vec3(0.1, 0.5, 0.5)).norm(), 1e-9) << on.transpose();
  EXPECT_NEAR(fast(on), d, 1e-12);
  Vec3 by_gradient;
  ASSERT_TRUE(point_on_level_near(fast, d, 0.5 * (a + b), by_gradient));
  EXPECT_GT((by_gradient - Vec3(0.1, 0.5, 0.5)).norm(), 0.3);
  // Both ends on the face y = 0.5: the gradients agree, no crease.
  EXPECT_FALSE(point_on_crease_across(fast, d, a, Vec3(-0.3, 0.5, 0.1), on));
}

TEST(MeshLevelSet, SphereOffsetsAreValidAndNearTheLevel) {
  const TriangleMesh sphere = make_icosphere(1.0, 2);
  const SignedDistance sdf(sphere);
  const FastSignedDistance fast(sdf);
  for (double d : {-0.5, 0.3}) {
    const std::function<double(const Vec3&)> f = [&](const Vec3& p) { return fast(p) - d; };
    const std::vector<Vec3> seeds = level_set_seeds(f, Vec3::Zero(), 2.0 + d, 16);
    ASSERT_EQ(seeds.size(), 16u);
    for (const Vec3& p : seeds) EXPECT_NEAR(f(p), 0.0, 1e-12);
    LevelSetMeshOptions o;
    o.radius_bound = 0.1;
    o.distance_bound = 0.01;
    const TriangleMesh m = mesh_level_set(f, Vec3::Zero(), 2.0 + d, seeds, o);
    const ValidatedMesh v = validate_mesh(m);
    EXPECT_TRUE(v.report.valid());
    EXPECT_EQ(v.report.genus, 0);
    EXPECT_GT(m.faces.size(), 100u);
    for (const Vec3& p : m.vertices) EXPECT_NEAR(fast(p), d, 1e-6);
  }
}

// The mesher uses only the sign of f: answering signs from a Lipschitz bound must give the very
// same mesh with far fewer evaluations (a wrong sign, or a bound without the distance term, changes
// the bisections and so the vertices). Scaling f by 3 with L = 3 must not change anything either.
// The box's flat faces make flat tetrahedra whose circumcentres lie very far out (1e15 and more on
// machined parts): there the bound's rounding must be relative to the magnitudes, or a spurious
// sign appears and the box's meshes differ.
TEST(MeshLevelSet, LipschitzSignsGiveTheSameMeshWithFewerEvaluations) {
  struct Case {
    TriangleMesh mesh;
    Vec3 center;
    double radius, d;
  };
  const std::vector<Case> cases{{make_torus(1.0, 0.35, 48, 24), Vec3(1.0, 0.0, 0.0), 3.0, -0.1},
                                {make_torus(1.0, 0.35, 48, 24), Vec3(1.0, 0.0, 0.0), 3.0, 0.2},
                                {make_box(Vec3(-1.0, -0.5, -0.25), Vec3(1.0, 0.5, 0.25)), Vec3::Zero(), 2.0, 0.05}};
  for (const Case& c : cases) {
    const SignedDistance sdf(c.mesh);
    const FastSignedDistance fast(sdf);
    // One scale under the sanitizers: 3, where the Lipschitz constant is not the default 1.
    for (double scale : test_scale::pick<std::vector<double>>({1.0, 3.0}, {3.0})) {
      const std::function<double(const Vec3&)> f = [&](const Vec3& p) { return scale * (fast(p) - c.d); };
      const std::vector<Vec3> seeds = level_set_seeds(f, c.center, c.radius, 32);
      LevelSetMeshOptions o;
      o.radius_bound = 0.15;
      o.distance_bound = 0.01;
      o.bisection_relative_error = 1e-6;
      LevelSetMeshStats plain, skipped;
      const TriangleMesh a = mesh_level_set(f, c.center, c.radius, seeds, o, &plain);
      o.lipschitz = scale;
      const TriangleMesh b = mesh_level_set(f, c.center, c.radius, seeds, o, &skipped);
      ASSERT_GT(a.faces.size(), 300u);
      EXPECT_EQ(a.faces, b.faces) << "d = " << c.d << ", scale " << scale;
      EXPECT_EQ(a.vertices, b.vertices) << "d = " << c.d << ", scale " << scale;
      EXPECT_EQ(plain.lipschitz, 0u);
      EXPECT_EQ(plain.calls, skipped.calls);  // the same questions, so the same bisections
      EXPECT_GT(skipped.lipschitz, plain.calls / 2);
      EXPECT_LT(skipped.evaluations * 2, plain.evaluations);
      EXPECT_TRUE(validate_mesh(b).report.valid());
    }
  }
}

// Mesh_3 in parallel mode as the candidate mesher: valid closed surfaces of the right topology,
// vertices on the level, about as many faces as Surface_mesher's for the same criteria, and only
// the components that hold a seed (no random initial points: Mesh_3's own loop without bound on
// an empty level and miss small components).
TEST(MeshLevelSet, ParallelMesherMeshesTheSeededComponents) {
  const TriangleMesh two = merge_meshes(make_torus(1.0, 0.35, 48, 24), make_icosphere(0.5, 2, Vec3(4.0, 0.0, 0.0)));
  const SignedDistance sdf(two);
  const FastSignedDistance fast(sdf);
  // One level under the sanitizers (the same code paths; the other side costs as much again).
  for (double d : test_scale::pick<std::vector<double>>({-0.1, 0.2}, {0.2})) {
    const std::function<double(const Vec3&)> f = [&](const Vec3& p) { return fast(p) - d; };
    std::vector<Vec3> torus_seeds = level_set_seeds(f, Vec3(1.0, 0.0, 0.0), 1.5, 32);
    std::vector<Vec3> all = torus_seeds;
    for (const Vec3& p : level_set_seeds(f, Vec3(4.0, 0.0, 0.0), 1.0, 16)) all.push_back(p);
    LevelSetMeshOptions o;
    o.radius_bound = 0.15;
    o.distance_bound = 0.01;
    o.bisection_relative_error = 1e-6;
    o.lipschitz = 1.0;
    const TriangleMesh serial = mesh_level_set(f, Vec3(2.0, 0.0, 0.0), 4.0, all, o);
    const TriangleMesh both = mesh_level_set_parallel(f, Vec3(2.0, 0.0, 0.0), 4.0, all, o);
    const TriangleMesh one = mesh_level_set_parallel(f, Vec3(2.0, 0.0, 0.0), 4.0, torus_seeds, o);
    const ValidatedMesh vb = validate_mesh(both), vo = validate_mesh(one);
    ASSERT_TRUE(vb.report.valid()) << vb.report.errors[0].message;
    ASSERT_TRUE(vo.report.valid()) << vo.report.errors[0].message;
    EXPECT_EQ(vb.report.components, 2u) << "d = " << d;
    EXPECT_EQ(vb.report.genus, 1) << "d = " << d;  // the torus's hole, plus a sphere
    EXPECT_EQ(vo.report.components, 1u) << "d = " << d;
    EXPECT_EQ(vo.report.genus, 1) << "d = " << d;
    EXPECT_GT(both.faces.size(), serial.faces.size() * 7 / 10);
    EXPECT_LT(both.faces.size(), serial.faces.size() * 13 / 10);
    for (const Vec3& p : both.vertices) EXPECT_NEAR(fast(p), d, 1e-5);
  }
}

// Red-green refinement: the split mesh is conforming (a T-junction would leave boundary edges, which
// validation reports), oriented like the input (volume unchanged for flat midpoints), and keeps
// the unmarked faces that have no split edge exactly.
TEST(RefineFaces, ConformingOrientedAndKeepsTheRest) {
  const TriangleMesh sphere = make_icosphere(1.0, 2);
  const ValidatedMesh before = validate_mesh(sphere);
  ASSERT_TRUE(before.report.valid());
  for (std::size_t stride : {1u, 2u, 7u, 50u}) {
    std::vector<char> wide(sphere.faces.size(), 0);
    for (std::size_t i = 0; i < wide.size(); i += stride) wide[i] = 1;
    const RefinedMesh r = refine_faces(sphere, wide, [](const Vec3& a, const Vec3& b, const Vec3&) { return 0.5 * (a + b); });
    const ValidatedMesh after = validate_mesh(r.mesh);
    ASSERT_TRUE(after.report.valid()) << "stride " << stride << ": " << after.report.errors[0].message;
    EXPECT_EQ(after.report.genus, 0);
    EXPECT_EQ(after.mesh.faces, r.mesh.faces) << "validation had to change the refined mesh";
    EXPECT_NEAR(after.report.volume_lo, before.report.volume_lo, 1e-12);
    ASSERT_EQ(r.is_new.size(), r.mesh.faces.size());
    std::size_t kept = 0, added = 0;
    for (std::size_t i = 0; i < r.mesh.faces.size(); ++i) {
      if (r.is_new[i]) { ++added; continue; }
      ++kept;
      EXPECT_FALSE(wide[r.kept_from[i]]);
      EXPECT_EQ(r.mesh.faces[i], sphere.faces[r.kept_from[i]]);
    }
    // Each split face becomes 4 or 2, each split edge adds one vertex: V - E + F stays 2.
    EXPECT_EQ(r.mesh.vertices.size(), sphere.vertices.size() + r.split_edges);
    // Where each new vertex came from (the repair places a folding one again from its edge).
    ASSERT_EQ(r.first_new_vertex, sphere.vertices.size());
    ASSERT_EQ(r.new_vertex_edge.size(), r.split_edges);
    ASSERT_EQ(r.new_vertex_normal.size(), r.split_edges);
    for (std::size_t k = 0; k < r.split_edges; ++k) {
      const auto [a, b] = r.new_vertex_edge[k];
      EXPECT_EQ(r.mesh.vertices[r.first_new_vertex + k], Vec3(0.5 * (sphere.vertices[a] + sphere.vertices[b])));
      // The sum of two outward unit normals of a convex surface points outwards, along the edge's midpoint.
      EXPECT_GT(r.new_vertex_normal[k].dot(sphere.vertices[a] + sphere.vertices[b]), 0.0);
    }
    EXPECT_GE(added, 4 * static_cast<std::size_t>(std::count(wide.begin(), wide.end(), 1)));
    if (stride == 1) {
      EXPECT_EQ(kept, 0u);
    }
    if (stride == 50) {
      EXPECT_GT(kept, sphere.faces.size() / 2);
    }
  }
}

}  // namespace
}  // namespace cdbench
