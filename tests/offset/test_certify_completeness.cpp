#include <gtest/gtest.h>

#include <chrono>
#include <iomanip>
#include <random>
#include <thread>
#include <vector>

#include "mesh/shapes.h"
#include "mesh/validate_mesh.h"
#include "offset/certify_band.h"
#include "offset/certify_completeness.h"
#include "offset/fast_signed_distance.h"
#include "offset/mesh_level_set.h"
#include "test_scale.h"

namespace cdbench {
namespace {

TriangleMesh offset_near(const SignedDistance& sdf, const Vec3& center, double radius, double d) {
  const FastSignedDistance fast(sdf);
  const std::function<double(const Vec3&)> f = [&](const Vec3& p) { return fast(p) - d; };
  LevelSetMeshOptions o;
  o.radius_bound = 0.25;
  o.distance_bound = 0.01;
  return mesh_level_set(f, center, radius, level_set_seeds(f, center, radius, 32), o);
}

// An offset mesh of the level set near `center`, its certified band and the search against it.
struct NearSearch {
  TriangleMesh mesh;
  double eps = 0.0;
  CompletenessResult result;
};
NearSearch search_near(const SignedDistance& sdf, const Vec3& center, double radius, double d) {
  NearSearch n;
  n.mesh = offset_near(sdf, center, radius, d);
  n.eps = certify_band(sdf, n.mesh, d, BandOptions{}).epsilon;
  n.result = certify_completeness(sdf, n.mesh, d, n.eps);
  return n;
}

// A complete search's discarded cells tile its domain (their volumes add up to the domain's).
void expect_tiled(const CompletenessResult& r) {
  ASSERT_TRUE(r.complete);
  EXPECT_GT(r.domain_volume, 0.0);
  EXPECT_NEAR(r.discarded_volume / r.domain_volume, 1.0, 1e-9);
}

TEST(CertifyCompleteness, SphereOffsetsAreComplete) {
  const SignedDistance sdf(make_icosphere(1.0, 2));
  for (double d : {-0.4, 0.3}) {
    const TriangleMesh m = offset_near(sdf, Vec3::Zero(), 3.0, d);
    const double eps = certify_band(sdf, m, d, BandOptions{}).epsilon;
    const CompletenessResult r = certify_completeness(sdf, m, d, eps);
    EXPECT_TRUE(r.complete) << "missed " << r.missed.size() << ", unresolved " << r.unresolved.size();
    expect_tiled(r);
  }
}

// The cell budget is a bound, not a target: a search never evaluates more cells than it allows (a
// level that does not fit, or children that would not, stop it), and one that fits is unchanged.
TEST(CertifyCompleteness, TheCellBudgetIsNeverExceeded) {
  const SignedDistance sdf(make_icosphere(1.0, 2));
  const double d = 0.3;
  const NearSearch near = search_near(sdf, Vec3::Zero(), 3.0, d);
  const TriangleMesh& m = near.mesh;
  const double eps = near.eps;
  const CompletenessResult& full = near.result;
  ASSERT_TRUE(full.complete);
  ASSERT_GT(full.cells, 1000u);  // more than the first level (512 cells)
  CompletenessOptions o;
  o.max_cells = full.cells;  // just enough: the same search
  const CompletenessResult exact = certify_completeness(sdf, m, d, eps, o);
  EXPECT_TRUE(exact.complete);
  EXPECT_FALSE(exact.budget_exhausted);
  EXPECT_EQ(budget_note(exact), "");
  EXPECT_EQ(exact.cells, full.cells);
  for (std::uint64_t budget : {full.cells - 1, full.cells / 2, full.cells / 7, std::uint64_t{600}, std::uint64_t{100}}) {
    o.max_cells = budget;
    const CompletenessResult r = certify_completeness(sdf, m, d, eps, o);
    EXPECT_FALSE(r.complete) << "budget " << budget;
    EXPECT_TRUE(r.budget_exhausted) << "budget " << budget;
    EXPECT_EQ(budget_note(r), " (cell budget reached after " + std::to_string(r.cells) + " cells)");
    EXPECT_LE(r.cells, budget);
    EXPECT_FALSE(r.unresolved.empty()) << "budget " << budget;  // where the search stopped
    EXPECT_TRUE(r.missed.empty());
  }
}

TEST(CertifyCompleteness, DroppedComponentIsFound) {
  // Two balls; an offset mesh of only the first must be reported incomplete, near the second.
  const TriangleMesh two = merge_meshes(make_icosphere(1.0, 2), make_icosphere(0.6, 2, Vec3(4, 0, 0)));
  const SignedDistance sdf(two);
  const double d = -0.2;
  const NearSearch near = search_near(sdf, Vec3::Zero(), 1.5, d);
  const TriangleMesh& first = near.mesh;
  const CompletenessResult& r = near.result;
  EXPECT_FALSE(r.complete);
  ASSERT_FALSE(r.missed.empty());
  EXPECT_NEAR(r.missed[0].x(), 4.0, 0.6);
  // With both components meshed it is complete.
  TriangleMesh both = merge_meshes(first, offset_near(sdf, Vec3(4, 0, 0), 1.0, d));
  const double eps2 = certify_band(sdf, both, d, BandOptions{}).epsilon;
  EXPECT_TRUE(certify_completeness(sdf, both, d, eps2).complete);
}

// Missed regions found at the same depth of the search are all reported, whatever their order
// and size: the reported points are spread over the missed cells (one per region first), so a
// large region does not crowd a small one out of the 64 points that seed the next attempt.
TEST(CertifyCompleteness, EveryMissedRegionIsReported) {
  const TriangleMesh three = merge_meshes(merge_meshes(make_icosphere(1.0, 2), make_icosphere(1.5, 2, Vec3(0, 0, -5))),
                                          make_icosphere(1.2, 2, Vec3(0, 0, 5)));
  const SignedDistance sdf(three);
  const CompletenessResult r = search_near(sdf, Vec3::Zero(), 1.5, -0.2).result;
  EXPECT_FALSE(r.complete);
  ASSERT_FALSE(r.missed.empty());
  EXPECT_LE(r.missed.size(), 64u);
  int low = 0, high = 0;
  for (const Vec3& x : r.missed) {
    low += (x - Vec3(0, 0, -5)).norm() < 1.5;
    high += (x - Vec3(0, 0, 5)).norm() < 1.2;
  }
  EXPECT_EQ(low + high, static_cast<int>(r.missed.size()));  // each in a missed ball
  EXPECT_GT(low, 0);
  EXPECT_GT(high, 0);
  std::printf("missed points reported: %zu (%d in the lower ball, %d in the upper)\n", r.missed.size(), low, high);
}

// Above the band (d - eps > 0) a missing component is found through one point inside each
// component of the solid, before any cell is searched; with it meshed the level is complete.
TEST(CertifyCompleteness, OutwardLevelMissingComponentIsFoundFromTheSolid) {
  const TriangleMesh two = merge_meshes(make_icosphere(1.0, 2), make_icosphere(0.6, 2, Vec3(4, 0, 0)));
  const SignedDistance sdf(two);
  const double d = 0.15;
  const TriangleMesh first = offset_near(sdf, Vec3::Zero(), 1.5, d);
  const double eps = certify_band(sdf, first, d, BandOptions{}).epsilon;
  ASSERT_LT(eps, d);
  const CompletenessResult r = certify_completeness(sdf, first, d, eps);
  EXPECT_FALSE(r.complete);
  ASSERT_FALSE(r.missed.empty());
  EXPECT_EQ(r.cells, 0u);
  EXPECT_NEAR(r.missed[0].x(), 4.0, 0.6);
  const TriangleMesh both = merge_meshes(first, offset_near(sdf, Vec3(4, 0, 0), 1.0, d));
  const double eps2 = certify_band(sdf, both, d, BandOptions{}).epsilon;
  const CompletenessResult r2 = certify_completeness(sdf, both, d, eps2);
  EXPECT_TRUE(r2.complete) << "missed " << r2.missed.size() << ", unresolved " << r2.unresolved.size();
}

// Below the band (d + eps < 0) the exterior's components are checked the same way: a hollow ball's
// cavity is a bounded component of the exterior, and an inner offset without the surface around
// it leaves the cavity (where s > 0 > d + eps) inside S_d.
TEST(CertifyCompleteness, InwardLevelMissingCavityIsFoundFromTheExterior) {
  TriangleMesh cavity = make_icosphere(0.5, 3);
  for (Face& f : cavity.faces) std::swap(f[1], f[2]);
  const ValidatedMesh hollow = validate_mesh(merge_meshes(make_icosphere(1.0, 3), cavity));
  ASSERT_TRUE(hollow.report.valid());
  const SignedDistance sdf(hollow.mesh);
  const double d = -0.1;
  const TriangleMesh outer = make_icosphere(0.9, 3);  // the level set is near |x| = 0.9 and |x| = 0.6
  const double eps = certify_band(sdf, outer, d, BandOptions{}).epsilon;
  ASSERT_LT(eps, 0.05);
  const CompletenessResult r = certify_completeness(sdf, outer, d, eps);
  EXPECT_FALSE(r.complete);
  ASSERT_FALSE(r.missed.empty());
  EXPECT_EQ(r.cells, 0u);
  EXPECT_LT(r.missed[0].norm(), 0.5);
  TriangleMesh inner = make_icosphere(0.6, 3);
  for (Face& f : inner.faces) std::swap(f[1], f[2]);
  const TriangleMesh both = merge_meshes(outer, inner);
  const double eps2 = certify_band(sdf, both, d, BandOptions{}).epsilon;
  ASSERT_LT(eps2, 0.05);
  const CompletenessResult r2 = certify_completeness(sdf, both, d, eps2);
  EXPECT_TRUE(r2.complete) << "missed " << r2.missed.size() << ", unresolved " << r2.unresolved.size();
}

// A first search against `first`, stopped by a missed region, then the union with `added` (its
// offset of the missing part, or not quite) searched afresh and resumed from the first.
struct Resumption {
  double eps = 0.0, eps2 = 0.0;  // the first part's band, the union's
  CompletenessResult first, fresh, resumed;
};
Resumption search_then_resume(const SignedDistance& sdf, const TriangleMesh& first, const TriangleMesh& added,
                              double d, const CompletenessOptions& o = {}) {
  Resumption r;
  r.eps = certify_band(sdf, first, d, BandOptions{}).epsilon;
  r.eps2 = std::max(r.eps, certify_band(sdf, added, d, BandOptions{}).epsilon);
  CompletenessCheckpoint checkpoint;
  r.first = certify_completeness(sdf, first, d, r.eps, o, &checkpoint);
  EXPECT_FALSE(r.first.complete);
  EXPECT_FALSE(r.first.missed.empty());
  EXPECT_TRUE(checkpoint.state);
  const TriangleMesh both = merge_meshes(first, added);
  r.fresh = certify_completeness(sdf, both, d, r.eps2, o);
  r.resumed = resume_completeness(sdf, both, added, d, r.eps2, checkpoint, o);
  EXPECT_FALSE(checkpoint.state);  // consumed
  EXPECT_TRUE(r.resumed.resumed);
  std::printf("cells: first search %llu, resumed %llu, fresh %llu\n", static_cast<unsigned long long>(r.first.cells),
              static_cast<unsigned long long>(r.resumed.cells), static_cast<unsigned long long>(r.fresh.cells));
  return r;
}

// A search stopped by a missed component, taken up once that component's offset is added: complete
// like a fresh search of the union, with fewer cells (those set aside far from the added part are
// not examined again), its leaves and the first search's kept ones tiling the domain.
TEST(ResumeCompleteness, AddedComponentCompletesTheSearch) {
  const TriangleMesh two = merge_meshes(make_icosphere(1.0, 2), make_icosphere(0.6, 2, Vec3(4, 0, 0)));
  const SignedDistance sdf(two);
  const double d = -0.2;
  const TriangleMesh first = offset_near(sdf, Vec3::Zero(), 1.5, d);
  const TriangleMesh island = offset_near(sdf, Vec3(4, 0, 0), 1.0, d);
  const Resumption r = search_then_resume(sdf, first, island, d);
  expect_tiled(r.fresh);
  expect_tiled(r.resumed);
  EXPECT_LT(r.resumed.cells, r.fresh.cells);
  // Without a checkpoint, or with a narrower band than the first search's, it is a fresh search.
  const TriangleMesh both = merge_meshes(first, island);
  CompletenessCheckpoint none;
  const CompletenessResult again = resume_completeness(sdf, both, island, d, r.eps2, none);
  EXPECT_FALSE(again.resumed);
  EXPECT_TRUE(again.complete);
  EXPECT_EQ(again.cells, r.fresh.cells);
  CompletenessCheckpoint second;
  certify_completeness(sdf, first, d, r.eps, {}, &second);
  ASSERT_TRUE(second.state);
  EXPECT_FALSE(resume_completeness(sdf, both, island, d, 0.5 * r.eps, second).resumed);
}

// Two balls missed at the same depth, one added: the resumed search still finds the other.
TEST(ResumeCompleteness, AComponentStillMissingIsFound) {
  const TriangleMesh three = merge_meshes(merge_meshes(make_icosphere(1.0, 2), make_icosphere(1.5, 2, Vec3(0, 0, -5))),
                                          make_icosphere(1.2, 2, Vec3(0, 0, 5)));
  const SignedDistance sdf(three);
  const double d = -0.2;
  const Resumption r =
      search_then_resume(sdf, offset_near(sdf, Vec3::Zero(), 1.5, d), offset_near(sdf, Vec3(0, 0, -5), 2.0, d), d);
  EXPECT_FALSE(r.fresh.complete);
  EXPECT_FALSE(r.resumed.complete);
  ASSERT_FALSE(r.resumed.missed.empty());
  for (const Vec3& x : r.resumed.missed) EXPECT_LT((x - Vec3(0, 0, 5)).norm(), 1.2) << x.transpose();
}

// The same search, cell for cell, with and without F's facts prefetched (all of them, part, none).
void expect_same_search(const CompletenessResult& a, const CompletenessResult& b) {
  EXPECT_EQ(a.complete, b.complete);
  EXPECT_EQ(a.cells, b.cells);
  EXPECT_EQ(a.budget_exhausted, b.budget_exhausted);
  EXPECT_EQ(a.resumed, b.resumed);
  EXPECT_EQ(a.discarded_volume, b.discarded_volume);
  ASSERT_EQ(a.missed.size(), b.missed.size());
  for (std::size_t i = 0; i < a.missed.size(); ++i) EXPECT_EQ(a.missed[i], b.missed[i]);
  ASSERT_EQ(a.unresolved.size(), b.unresolved.size());
  for (std::size_t i = 0; i < a.unresolved.size(); ++i) EXPECT_EQ(a.unresolved[i], b.unresolved[i]);
}

// A search takes F's facts from a prefetch made for its level and gets the same cells, verdicts
// and results however far the prefetch got: finished, stopped by its budget, stopped at once, or
// stopped by another thread at an arbitrary cell. Inward and outward levels, complete or not, and a
// search resumed after the missed part is added. A prefetch for another level is not used.
TEST(CompletenessPrefetch, TheSearchIsTheSameHoweverFarItGot) {
  const TriangleMesh two = merge_meshes(make_torus(1.0, 0.4, 32, 16), make_icosphere(0.6, 2, Vec3(6, 0, 0)));
  const SignedDistance sdf(two);
  // Under the sanitizers (14x slower here: 114 s) the outward level alone, whose search is half
  // the inward one's, and the resumed searches' other prefetches once: the same code paths.
  for (double d : test_scale::pick<std::vector<double>>({-0.15, 0.2}, {0.2})) {
    SCOPED_TRACE("d = " + std::to_string(d));
    const TriangleMesh torus_part = offset_near(sdf, Vec3(1.0, 0, 0), 2.6, d);
    const TriangleMesh ball_part = offset_near(sdf, Vec3(6, 0, 0), 1.2, d);
    const double eps = std::max(certify_band(sdf, torus_part, d, BandOptions{}).epsilon,
                                certify_band(sdf, ball_part, d, BandOptions{}).epsilon);
    const TriangleMesh both = merge_meshes(torus_part, ball_part);
    CompletenessOptions o;
    o.band_bound = 2.0 * eps;
    CompletenessCheckpoint cp_plain;
    const CompletenessResult plain_first = certify_completeness(sdf, torus_part, d, eps, o, &cp_plain);
    const CompletenessResult plain = certify_completeness(sdf, both, d, eps, o);
    const CompletenessResult plain_resumed = resume_completeness(sdf, both, ball_part, d, eps, cp_plain, o);
    ASSERT_FALSE(plain_first.complete);
    ASSERT_TRUE(plain.complete);
    ASSERT_TRUE(plain_resumed.complete);
    EXPECT_EQ(plain.prefetched, 0u);
    std::atomic<bool> stop{false};
    for (int how = 0; how < 4; ++how) {
      SCOPED_TRACE("prefetch " + std::to_string(how));
      CompletenessPrefetch prefetch(sdf, d, o.band_bound, how == 1 ? 3000 : 8000000);
      if (how == 0 || how == 1) {
        prefetch.run(stop);
        EXPECT_TRUE(prefetch.finished());
      } else if (how == 3) {
        std::atomic<bool> stop_soon{false};
        std::thread stopper([&] {
          std::this_thread::sleep_for(std::chrono::milliseconds(3));
          stop_soon = true;
        });
        prefetch.run(stop_soon);
        stopper.join();
      }
      CompletenessOptions with = o;
      with.prefetch = &prefetch;
      CompletenessCheckpoint cp;
      const CompletenessResult first = certify_completeness(sdf, torus_part, d, eps, with, &cp);
      const CompletenessResult whole = certify_completeness(sdf, both, d, eps, with);
      const CompletenessResult resumed = resume_completeness(sdf, both, ball_part, d, eps, cp, with);
      expect_same_search(first, plain_first);
      expect_same_search(whole, plain);
      expect_same_search(resumed, plain_resumed);
      if (how == 0) {
        // Most cells' facts came from it, not all: the search splits cells next to S_d that the
        // prefetch could not know to expand.
        EXPECT_GT(whole.prefetched, whole.cells / 2) << whole.prefetched << " of " << whole.cells;
        std::printf("d %g: prefetch %llu cells, the search %llu of %llu from it\n", d,
                    static_cast<unsigned long long>(prefetch.cells()), static_cast<unsigned long long>(whole.prefetched),
                    static_cast<unsigned long long>(whole.cells));
      }
      if (how == 2) {
        EXPECT_EQ(whole.prefetched, 0u);
      }
      // Resumed with another prefetch of the level (smaller: the first one's node numbers mean
      // nothing in it) or with none: the same search.
      for (int resume_with = 0; resume_with < 2 && (how == 0 || !test_scale::kSanitized); ++resume_with) {
        CompletenessPrefetch small(sdf, d, o.band_bound, 3000);
        small.run(stop);
        CompletenessOptions other_options = o;
        if (resume_with == 0) other_options.prefetch = &small;
        CompletenessCheckpoint again;
        certify_completeness(sdf, torus_part, d, eps, with, &again);
        expect_same_search(resume_completeness(sdf, both, ball_part, d, eps, again, other_options), plain_resumed);
      }
      // Another level's prefetch is not used.
      CompletenessPrefetch other(sdf, 0.9 * d, o.band_bound);
      other.run(stop);
      with.prefetch = &other;
      const CompletenessResult not_used = certify_completeness(sdf, both, d, eps, with);
      EXPECT_EQ(not_used.prefetched, 0u);
      expect_same_search(not_used, plain);
    }
  }
}

// A hollow ball (outer radius `outer`, a cavity of radius 0.5 about `at`), for both sides searched.
TriangleMesh hollow_ball(double outer, const Vec3& at) {
  TriangleMesh cavity = make_icosphere(0.5, 3, at);
  for (Face& f : cavity.faces) std::swap(f[1], f[2]);
  const ValidatedMesh hollow = validate_mesh(merge_meshes(make_icosphere(outer, 3, at), cavity));
  EXPECT_TRUE(hollow.report.valid());
  return hollow.mesh;
}

CompletenessOptions both_sides() {
  CompletenessOptions o;
  o.one_sided = false;
  return o;
}

// Both sides searched (no one-sided shortcut): a hollow ball's inner offset (about its cavity)
// missing, the search stops at cells of the cavity inside the outer offset; with the inner offset
// added the resumed search replays the cells about it (set aside by rule (2) against the outer
// offset alone) and completes, as a fresh search does.
TEST(ResumeCompleteness, BothSidesAboutAnAddedInnerOffset) {
  const SignedDistance sdf(hollow_ball(2.0, Vec3::Zero()));
  TriangleMesh inner = make_icosphere(0.6, 3);
  for (Face& f : inner.faces) std::swap(f[1], f[2]);
  const Resumption r = search_then_resume(sdf, make_icosphere(1.9, 3), inner, -0.1, both_sides());
  ASSERT_LT(r.eps2, 0.05);
  EXPECT_GT(r.first.cells, 0u);
  ASSERT_FALSE(r.first.missed.empty());
  EXPECT_LT(r.first.missed[0].norm(), 0.6);
  expect_tiled(r.fresh);
  expect_tiled(r.resumed);
  EXPECT_LT(r.resumed.cells, r.fresh.cells);
}

// The cells the first search set aside by rule (2) near the added parts are examined again: a
// sphere within the band nested inside a ball's (correct) offset leaves the ball's deep core outside
// the union, which the first search had set aside as inside the offset. The resumed search must
// find it, as a fresh one does (stopped first by a small ball's missing offset, far away).
TEST(ResumeCompleteness, CellsSetAsideNearTheAddedPartsAreExaminedAgain) {
  const TriangleMesh two = merge_meshes(make_icosphere(2.0, 3), make_icosphere(0.6, 2, Vec3(5, 0, 0)));
  const SignedDistance sdf(two);
  const double d = -0.5;
  const TriangleMesh first = make_icosphere(1.5, 3);
  double inscribed = 1.5;  // of the first sphere's faces
  for (const Face& f : first.faces) {
    const Vec3 &a = first.vertices[f[0]], &b = first.vertices[f[1]], &c = first.vertices[f[2]];
    inscribed = std::min(inscribed, std::abs((b - a).cross(c - a).normalized().dot(a)));
  }
  TriangleMesh nested = make_icosphere(0.999 * inscribed, 3);
  for (Face& f : nested.faces) std::swap(f[1], f[2]);
  const TriangleMesh added = merge_meshes(nested, offset_near(sdf, Vec3(5, 0, 0), 1.0, d));
  const TriangleMesh both = merge_meshes(first, added);
  const ValidatedMesh v = validate_mesh(both);
  ASSERT_TRUE(v.report.valid());
  ASSERT_EQ(v.mesh.faces, both.faces);  // nested parts, oriented as given
  const Resumption r = search_then_resume(sdf, first, added, d);
  ASSERT_LT(r.eps2, 0.2);  // the core |x| < 1.5 - eps2 is in A
  ASSERT_FALSE(r.first.missed.empty());
  EXPECT_GT(r.first.missed[0].x(), 4.0);
  EXPECT_FALSE(r.fresh.complete);
  EXPECT_FALSE(r.resumed.complete);
  ASSERT_FALSE(r.resumed.missed.empty());
  for (const Vec3& x : r.resumed.missed) EXPECT_LT(x.norm(), 1.5) << x.transpose();
}

// Both sides searched, a far hollow ball's two inner offsets missing: with only the outer one
// added, the resumed search still finds its cavity inside the union.
TEST(ResumeCompleteness, AnAddedPartsCavityIsSearchedAgain) {
  const SignedDistance sdf(merge_meshes(make_icosphere(1.0, 2), hollow_ball(1.2, Vec3(5, 0, 0))));
  const double d = -0.1;
  const Resumption r = search_then_resume(sdf, offset_near(sdf, Vec3::Zero(), 1.5, d),
                                          make_icosphere(1.1, 3, Vec3(5, 0, 0)), d, both_sides());
  ASSERT_LT(r.eps2, 0.05);
  EXPECT_FALSE(r.fresh.complete);
  EXPECT_FALSE(r.resumed.complete);
  ASSERT_FALSE(r.resumed.missed.empty());
  for (const Vec3& x : r.resumed.missed) EXPECT_LT((x - Vec3(5, 0, 0)).norm(), 0.6) << x.transpose();
}

// An L-shaped prism: its reflex edge along z at (1, 1) is where the disc bound fails (both walls'
// parts in the ball reach past the cell). Every cell the test accepts must have, at sampled points,
// w.(x - p) > 0 for the nearest points p, for the heuristic w and for random directions; and the
// cells near the reflex edge (outside) and near the convex edges (inside) must be accepted, which
// the disc bound alone does not do.
TriangleMesh l_prism() {
  const double xy[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  TriangleMesh m;
  for (int z = 0; z < 2; ++z)
    for (const auto& p : xy) m.vertices.push_back(Vec3(p[0], p[1], z));
  const std::uint32_t n = 6;
  for (std::uint32_t k = 0; k < n; ++k) {  // walls, counter-clockwise polygon: outward
    const std::uint32_t a = k, b = (k + 1) % n;
    m.faces.push_back(Face{a, b, b + n});
    m.faces.push_back(Face{a, b + n, a + n});
  }
  // Caps: a fan from the reflex vertex 3.
  for (std::uint32_t k : {4u, 5u, 0u, 1u}) {
    const std::uint32_t next = (k + 1) % n;
    m.faces.push_back(Face{3 + n, k + n, next + n});  // top, normal +z
    m.faces.push_back(Face{3, next, k});                // bottom, normal -z
  }
  return m;
}

// A cube cell of half size h about c, its covering radius r about c and s(c); true when the cell
// avoids F (|s| > r on one side), as the search's rule (3) requires.
bool cube_cell_off_surface(const SignedDistance& sdf, const Vec3& c, double h, Aabb* cell, double* r, Interval* s) {
  cell->lo = c - Vec3::Constant(h);
  cell->hi = c + Vec3::Constant(h);
  *r = std::sqrt(3.0) * h * (1 + 1e-12);
  *s = sdf.signed_distance(c);
  return std::abs(s->lo) > *r && std::abs(s->hi) > *r && std::signbit(s->lo) == std::signbit(s->hi);
}

TEST(NoCriticalPoint, DirectionIsProvenAtReflexAndConvexEdges) {
  const ValidatedMesh v = validate_mesh(l_prism());
  ASSERT_TRUE(v.report.valid());
  ASSERT_TRUE(v.report.notices.empty()) << v.report.notices[0];  // outward as built
  const SignedDistance sdf(v.mesh);
  const TriangleMesh& m = sdf.mesh();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::uint32_t> ids;
  int accepted_reflex = 0, accepted_convex = 0, checked = 0;
  std::size_t random_accepted = 0;
  for (int k = 0; k < 4000; ++k) {
    const bool outside = k % 2 == 0;
    // Outside: around the reflex edge, x, y > 1. Inside: near the convex edge x = 0, y = 0.
    const Vec3 c = outside ? Vec3{1.0 + 0.6 * u(rng), 1.0 + 0.6 * u(rng), 0.2 + 0.6 * u(rng)}
                           : Vec3{0.5 * u(rng), 0.5 * u(rng), 0.3 + 0.4 * u(rng)};
    const double h = 0.01 + 0.1 * u(rng);
    Aabb cell;
    double r = 0.0;
    Interval s;
    if (!cube_cell_off_surface(sdf, c, h, &cell, &r, &s)) continue;
    if ((s.lo > 0) != outside) continue;
    const double radius = std::max(std::abs(s.lo), std::abs(s.hi)) + 2 * r;
    Vec3 w;
    const bool proven = no_critical_point(sdf, cell, c, radius * (1 + 1e-12), outside ? 1.0 : -1.0, ids, &w);
    // Where both walls of the edge are within reach of the cell's points.
    const bool near_edge = outside ? (c.x() - 1 < radius && c.y() - 1 < radius) : (c.x() < radius && c.y() < radius);
    if (proven && near_edge) ++(outside ? accepted_reflex : accepted_convex);
    // The heuristic direction and random ones: whichever the proof accepts must hold at samples.
    std::vector<Vec3> directions;
    if (proven) directions.push_back(w);
    sdf.triangles_within(c, radius * (1 + 1e-12), 100000, ids);
    for (int j = 0; j < 8; ++j) {
      const Vec3 r3{u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5};
      if (r3.norm() > 0.1 && increases_along(sdf, cell, c, radius * (1 + 1e-12), outside ? 1.0 : -1.0,
                                             r3.normalized(), ids))
        directions.push_back(r3.normalized());
    }
    random_accepted += directions.size() - (proven ? 1 : 0);
    for (const Vec3& dir : directions)
      for (int j = 0; j < 50; ++j) {
        const Vec3 x = cell.lo + Vec3{u(rng), u(rng), u(rng)}.cwiseProduct(cell.hi - cell.lo);
        const Interval dx = sdf.unsigned_distance(x);
        for (std::uint32_t id = 0; id < m.faces.size(); ++id) {
          const Face& f = m.faces[id];
          const Vec3 p = closest_point_on_triangle(x, m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]]);
          if ((x - p).norm() > dx.hi + 1e-12) continue;  // not a nearest point
          ++checked;
          ASSERT_GT(dir.dot(x - p), 0.0) << std::setprecision(17) << "cell centre (" << c.x() << ", " << c.y() << ", "
                                         << c.z() << "), half size " << h << ", x (" << x.x() << ", " << x.y()
                                         << ", " << x.z() << "), face " << id << ", w (" << dir.x() << ", " << dir.y()
                                         << ", " << dir.z() << ")";
        }
      }
  }
  EXPECT_GT(checked, 10000);
  EXPECT_GT(accepted_reflex, 100);
  EXPECT_GT(accepted_convex, 100);
  EXPECT_GT(random_accepted, 1000u);
}

// On a finely tessellated surface a cell's possibly-nearest set exceeds the 256 triangles from which
// the direction is chosen; the proof then runs over the tree with subtrees wholly behind the cell
// left out. Whatever it proves must hold with every triangle within the radius (increases_along on
// the full list) and at sampled points of the cell (every nearest point behind along w).
TEST(NoCriticalPoint, BeyondTheFirstTrianglesTheProofCoversThemAll) {
  const SignedDistance sdf(make_torus(1.0, 0.4, 200, 80));  // 32,000 faces
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::uint32_t> ids, full, near;
  int capped = 0, capped_proven = 0, checked = 0;
  for (int k = 0; k < 3000; ++k) {
    const bool outside = k % 2 == 0;
    const double theta = 2 * M_PI * u(rng), phi = 2 * M_PI * u(rng);
    const double rho = outside ? 0.45 + 0.4 * u(rng) : 0.08 + 0.25 * u(rng);  // from the core circle
    const Vec3 radial(std::cos(theta), std::sin(theta), 0.0);
    const Vec3 c = (1.0 + rho * std::cos(phi)) * radial + Vec3(0, 0, rho * std::sin(phi));
    const double h = 0.005 + 0.04 * u(rng);
    Aabb cell;
    double r = 0.0;
    Interval s;
    if (!cube_cell_off_surface(sdf, c, h, &cell, &r, &s)) continue;
    const double radius = (std::max(std::abs(s.lo), std::abs(s.hi)) + 2 * r) * (1 + 1e-12);
    const double sign = s.lo > 0 ? 1.0 : -1.0;
    const bool is_capped = !sdf.triangles_within(c, radius, 256, ids);
    Vec3 w;
    const bool proven = no_critical_point(sdf, cell, c, radius, sign, ids, &w);
    if (is_capped) ++capped;
    if (!proven) continue;
    if (is_capped) ++capped_proven;
    ASSERT_TRUE(sdf.triangles_within(c, radius, 1u << 20, full));
    ASSERT_TRUE(increases_along(sdf, cell, c, radius, sign, w, full))
        << std::setprecision(17) << "cell centre (" << c.transpose() << "), half size " << h;
    for (int j = 0; j < 10; ++j) {
      const Vec3 x = cell.lo + Vec3{u(rng), u(rng), u(rng)}.cwiseProduct(cell.hi - cell.lo);
      const Interval dx = sdf.unsigned_distance(x);
      sdf.triangles_within(x, dx.hi + 1e-12, 1u << 20, near);
      for (std::uint32_t id : near) {
        const Face& f = sdf.mesh().faces[id];
        const Vec3 p = closest_point_on_triangle(x, sdf.mesh().vertices[f[0]], sdf.mesh().vertices[f[1]],
                                                 sdf.mesh().vertices[f[2]]);
        if ((x - p).norm() > dx.hi + 1e-12) continue;  // not a nearest point
        ++checked;
        ASSERT_GT(w.dot(x - p), 0.0) << std::setprecision(17) << "x (" << x.transpose() << "), face " << id;
      }
    }
  }
  EXPECT_GT(capped, 300);
  EXPECT_GT(capped_proven, 100);  // before the tree proof: none (a capped cell was not proven)
  EXPECT_GT(checked, 1000);
}

TEST(CertifyCompleteness, EmptyLevels) {
  const SignedDistance sdf(make_box(Vec3(0, 0, 0), Vec3(2, 2, 2)));  // max penetration 1
  EXPECT_TRUE(certify_completeness(sdf, TriangleMesh{}, -1.2, 0.01).complete);   // below the deepest point
  const CompletenessResult r = certify_completeness(sdf, TriangleMesh{}, -0.5, 0.01);  // not empty
  EXPECT_FALSE(r.complete);
  EXPECT_FALSE(r.missed.empty());
}

// The bound on w.(p - c) over the part of a triangle within rho of c never falls below the largest
// value at densely sampled points of that part (random, long, sliver and far triangles, balls that
// cut or miss the plane), and for a long triangle it is the disc's value, far below the vertices'.
TEST(MaxTowards, BoundsTheTrianglePartInTheBallFromAbove) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0), pos(0.0, 1.0);
  int sampled = 0;
  for (int k = 0; k < 400; ++k) {
    const double scale = k % 4 == 0 ? 50.0 : 1.0;  // long triangles, far wider than the ball
    const Vec3 a = scale * Vec3{u(rng), u(rng), u(rng)}, b = scale * Vec3{u(rng), u(rng), u(rng)};
    Vec3 q = scale * Vec3{u(rng), u(rng), u(rng)};
    if (k % 4 == 1) {  // sliver
      const double along = pos(rng);
      q = a + (b - a) * along + 1e-6 * Vec3{u(rng), u(rng), u(rng)};
    }
    const Vec3 c = Vec3{u(rng), u(rng), u(rng)}, w = Vec3{u(rng), u(rng), u(rng)}.normalized();
    const double rho = 0.2 + 1.5 * pos(rng);
    const double bound = max_towards(w, c, rho, a, b, q);
    double best = -HUGE_VAL;
    const int n = 300;
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Vec3 p = a + (double(i) / n) * (b - a) + (double(j) / n) * (q - a);
        if ((p - c).norm() <= rho) best = std::max(best, w.dot(p - c));
      }
    if (best > -HUGE_VAL) ++sampled;
    // The samples are rounded points of the triangle: 1e-12 x scale covers that, far below a real miss.
    ASSERT_LE(best, bound + 1e-12 * scale) << std::setprecision(17) << "case " << k << " rho " << rho << " best " << best << " bound " << bound;
  }
  EXPECT_GT(sampled, 100);
  // A long triangle in z = 0, a ball of radius 2 about (0, 0, 1): along x the part in the ball
  // reaches sqrt(3), its vertices 100.
  const double disc = max_towards(Vec3(1, 0, 0), Vec3(0, 0, 1), 2.0, Vec3(-100, -100, 0), Vec3(100, -100, 0),
                                  Vec3(0, 100, 0));
  EXPECT_GE(disc, std::sqrt(3.0));
  EXPECT_LT(disc, std::sqrt(3.0) + 1e-9);
  // A ball that misses the plane holds no point of the triangle.
  EXPECT_EQ(max_towards(Vec3(1, 0, 0), Vec3(0, 0, 3), 2.0, Vec3(-100, -100, 0), Vec3(100, -100, 0), Vec3(0, 100, 0)),
            -HUGE_VAL);
}

}  // namespace
}  // namespace cdbench
