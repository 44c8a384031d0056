#include <gtest/gtest.h>

#include <cmath>

#include "mesh/alpha_wrap.h"
#include "mesh/repair.h"
#include "mesh/validate_mesh.h"
#include "util/error.h"
#include "mesh/shapes.h"

namespace cdbench {
namespace {

// Boxes as separate vertex blocks, the way assemblies are often exported.
PolygonSoup boxes(const std::vector<std::pair<Vec3, Vec3>>& list) {
  PolygonSoup s;
  for (const auto& [lo, hi] : list) {
    const TriangleMesh b = make_box(lo, hi);
    const std::size_t base = s.points.size();
    s.points.insert(s.points.end(), b.vertices.begin(), b.vertices.end());
    for (const Face& f : b.faces) s.polygons.push_back({base + f[0], base + f[1], base + f[2]});
  }
  return s;
}

// A coarse wrap (alpha = diagonal / 10) keeps these tests fast; the default is diagonal / 100.
RepairOptions coarse() {
  RepairOptions o;
  o.wrap.relative_alpha = 10.0;
  return o;
}

TEST(Repair, AValidSolidIsLeftUnchanged) {
  const RepairResult r = repair_mesh(boxes({{Vec3(0, 0, 0), Vec3(1, 2, 3)}}));
  EXPECT_EQ(r.method, RepairMethod::Unchanged);
  EXPECT_TRUE(r.result.report.valid());
  EXPECT_EQ(r.result.mesh.faces.size(), 12u);
}

TEST(Repair, OverlappingBoxesBecomeTheirExactUnion) {
  const RepairResult r = repair_mesh(boxes({{Vec3(0, 0, 0), Vec3(1, 1, 1)}, {Vec3(0.5, 0.25, 0.25), Vec3(2, 0.75, 0.75)}}));
  ASSERT_EQ(r.method, RepairMethod::ExactUnion) << r.exact_note;
  EXPECT_EQ(r.parts, 2u);
  ASSERT_TRUE(r.result.report.valid());
  // 1 + 1.5 * 0.5 * 0.5 - 0.5 * 0.5 * 0.5: dyadic, so the certified volume encloses it tightly.
  EXPECT_LE(r.result.report.volume_lo, 1.25);
  EXPECT_GE(r.result.report.volume_hi, 1.25);
  EXPECT_LT(r.result.report.volume_hi - r.result.report.volume_lo, 1e-12);
  EXPECT_FALSE(r.input_report.valid());
}

TEST(Repair, BoxesTouchingAlongAFaceBecomeOneSolid) {
  const RepairResult r = repair_mesh(boxes({{Vec3(0, 0, 0), Vec3(1, 1, 1)}, {Vec3(1, 0, 0), Vec3(2, 1, 1)}}));
  ASSERT_EQ(r.method, RepairMethod::ExactUnion) << r.exact_note;
  EXPECT_EQ(r.result.report.components, 1u);
  EXPECT_LE(r.result.report.volume_lo, 2.0);
  EXPECT_GE(r.result.report.volume_hi, 2.0);
}

TEST(Repair, PartsSharingAnEdgeFallBackToTheWrapAndSayWhy) {
  // The union of two boxes that share only an edge is not a 2-manifold.
  const RepairResult r = repair_mesh(boxes({{Vec3(0, 0, 0), Vec3(1, 1, 1)}, {Vec3(1, 1, 0), Vec3(2, 2, 1)}}), coarse());
  EXPECT_EQ(r.method, RepairMethod::AlphaWrap);
  EXPECT_NE(r.exact_note.find("2-manifold"), std::string::npos) << r.exact_note;
  EXPECT_TRUE(r.result.report.valid());
  EXPECT_GT(r.offset, 0.0);
}

TEST(Repair, AnOpenSurfaceIsWrappedUnlessWrappingIsForbidden) {
  PolygonSoup open = boxes({{Vec3(0, 0, 0), Vec3(1, 1, 1)}});
  open.polygons.pop_back();
  const RepairResult wrapped = repair_mesh(open, coarse());
  EXPECT_EQ(wrapped.method, RepairMethod::AlphaWrap);
  EXPECT_TRUE(wrapped.result.report.valid());
  RepairOptions no_wrap;
  no_wrap.allow_wrap = false;
  const RepairResult refused = repair_mesh(open, no_wrap);
  EXPECT_EQ(refused.method, RepairMethod::Unchanged);
  EXPECT_FALSE(refused.result.report.valid());
}

// An absolute alpha or offset finer than the relative options allow is refused before wrapping
// (--alpha 1e-6 on the unit sphere had not finished after a minute), naming the value and the limit.
TEST(Repair, AWrapFinerThanTheRelativeRangeIsRefused) {
  PolygonSoup open = boxes({{Vec3(0, 0, 0), Vec3(1, 1, 1)}});
  open.polygons.pop_back();
  const double diag = std::sqrt(3.0);
  AlphaWrapOptions o;
  o.alpha = diag / kMaxRelativeAlpha * 0.999;
  try {
    alpha_wrap(open, o);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--alpha"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("at most 100000"), std::string::npos) << e.what();
  }
  o.alpha = 0.5;
  o.offset = diag / kMaxRelativeOffset * 0.999;
  EXPECT_THROW(alpha_wrap(open, o), InputError);
  o.offset = 0.05;  // a coarse wrap within both ranges
  EXPECT_TRUE(validate_mesh(alpha_wrap(open, o).mesh).report.valid());
}

// The face limit: a wrap estimated above it is refused before the work; a wrap the estimate
// misjudges (an open sheet is wrapped on both sides, twice its area) is stopped during the work
// when its Steiner points pass the limit. Either error names --max-faces and a coarser alpha.
TEST(Repair, AWrapLargerThanTheFaceLimitIsRefusedOrStopped) {
  PolygonSoup sheet;
  sheet.points = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  sheet.polygons = {{0, 1, 2}, {0, 2, 3}};
  AlphaWrapOptions o;
  o.alpha = 0.05;
  o.offset = 0.01;
  const double estimate = estimated_wrap_faces(1.0, o.alpha);
  const AlphaWrapResult full = alpha_wrap(sheet, o);
  const double faces = static_cast<double>(full.mesh.faces.size());
  EXPECT_GT(faces, 1.5 * estimate) << "the sheet's wrap covers both sides";
  const auto message = [&](std::size_t limit) {
    o.max_faces = limit;
    try {
      alpha_wrap(sheet, o);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string refused = message(static_cast<std::size_t>(estimate / 2));
  EXPECT_NE(refused.find("estimated from the input's area"), std::string::npos) << refused;
  EXPECT_NE(refused.find("--max-faces"), std::string::npos) << refused;
  const std::string stopped = message(static_cast<std::size_t>(estimate * 1.05));
  EXPECT_NE(stopped.find("stopped after"), std::string::npos) << stopped;
  EXPECT_NE(stopped.find("--relative-alpha"), std::string::npos) << stopped;
  EXPECT_EQ(message(static_cast<std::size_t>(faces)), "no error") << "a wrap under the limit is never stopped";
}

}  // namespace
}  // namespace cdbench
