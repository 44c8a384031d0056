// Certified clearance against cases with known answers (boxes) and against an independent fine
// Lipschitz enclosure from dense surface sampling (spheres, torus).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <memory>
#include <optional>
#include <random>

#include "distance/support_planes.h"
#include "mesh/components.h"
#include "mesh/read_mesh.h"
#include "mesh/shapes.h"
#include "mesh/validate_mesh.h"
#include "placement/advance.h"
#include "placement/clearance.h"
#include "placement/place_pose.h"
#include "sampling/sampling.h"
#include "scene.h"
#include "test_scale.h"

namespace cdbench {
namespace {

using testing::random_direction;
using testing::random_rotation;
using testing::Scene;

// No pose between `pose_lambda` and the far start (sampled at n points) is certified below the
// target: the pose is on the first crossing.
void expect_no_earlier_crossing(const SignedDistance& fixed, const TriangleMesh& mover, const OrientationFrame& frame,
                                const Vec3& dir, const ApproachSetup& setup, double pose_lambda, double target,
                                double tolerance, int n) {
  const double far = setup.fixed_radius + setup.mover_radius + std::abs(target);
  ClearanceOptions copt;
  copt.tolerance = 1e-3;
  for (int i = 1; i <= n; ++i) {
    const double lambda = pose_lambda + (far - pose_lambda) * i / n;
    const ClearanceResult c = certify_clearance(fixed, mover, setup.components, frame.orientation,
                                                pose_translation(frame, dir, lambda), copt);
    ASSERT_GE(c.clearance.hi, target - tolerance) << std::setprecision(17) << "target " << target << " pose lambda "
                                                  << pose_lambda << " passed a crossing at lambda " << lambda;
  }
}


struct Case {
  SignedDistance fixed;
  TriangleMesh mover;
  std::vector<std::uint32_t> comps;
  Case(TriangleMesh f, TriangleMesh m) : fixed(std::move(f)), mover(std::move(m)), comps(component_representatives(mover)) {}
  ClearanceResult run(const Eigen::Matrix3d& R, const Vec3& t, double tol, const CoincidentFaces* coincident = nullptr) {
    const MoverOrientation o = make_mover_orientation(mover, R);
    ClearanceOptions opt;
    opt.tolerance = tol;
    opt.coincident = coincident;
    return certify_clearance(fixed, mover, comps, o, t, opt);
  }
};

// Axis-aligned boxes are the worst case of the branch and bound (the deepest points form plateaus
// split between coplanar triangles, or whole faces coincide; see doc/poses.md), so a coarser
// tolerance here; the answers are known exactly.
// One vertex per connected component of the mover (the side tests of the distance path need one
// each), the least index of each, and none for a vertex no face uses.
TEST(Mover, OneRepresentativePerComponent) {
  TriangleMesh m = merge_meshes(make_box(Vec3(0, 0, 0), Vec3(1, 1, 1)), make_icosphere(0.5, 1, Vec3(3, 0, 0)));
  const std::size_t box_vertices = make_box(Vec3(0, 0, 0), Vec3(1, 1, 1)).vertices.size();
  m = merge_meshes(m, make_torus(1.0, 0.2, 12, 6));
  m.vertices.push_back(Vec3(9, 9, 9));  // used by no face
  const std::vector<std::uint32_t> reps = component_representatives(m);
  ASSERT_EQ(reps.size(), 3u);
  EXPECT_EQ(reps[0], 0u);
  EXPECT_EQ(reps[1], box_vertices);
  // Reversing the faces' order changes nothing (the least index of a component is its root).
  std::reverse(m.faces.begin(), m.faces.end());
  EXPECT_EQ(component_representatives(m), reps);
}

TEST(Clearance, BoxesWithKnownAnswers) {
  Case c(make_box(Vec3(-2, -2, -2), Vec3(2, 2, 2)), make_box(Vec3(-1, -1, -1), Vec3(1, 1, 1)));
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const double tol = 1e-2;
  // Separated by a gap of 2: the distance path, a few ulps wide.
  ClearanceResult r = c.run(I, Vec3(5, 0, 0), tol);
  EXPECT_TRUE(r.separated);
  EXPECT_TRUE(r.clearance.contains(2.0));
  EXPECT_LT(r.clearance.width(), 1e-13);
  EXPECT_EQ(r.cells, 0u);
  // Inside, shifted by 0.5: the deepest mover surface point is 1.5 deep (face x = -0.5 centre).
  r = c.run(I, Vec3(0.5, 0, 0), tol);
  EXPECT_FALSE(r.separated);
  EXPECT_TRUE(r.tolerance_reached);
  EXPECT_TRUE(r.clearance.contains(-1.5)) << r.clearance.lo << " " << r.clearance.hi;
  EXPECT_LE(r.clearance.width(), tol * 1.001);
  // Touching along a face: c = 0.
  r = c.run(I, Vec3(3, 0, 0), tol);
  EXPECT_TRUE(r.clearance.contains(0.0)) << r.clearance.lo << " " << r.clearance.hi;
  EXPECT_LE(r.clearance.width(), tol * 1.001);
  // Crossing: mover centred at x = 2.5 reaches x = 1.5 inside; its deepest surface points are on
  // the face x = 1.5, 0.5 deep.
  r = c.run(I, Vec3(2.5, 0, 0), tol);
  EXPECT_TRUE(r.clearance.contains(-0.5)) << r.clearance.lo << " " << r.clearance.hi;
  EXPECT_LE(r.clearance.width(), tol * 1.001);
}

// A certificate reaches the tolerance only when its interval is finite and that narrow: far out the
// distance path's interval is rigorous but rounding alone makes it wider (certify reported such
// poses certified until session 45).
TEST(Clearance, FarPosesDoNotReachTheTolerance) {
  Case c(make_box(Vec3(-2, -2, -2), Vec3(2, 2, 2)), make_box(Vec3(-1, -1, -1), Vec3(1, 1, 1)));
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const double tol = 1e-6;
  ClearanceResult r = c.run(I, Vec3(5, 0, 0), tol);
  EXPECT_TRUE(reaches_tolerance(r, tol));
  r = c.run(I, Vec3(1e12, 0, 0), tol);  // doubles 1.2e-4 apart there
  EXPECT_TRUE(r.separated);
  EXPECT_TRUE(r.clearance.contains(1e12 - 3.0));
  EXPECT_GT(r.clearance.width(), tol);
  EXPECT_FALSE(reaches_tolerance(r, tol));
  r = c.run(I, Vec3(0.5, 0, 0), tol);  // the branch and bound's interval, widened for the transform
  EXPECT_TRUE(reaches_tolerance(r, tol));
  r.clearance.hi = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(reaches_tolerance(r, tol));
}

// Contacts seen from outside, and the same pushed in by a little: a tetrahedron's vertex on the top
// face and on the bottom face (from below) of a box, a rotated cube's edge across the box's top
// edge. The exact clearance is 0 or minus the push (the deepest point is the vertex, or the edge
// point over the face); the certificate must contain it at a tight tolerance, with few cells (the
// touching cells are set aside by a separating plane, not by subdividing to the tolerance).
TEST(Clearance, ContactsSeenFromOutsideWithKnownAnswers) {
  // A regular tetrahedron with a vertex at the origin pointing down -z (its other vertices at z = 1).
  TriangleMesh tet;
  tet.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 1), Vec3(-0.5, 0.8660254037844386, 1), Vec3(-0.5, -0.8660254037844386, 1)};
  tet.faces = {{0, 2, 1}, {0, 3, 2}, {0, 1, 3}, {1, 2, 3}};
  const TriangleMesh cube = make_box(Vec3(-0.5, -0.5, -0.5), Vec3(0.5, 0.5, 0.5));
  Case down(make_box(Vec3(0, 0, 0), Vec3(2, 2, 2)), tet);
  Case edge(make_box(Vec3(0, 0, 0), Vec3(2, 2, 2)), cube);
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d flip = Eigen::AngleAxisd(M_PI, Vec3(1, 0, 0)).toRotationMatrix();  // vertex up
  // The cube turned 45 degrees about x (a bottom edge along x) and then 30 degrees about z.
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(0.5235987755982988, Vec3(0, 0, 1)) * Eigen::AngleAxisd(0.7853981633974483, Vec3(1, 0, 0)))
          .toRotationMatrix();
  const double half_diag = std::sqrt(0.5);  // the turned cube's lowest edge lies half_diag below its centre
  const double tol = 1e-7;
  for (double push : {0.0, 1e-5, 3e-3}) {
    SCOPED_TRACE("push " + std::to_string(push));
    struct Run {
      const char* what;
      ClearanceResult r;
    };
    const std::vector<Run> runs{
        {"vertex on the top face", down.run(I, Vec3(1.2, 0.9, 2 - push), tol)},
        {"vertex on the bottom face, from below", down.run(flip, Vec3(0.8, 1.1, push), tol)},
        {"edge across the top edge", edge.run(turn, Vec3(2, 1.1, 2 + half_diag - push), tol)}};
    for (const Run& run : runs) {
      SCOPED_TRACE(run.what);
      // The rotations are rounded: the exact answer is -push up to a few ulps.
      EXPECT_LE(run.r.clearance.lo, -push + 1e-12) << std::setprecision(17) << run.r.clearance.lo;
      EXPECT_GE(run.r.clearance.hi, -push - 1e-12) << std::setprecision(17) << run.r.clearance.hi;
      EXPECT_TRUE(run.r.tolerance_reached);
      EXPECT_LE(run.r.clearance.width(), tol * 1.001);
      if (push == 0.0) {
        EXPECT_LT(run.r.cells, 60u) << "a touching certificate subdivided towards the contact";
      }
    }
  }
}

// A tetrahedron's faces across a thin plate (0.02 thick), its vertex below it in the open, or in a
// thick block under the plate: known answers -0.01 (the plate's mid-plane) and -0.05 (the vertex's
// depth in the block). The large cells across the plate, centred outside, are bounded by the slab
// between the plate's faces (BranchAndBound::slab_lower); where their part below the plate lies
// in the block, that part must be kept (its side is tested), or the vertex would be missed.
TEST(Clearance, CellsAcrossAThinWallWithKnownAnswers) {
  TriangleMesh tet;
  tet.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 1), Vec3(-0.5, 0.8660254037844386, 1), Vec3(-0.5, -0.8660254037844386, 1)};
  tet.faces = {{0, 2, 1}, {0, 3, 2}, {0, 1, 3}, {1, 2, 3}};
  const TriangleMesh plate = make_box(Vec3(-3, -3, 0), Vec3(3, 3, 0.02));
  Case wall(plate, tet);
  Case blocked(merge_meshes(plate, make_box(Vec3(-3, -3, -1), Vec3(3, 3, -0.3))), tet);
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const double tol = 1e-7;
  const ClearanceResult a = wall.run(I, Vec3(0.1, 0.2, -0.3), tol);
  EXPECT_LE(a.clearance.lo, -0.01 + 1e-12) << std::setprecision(17) << a.clearance.lo;
  EXPECT_GE(a.clearance.hi, -0.01 - 1e-12) << std::setprecision(17) << a.clearance.hi;
  EXPECT_TRUE(a.tolerance_reached);
  EXPECT_LE(a.clearance.width(), tol * 1.001);
  // 114 cells measured; 2,985 without the slab bound.
  EXPECT_LT(a.cells, 400u) << "cells across the plate subdivided along the crossing";
  const ClearanceResult b = blocked.run(I, Vec3(0.1, 0.2, -0.35), tol);
  EXPECT_LE(b.clearance.lo, -0.05 + 1e-12) << std::setprecision(17) << b.clearance.lo;
  EXPECT_GE(b.clearance.hi, -0.05 - 1e-12) << std::setprecision(17) << b.clearance.hi;
  EXPECT_TRUE(b.tolerance_reached);
  EXPECT_LE(b.clearance.width(), tol * 1.001);
}

// A cube resting face-on on a step of an L-shaped part (the step's face, z = 1, does not support
// the part: its upper arm rises above that plane, so no hull plane bounds it): on the step, over
// its edge, in the corner against the wall, turned about the vertical (z stays exact), and pushed
// into the step by 1e-3. The exact clearance is 0, or minus the push. The cells of the resting
// face are centred exactly on F, where the depth bound gave no bound before session 93: the cells
// were split towards the tolerance until the work limit (`cdbench certify` of such poses: 400,000
// cells, 8 s, intervals 3e-4 to 7e-4 wide, uncertified).
TEST(Clearance, CubesRestingFaceOnAStepWithKnownAnswers) {
  // The L profile (x, z) = (0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2), extruded along y in [0, 1].
  TriangleMesh step;
  const double profile[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  for (double y : {0.0, 1.0})
    for (const auto& p : profile) step.vertices.push_back(Vec3(p[0], y, p[1]));
  for (std::uint32_t k = 1; k < 5; ++k) {  // the two L-shaped caps, fans from (0, 0)
    step.faces.push_back({0, k, k + 1});
    step.faces.push_back({6, 7 + k, 6 + k});
  }
  for (std::uint32_t i = 0; i < 6; ++i) {  // the six sides
    const std::uint32_t j = (i + 1) % 6;
    step.faces.push_back({i, i + 6, j + 6});
    step.faces.push_back({i, j + 6, j});
  }
  ASSERT_TRUE(validate_mesh(step).report.valid());
  Case c(step, make_box(Vec3(0, 0, 0), Vec3(0.5, 0.5, 0.5)));
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const double tol = 1e-7;
  struct Pose {
    const char* what;
    Eigen::Matrix3d R;
    Vec3 t;
    double clearance;
  };
  const std::vector<Pose> poses{
      {"on the step", I, Vec3(1.2, 0.2, 1), 0.0},
      {"over the step's edge", I, Vec3(1.75, 0.2, 1), 0.0},
      {"in the corner against the wall", I, Vec3(1, 0.25, 1), 0.0},
      {"flush with the side", I, Vec3(1.25, 0, 1), 0.0},
      {"turned", Eigen::AngleAxisd(0.7, Vec3(0, 0, 1)).toRotationMatrix(), Vec3(1.6, 0.1, 1), 0.0},
      {"pushed in", I, Vec3(1.2, 0.2, 0.999), -1e-3}};
  for (const Pose& p : poses) {
    SCOPED_TRACE(p.what);
    const ClearanceResult r = c.run(p.R, p.t, tol);
    // Rounded rotations and translations: the exact answer up to a few ulps.
    EXPECT_LE(r.clearance.lo, p.clearance + 1e-12) << std::setprecision(17) << r.clearance.lo;
    EXPECT_GE(r.clearance.hi, p.clearance - 1e-12) << std::setprecision(17) << r.clearance.hi;
    EXPECT_TRUE(r.tolerance_reached);
    EXPECT_LE(r.clearance.width(), tol * 1.001);
    EXPECT_LT(r.cells, 5000u) << "cells lying on F split towards the tolerance";
  }
}

// Coincident meshes: the mover is the fixed mesh at the identity, and a turned copy of both (every
// coordinate rounded, so the surfaces coincide up to rounding). The exact clearance is 0 (up to
// the copy's rounding), and every cell lies on F. Its centre lies on a triangle exactly or up to
// its nearest point's rounding, or is proved outside F by a hair: before session 93 the torus's
// hole (faces that do not support it) kept such cells at their Lipschitz bound, and `cdbench
// certify` stopped at the work limit (36 s).
TEST(Clearance, CoincidentMeshesAreCertified) {
  const TriangleMesh torus = make_torus(1.0, 0.35, 24, 12);
  std::mt19937_64 rng(11);
  const Eigen::Matrix3d turn = random_rotation(rng);
  TriangleMesh turned = torus;
  for (Vec3& x : turned.vertices) x = turn * x;
  Case same(torus, torus);
  Case copy(turned, torus);
  const double tol = 1e-7;
  for (const auto& [what, r] : {std::pair<const char*, ClearanceResult>{"identity", same.run(Eigen::Matrix3d::Identity(), Vec3::Zero(), tol)},
                                {"turned", copy.run(turn, Vec3::Zero(), tol)}}) {
    SCOPED_TRACE(what);
    EXPECT_LE(r.clearance.lo, 1e-12) << std::setprecision(17) << r.clearance.lo;
    EXPECT_GE(r.clearance.hi, -1e-12) << std::setprecision(17) << r.clearance.hi;
    EXPECT_TRUE(r.tolerance_reached);
    EXPECT_LE(r.clearance.width(), tol * 1.001);
    // 1,709 and 1,688 cells measured; 8,740 and 9,664 when centres on F up to rounding, or proved
    // outside by a hair, were weighted by the rounding's direction or split without a depth bound.
    EXPECT_LT(r.cells, 4000u) << "cells lying on F split towards the tolerance";
  }
}

// The same known answer with a needle tetrahedron (faces 6 long and 0.26 wide: needle cells, cut
// across their length, centred at the middle of a median): its vertex pushed into a box's top face
// at three tilts; the exact clearance is -push.
TEST(Clearance, NeedleVertexInAFaceWithKnownAnswers) {
  TriangleMesh needle;
  needle.vertices = {Vec3(0, 0, 0), Vec3(0.15, 0, 6), Vec3(-0.075, 0.13, 6), Vec3(-0.075, -0.13, 6)};
  needle.faces = {{0, 2, 1}, {0, 3, 2}, {0, 1, 3}, {1, 2, 3}};
  Case c(make_box(Vec3(0, 0, 0), Vec3(2, 2, 2)), needle);
  const double tol = 1e-7;
  for (const double tilt : {0.0, 0.3, 0.9}) {
    const Eigen::Matrix3d R = Eigen::AngleAxisd(tilt, Vec3(1, 0.5, 0).normalized()).toRotationMatrix();
    for (const double push : {1e-5, 3e-3, 0.05}) {
      SCOPED_TRACE("tilt " + std::to_string(tilt) + " push " + std::to_string(push));
      const ClearanceResult r = c.run(R, Vec3(1.2, 0.9, 2 - push), tol);
      EXPECT_LE(r.clearance.lo, -push + 1e-12) << std::setprecision(17) << r.clearance.lo;
      EXPECT_GE(r.clearance.hi, -push - 1e-12) << std::setprecision(17) << r.clearance.hi;
      EXPECT_TRUE(r.tolerance_reached);
      EXPECT_LE(r.clearance.width(), tol * 1.001);
    }
  }
}

// Fine sampling of the mover surface: min of certified s over samples is an upper bound of c, and
// min - h (h the sampling radius) a lower bound; the certificate must intersect that enclosure.
Interval sampled_enclosure(const SignedDistance& fixed, const std::vector<Vec3>& P, const std::vector<Face>& faces, int n) {
  double best = HUGE_VAL, h = 0.0;
  for (const Face& f : faces) {
    const Vec3 &a = P[f[0]], &b = P[f[1]], &c = P[f[2]];
    h = std::max(h, std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()}) / n);
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) {
        const Vec3 x = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
        best = std::min(best, fixed.signed_distance(x).hi);
      }
  }
  return {best - h, best};
}

// F's faces by their corners: any order of the corners, -0 as +0; three of F's vertices that do not
// form one of its faces, or a corner off by an ulp, are not one.
TEST(CoincidentFaces, RecognisesExactlyFsFaces) {
  const TriangleMesh box = make_box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const CoincidentFaces index(box);
  for (const Face& f : box.faces) {
    const Vec3 &a = box.vertices[f[0]], &b = box.vertices[f[1]], &c = box.vertices[f[2]];
    EXPECT_TRUE(index.contains(a, b, c));
    EXPECT_TRUE(index.contains(c, a, b));
    EXPECT_TRUE(index.contains(b, a, c));
    EXPECT_TRUE(index.contains(-(-a), b, c));  // the origin's corner as -0
    // A corner an ulp off is no exact match, but one up to rounding: e bounds the ulp.
    const Vec3 off = c + Vec3(0, 0, std::nextafter(c[2], 2.0) - c[2]);
    EXPECT_FALSE(index.contains(a, b, off));
    const double e = index.match(a, b, off);
    EXPECT_GE(e, off[2] - c[2]);  // one ulp, a subnormal one at 0
    EXPECT_LE(e, 4.0 * (off[2] - c[2]));
    EXPECT_EQ(index.match(a, b, c), 0.0);
    // Beyond radius() it matches nothing.
    EXPECT_LT(index.match(a, b, c + Vec3(0, 0, 2.0 * index.radius())), 0.0);
  }
  EXPECT_EQ(index.radius(), std::ldexp(1.0, -40));  // the largest coordinate is 1
  // A face's diagonal with the opposite corner of the box: three vertices, no face.
  EXPECT_FALSE(index.contains(Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(1, 1, 1)));
  EXPECT_FALSE(index.contains(Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 0)));
}

// Faces placed exactly onto F's faces (ClearanceOptions::coincident) are settled at s = 0: the
// torus against itself at the identity needs no cell (1,709 without the index, above); with one
// vertex pushed into F (on the outer equator and in the saddle about the hole), the other faces
// are settled and the certificate agrees with the one computed without the index and with dense
// sampling, in a third of the cells. Pushed out, the faces about the vertex hinge on F's edges
// from outside and lie on F's outer side: their cells are settled at s >= 0 by the triangles their
// interiors may meet (triangles_meeting_interior), where they were split towards the tolerance
// along the hinge before (66,000 cells on the outer equator; 400,000 and uncertified in the
// saddle; doc/poses.md, "Faces hinged on F's edges").
TEST(Clearance, FacesPlacedOntoFsFacesAreSettled) {
  const TriangleMesh torus = make_torus(1.0, 0.35, 24, 12);
  const CoincidentFaces index(torus);
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  const double tol = 1e-7;
  Case same(torus, torus);
  const ClearanceResult r = same.run(I, Vec3::Zero(), tol, &index);
  EXPECT_EQ(r.cells, 0u);
  EXPECT_TRUE(r.tolerance_reached);
  EXPECT_LE(r.clearance.lo, 0.0);
  EXPECT_GE(r.clearance.hi, 0.0);
  EXPECT_LT(r.clearance.width(), 1e-13);
  for (const std::uint32_t vertex : {36u, 40u}) {
    SCOPED_TRACE("vertex " + std::to_string(vertex) + " pushed in along its radius from the tube's axis");
    TriangleMesh dented = torus;
    Vec3& x = dented.vertices[vertex];
    const Vec3 axis_point = Vec3(x[0], x[1], 0.0).normalized();  // the tube's centre circle, radius 1
    x -= 2e-3 * (x - axis_point).normalized();
    Case c(torus, dented);
    const ClearanceResult with = c.run(I, Vec3::Zero(), tol, &index), without = c.run(I, Vec3::Zero(), tol);
    EXPECT_TRUE(with.tolerance_reached);
    EXPECT_TRUE(without.tolerance_reached);
    EXPECT_LE(with.clearance.lo, without.clearance.hi) << std::setprecision(17) << with.clearance.lo;
    EXPECT_GE(with.clearance.hi, without.clearance.lo) << std::setprecision(17) << with.clearance.hi;
    EXPECT_LE(with.clearance.width(), tol * 1.001);
    const MoverOrientation o = make_mover_orientation(dented, I);
    const Interval sampled = sampled_enclosure(c.fixed, o.placed(Vec3::Zero()), dented.faces, 6);
    EXPECT_LE(with.clearance.lo, sampled.hi);
    EXPECT_GE(with.clearance.hi, sampled.lo);
    EXPECT_LT(with.clearance.hi, -1e-3);  // the vertex lies about 1.9e-3 inside F
    // 514 and 528 cells measured, 1,699 and 1,712 without the index.
    EXPECT_LT(with.cells, without.cells / 2) << with.cells << " cells against " << without.cells;
  }
  for (const std::uint32_t vertex : {36u, 40u})
    for (const double push : {2e-3, 0.05}) {
      SCOPED_TRACE("vertex " + std::to_string(vertex) + " pushed out by " + std::to_string(push));
      TriangleMesh bulged = torus;
      Vec3& x = bulged.vertices[vertex];
      x += push * (x - Vec3(x[0], x[1], 0.0).normalized()).normalized();
      Case c(torus, bulged);
      const ClearanceResult with = c.run(I, Vec3::Zero(), tol, &index);
      // The rest lies on F, the bulge outside: c = 0.
      EXPECT_TRUE(with.tolerance_reached);
      EXPECT_LE(with.clearance.lo, 0.0) << std::setprecision(17) << with.clearance.lo;
      EXPECT_GE(with.clearance.hi, 0.0) << std::setprecision(17) << with.clearance.hi;
      EXPECT_LE(with.clearance.width(), tol * 1.001);
      // 512-630 cells measured.
      EXPECT_LT(with.cells, 5000u) << "cells along a hinge split towards the tolerance";
    }
}

// A lower end wanted (ClearanceOptions::floor: a two-sided step's far end). At penetrating poses of
// a small sphere in a torus, a loose certificate (0.6 of the way to a target below, as a deep
// level's steps) with a floor reaches it wherever a tight certificate shows it can (its lower end
// well above), lifting lower ends the loose width alone left below (27 of 27 penetrating poses at
// the default scale); with a floor above the
// tight upper end its search goes on until its own upper end refutes the floor. Every interval
// meets the tight one and holds the sampled minimum's upper end.
TEST(Clearance, FloorsAreReachedOrRefuted) {
  const TriangleMesh torus = make_torus(1.0, 0.35, 24, 12);
  Case c(torus, make_icosphere(0.2, 1));
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double tol = 1e-6;
  int raised = 0, tried = 0;
  for (int k = 0; k < test_scale::cases(30); ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const double a = 3.14159 * u(rng), radial = 1.0 + 0.45 * u(rng), z = 0.45 * u(rng);
    const Vec3 t{radial * std::cos(a), radial * std::sin(a), z};
    const MoverOrientation o = make_mover_orientation(c.mover, R);
    ClearanceOptions opt;
    opt.tolerance = tol;
    const ClearanceResult tight = certify_clearance(c.fixed, c.mover, c.comps, o, t, opt);
    ASSERT_TRUE(tight.tolerance_reached);
    if (!(tight.clearance.hi < -0.02)) continue;  // penetrating poses only
    ++tried;
    const Interval sampled = sampled_enclosure(c.fixed, o.placed(t), c.mover.faces, 4);
    opt.target = tight.clearance.lo - 0.05;
    opt.relative_tolerance = 0.6;
    const ClearanceResult loose = certify_clearance(c.fixed, c.mover, c.comps, o, t, opt);
    SCOPED_TRACE(::testing::Message() << std::setprecision(17) << "pose " << k << " t " << t.transpose());
    const double reachable = opt.target + 0.9 * (tight.clearance.lo - opt.target);
    const double unreachable = tight.clearance.hi + 0.01;
    for (const double floor : {reachable, unreachable}) {
      opt.floor = floor;
      const ClearanceResult r = certify_clearance(c.fixed, c.mover, c.comps, o, t, opt);
      EXPECT_LE(r.clearance.lo, tight.clearance.hi);
      EXPECT_GE(r.clearance.hi, tight.clearance.lo);
      EXPECT_LE(r.clearance.lo, sampled.hi);
      if (floor == reachable) {
        EXPECT_GE(r.clearance.lo, floor) << loose.clearance.lo;
        raised += loose.clearance.lo < floor;
      } else {
        EXPECT_LT(r.clearance.hi, floor);
      }
    }
  }
  EXPECT_GT(tried, test_scale::cases(30) / 3);
  EXPECT_GT(raised, 0);
}

// A copy of the torus turned by R (its coordinates rounded) and placed back by R^T lands a few ulps
// off F: its faces are matched up to rounding and settled at [-e, e] (no cell), where without the
// index every face is split towards the tolerance. With a vertex pushed in, the certificate agrees
// with sampling and with the one computed without the index. A match wider than a quarter of the
// tolerance settles nothing (match_settles): the search then runs as without the index.
TEST(Clearance, TurnedCopiesPlacedBackAreSettled) {
  const TriangleMesh torus = make_torus(1.0, 0.35, 24, 12);
  const CoincidentFaces index(torus);
  std::mt19937_64 rng(11);
  const double tol = 1e-7;
  for (int trial = 0; trial < 3; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const Eigen::Matrix3d R = random_rotation(rng);
    TriangleMesh turned = torus;
    for (Vec3& x : turned.vertices) x = R * x;
    const Eigen::Matrix3d back = R.transpose();
    Case c(torus, turned);
    const ClearanceResult with = c.run(back, Vec3::Zero(), tol, &index);
    const MoverOrientation o = make_mover_orientation(turned, back);
    const Interval sampled = sampled_enclosure(c.fixed, o.placed(Vec3::Zero()), turned.faces, 3);
    EXPECT_EQ(with.cells, 0u);
    EXPECT_TRUE(with.tolerance_reached);
    EXPECT_LE(with.clearance.lo, sampled.hi) << std::setprecision(17) << with.clearance.lo;
    EXPECT_GE(with.clearance.hi, sampled.lo) << std::setprecision(17) << with.clearance.hi;
    EXPECT_LT(with.clearance.width(), 1e-13);
    if (trial == 0) {
      const ClearanceResult without = c.run(back, Vec3::Zero(), tol);
      EXPECT_GT(without.cells, 1000u);
    }
    TriangleMesh dented = turned;
    Vec3& x = dented.vertices[static_cast<std::size_t>(36 + trial * 50)];
    const Vec3 home = back * x;
    x -= 2e-3 * (R * (home - Vec3(home[0], home[1], 0.0).normalized())).normalized();
    Case d(torus, dented);
    const ClearanceResult in = d.run(back, Vec3::Zero(), tol, &index), in_without = d.run(back, Vec3::Zero(), tol);
    const Interval in_sampled =
        sampled_enclosure(d.fixed, make_mover_orientation(dented, back).placed(Vec3::Zero()), dented.faces, 6);
    EXPECT_TRUE(in.tolerance_reached);
    EXPECT_LE(in.clearance.lo, in_sampled.hi);
    EXPECT_GE(in.clearance.hi, in_sampled.lo);
    EXPECT_LE(in.clearance.lo, in_without.clearance.hi);
    EXPECT_GE(in.clearance.hi, in_without.clearance.lo);
    EXPECT_LT(in.clearance.hi, -1e-3);
    EXPECT_LT(in.cells, in_without.cells / 2) << in.cells << " cells against " << in_without.cells;
  }
  EXPECT_TRUE(match_settles(0.0, 0.0));
  EXPECT_TRUE(match_settles(1e-14, 1e-13));
  EXPECT_FALSE(match_settles(1e-13, 1e-13));
  EXPECT_FALSE(match_settles(-1.0, 1.0));
}

// A copy of the torus written in single precision, at the identity: its corners lie up to 3e-8 off
// F's, far beyond the rounding index's radius, and with 50 cells the search ends short of the
// tolerance. With a retry index (radius tolerance / 8) the faces are settled at [-e, e] in a
// second run and the result is the intersection of both runs' intervals: certified, holding sampled
// s. Without the retry, or with a tolerance too tight for the match, it stays uncertified.
TEST(Clearance, SinglePrecisionCopiesSettledOnRetry) {
  const TriangleMesh torus = make_torus(1.0, 0.35, 24, 12);
  TriangleMesh single = torus;
  for (Vec3& x : single.vertices)
    for (int i = 0; i < 3; ++i) x[i] = static_cast<double>(static_cast<float>(x[i]));
  const CoincidentFaces index(torus);
  const double tol = 1e-5;
  const LazyCoincidentFaces wide(torus, tol / 8.0);
  const SignedDistance fixed(torus);
  const MoverOrientation o = make_mover_orientation(single, Eigen::Matrix3d::Identity());
  const std::vector<std::uint32_t> comps = component_representatives(single);
  const auto run = [&](const LazyCoincidentFaces* retry, double tolerance) {
    ClearanceOptions opt;
    opt.tolerance = tolerance;
    opt.max_cells = 50;
    opt.coincident = &index;
    opt.coincident_retry = retry;
    return certify_clearance(fixed, single, comps, o, Vec3::Zero(), opt);
  };
  const Interval sampled = sampled_enclosure(fixed, o.placed(Vec3::Zero()), single.faces, 4);
  const ClearanceResult once = run(nullptr, tol), retried = run(&wide, tol);
  EXPECT_FALSE(reaches_tolerance(once, tol));
  EXPECT_TRUE(reaches_tolerance(retried, tol));
  EXPECT_GE(retried.cells, once.cells);  // both runs counted
  for (const ClearanceResult* r : {&once, &retried}) {
    EXPECT_LE(r->clearance.lo, sampled.hi) << std::setprecision(17) << r->clearance.lo;
    EXPECT_GE(r->clearance.hi, sampled.lo) << std::setprecision(17) << r->clearance.hi;
  }
  EXPECT_GE(retried.clearance.lo, once.clearance.lo);
  EXPECT_LE(retried.clearance.hi, once.clearance.hi);
  EXPECT_LT(retried.clearance.width(), 1e-6);  // e: the float rounding, about 3e-8 times sqrt(3)
  // A tolerance below 4 e: the wide match settles nothing, and the retry ends short too.
  EXPECT_FALSE(reaches_tolerance(run(&wide, 1e-8), 1e-8));
  // With a budget of 1,000 cells (the plain search needs about 1,500) and a probe of 50: the wide
  // run follows the probe at once and settles every face (armadillo x16's copy spent its whole
  // budget of 400,000 cells before its retry); without the retry the budget is spent short of the
  // tolerance.
  ClearanceOptions big;
  big.tolerance = tol;
  big.max_cells = 1000;
  big.coincident = &index;
  big.retry_probe_cells = 50;
  const ClearanceResult plain = certify_clearance(fixed, single, comps, o, Vec3::Zero(), big);
  big.coincident_retry = &wide;
  const ClearanceResult probed = certify_clearance(fixed, single, comps, o, Vec3::Zero(), big);
  EXPECT_FALSE(reaches_tolerance(plain, tol));
  EXPECT_EQ(plain.cells, 1000u);
  EXPECT_TRUE(reaches_tolerance(probed, tol));
  EXPECT_LE(probed.cells, 100u);
  // Without the exact index nothing is retried, so nothing may stop for a retry either.
  ClearanceOptions no_index = big;
  no_index.coincident = nullptr;
  const ClearanceResult unstopped = certify_clearance(fixed, single, comps, o, Vec3::Zero(), no_index);
  EXPECT_FALSE(unstopped.probe_stopped);
  EXPECT_EQ(unstopped.cells, 1000u);
  // At a tolerance the wide match cannot settle: the probe, the wide run and the whole first search
  // again, each short, their intervals intersected.
  big.tolerance = 1e-8;
  const ClearanceResult again = certify_clearance(fixed, single, comps, o, Vec3::Zero(), big);
  EXPECT_FALSE(reaches_tolerance(again, 1e-8));
  EXPECT_EQ(again.cells, 50u + 1000u + 1000u);
  EXPECT_LE(again.clearance.lo, sampled.hi) << std::setprecision(17) << again.clearance.lo;
  EXPECT_GE(again.clearance.hi, sampled.lo) << std::setprecision(17) << again.clearance.hi;
  EXPECT_LE(probed.clearance.lo, sampled.hi) << std::setprecision(17) << probed.clearance.lo;
  EXPECT_GE(probed.clearance.hi, sampled.lo) << std::setprecision(17) << probed.clearance.hi;
}

// A hard pose with no placed vertex near one of F's (the torus against a copy turned and shifted
// into it): the search does not stop at the probe's count, whatever it is, and gives the interval,
// and spends the cells, of the search without the retry.
TEST(Clearance, HardPosesAwayFromFsVerticesAreNotProbed) {
  const TriangleMesh torus = make_torus(1.0, 0.35, 24, 12);
  const CoincidentFaces index(torus);
  const double tol = 1e-7;
  const LazyCoincidentFaces wide(torus, tol / 8.0);
  const SignedDistance fixed(torus);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const MoverOrientation o = make_mover_orientation(torus, R);
  const std::vector<std::uint32_t> comps = component_representatives(torus);
  const Vec3 t(0.05, 0.02, 0.01);
  ClearanceOptions opt;
  opt.tolerance = tol;
  opt.coincident = &index;
  const ClearanceResult one = certify_clearance(fixed, torus, comps, o, t, opt);
  ASSERT_TRUE(reaches_tolerance(one, tol));
  ASSERT_GT(one.cells, 400u) << "the pose is too easy to test a probe";
  const Interval sampled = sampled_enclosure(fixed, o.placed(t), torus.faces, 3);
  EXPECT_LE(one.clearance.lo, sampled.hi) << std::setprecision(17) << one.clearance.lo;
  opt.coincident_retry = &wide;
  for (const std::uint64_t probe : {1u, 50u, 200u}) {
    SCOPED_TRACE("probe " + std::to_string(probe));
    opt.retry_probe_cells = probe;
    const ClearanceResult r = certify_clearance(fixed, torus, comps, o, t, opt);
    EXPECT_FALSE(r.probe_stopped);
    EXPECT_EQ(r.clearance.lo, one.clearance.lo);
    EXPECT_EQ(r.clearance.hi, one.clearance.hi);
    EXPECT_EQ(r.cells, one.cells);
  }
}

// The triangles of F that may meet a triangle's open interior: a face of F lists itself and the
// coplanar face across its diagonal (the box's top is two triangles); turned outwards or inwards
// about one of its edges, none; turned through a side, that side's faces.
TEST(CoincidentFaces, TrianglesMeetingTheInterior) {
  const TriangleMesh box = make_box(Vec3(0, 0, 0), Vec3(1, 1, 1));
  const SignedDistance fixed(box);
  std::vector<std::uint32_t> ids;
  // Face {4, 5, 6} of make_box lies in the top z = 1: corners (0,0,1), (1,0,1), (0,1,1).
  const Vec3 a(0, 0, 1), b(1, 0, 1), c(0, 1, 1);
  ASSERT_TRUE(triangles_meeting_interior(fixed, a, b, c, 16, ids));
  std::sort(ids.begin(), ids.end());
  EXPECT_EQ(ids, (std::vector<std::uint32_t>{2u, 3u}));  // itself and the top's other half
  ASSERT_TRUE(triangles_meeting_interior(fixed, a, b, Vec3(0, 1, 1.25), 16, ids));  // turned out about ab
  EXPECT_TRUE(ids.empty());
  ASSERT_TRUE(triangles_meeting_interior(fixed, a, b, Vec3(0, 1, 0.75), 16, ids));  // turned in: inside the box
  EXPECT_TRUE(ids.empty());
  ASSERT_TRUE(triangles_meeting_interior(fixed, a, b, Vec3(0, 1.5, 0.75), 16, ids));  // through the side y = 1
  EXPECT_FALSE(ids.empty());
  for (const std::uint32_t id : ids) EXPECT_TRUE(id == 6u || id == 7u) << id;
  EXPECT_FALSE(triangles_meeting_interior(fixed, a, b, Vec3(2, 0, 1), 16, ids));  // degenerate
}

// The torus against copies of itself with one to five vertices pushed in or out along the tube's
// radius by 10^-7 to 10^-1 (faces on F, hinged on its edges from outside, crossing it): each
// certificate holds the least s sampled at the faces' vertices and on a grid over them, an upper
// bound of c (a hinged cell wrongly set aside at s >= 0 would put the lower end above a deeper
// sampled point), and reaches the tolerance.
TEST(Clearance, RandomBulgesAgreeWithSampling) {
  const TriangleMesh torus = make_torus(1.0, 0.35, 24, 12);
  const CoincidentFaces index(torus);
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<std::uint32_t> pick(0, 287);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 12; ++trial) {
    TriangleMesh m = torus;
    const int k = 1 + trial % 5;
    for (int i = 0; i < k; ++i) {
      Vec3& x = m.vertices[pick(rng)];
      const double size = std::pow(10.0, -1.0 - 6.0 * std::abs(u(rng)));
      const double push = u(rng) > 0 ? size : -size;
      x += push * (x - Vec3(x[0], x[1], 0.0).normalized()).normalized();
    }
    SCOPED_TRACE("trial " + std::to_string(trial));
    Case c(torus, m);
    const ClearanceResult r = c.run(I, Vec3::Zero(), 1e-7, &index);
    const Interval sampled = sampled_enclosure(c.fixed, make_mover_orientation(m, I).placed(Vec3::Zero()), m.faces, 3);
    EXPECT_TRUE(r.tolerance_reached);
    EXPECT_LE(r.clearance.lo, sampled.hi) << std::setprecision(17) << r.clearance.lo << " above a sampled point";
    EXPECT_GE(r.clearance.hi, sampled.lo) << std::setprecision(17) << r.clearance.hi;
    EXPECT_LT(r.cells, 5000u);  // 511-702 measured over 40 such trials
  }
}

TEST(Clearance, AgreesWithDenseSampling) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Case c(make_torus(1.0, 0.4, 24, 12), make_icosphere(0.5, 1));
  int separated = 0, penetrating = 0;
  for (int k = 0; k < 24; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const Vec3 t = k % 4 == 0 ? Vec3{0.05 * u(rng), 0.05 * u(rng), 0.05 * u(rng)}  // in the hole
                              : Vec3{1.6 * u(rng), 1.6 * u(rng), 0.9 * u(rng)};
    const double tol = 1e-6;
    const ClearanceResult r = c.run(R, t, tol);
    const MoverOrientation o = make_mover_orientation(c.mover, R);
    const Interval ref = sampled_enclosure(c.fixed, o.placed(t), c.mover.faces, 12);
    SCOPED_TRACE("case " + std::to_string(k));
    EXPECT_TRUE(r.tolerance_reached);
    EXPECT_LE(r.clearance.lo, ref.hi) << r.clearance.lo << " " << r.clearance.hi << " vs " << ref.lo << " " << ref.hi;
    EXPECT_GE(r.clearance.hi, ref.lo) << r.clearance.lo << " " << r.clearance.hi << " vs " << ref.lo << " " << ref.hi;
    EXPECT_LE(r.clearance.width(), r.separated ? 1e-12 : tol * 1.001);
    (r.separated ? separated : penetrating)++;
  }
  EXPECT_GT(separated, 2);
  EXPECT_GT(penetrating, 2);
}

// Far from the origin the doubles' rounding is a fair part of a tight tolerance (doc/poses.md, "Far
// from the origin"): at 2^24 a certificate still reaches 2e-6 (it could not before session 69, whose
// near-point and combination bounds are 5x and 2.5x tighter), agreeing with dense sampling; at 2^27
// the rounding alone is wider than 1e-6, and the search stops at a cell below its own rounding
// instead of splitting to its cell budget, its interval still rigorous.
TEST(Clearance, FarFromTheOriginReachesWhatRoundingAllows) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const double far : {0x1p24, 0x1p27}) {
    TriangleMesh torus = make_torus(1.0, 0.4, 24, 12);
    for (Vec3& v : torus.vertices) v += Vec3(far, -far, far);
    Case c(torus, make_icosphere(0.5, 1));
    const double tol = far < 0x1p25 ? 2e-6 : 1e-6;
    int penetrating = 0;
    for (int k = 0; k < 12; ++k) {
      const Eigen::Matrix3d R = random_rotation(rng);
      const Vec3 t = Vec3(far, -far, far) + Vec3{1.6 * u(rng), 1.6 * u(rng), 0.9 * u(rng)};
      const ClearanceResult r = c.run(R, t, tol);
      const MoverOrientation o = make_mover_orientation(c.mover, R);
      const Interval ref = sampled_enclosure(c.fixed, o.placed(t), c.mover.faces, 12);
      SCOPED_TRACE(::testing::Message() << std::setprecision(17) << "far " << far << " t = (" << t.transpose() << ")");
      EXPECT_LE(r.clearance.lo, ref.hi) << r.clearance.lo << " " << r.clearance.hi << " vs " << ref.lo << " " << ref.hi;
      EXPECT_GE(r.clearance.hi, ref.lo) << r.clearance.lo << " " << r.clearance.hi << " vs " << ref.lo << " " << ref.hi;
      if (r.separated) continue;
      ++penetrating;
      if (far < 0x1p25) {
        EXPECT_TRUE(reaches_tolerance(r, tol)) << r.clearance.width() << " wide after " << r.cells << " cells";
        EXPECT_FALSE(r.rounding_floor);
      } else {
        EXPECT_FALSE(r.tolerance_reached);
        EXPECT_TRUE(r.rounding_floor);
        EXPECT_LT(r.cells, 100000u);  // far below the budget of 400,000 it would otherwise spend
      }
    }
    EXPECT_GT(penetrating, 3);
  }
}

// A pose's cold certificate, and the same pose warm-started from a nearby pose's frontier, both
// checked against dense sampling (`samples` points per edge): both are returned.
std::array<ClearanceResult, 2> expect_cold_and_warm_agree(Case& c, const Eigen::Matrix3d& R, const Vec3& t, double tol,
                                                          int samples) {
  const ClearanceResult r = c.run(R, t, tol);
  const MoverOrientation o = make_mover_orientation(c.mover, R);
  const Interval ref = sampled_enclosure(c.fixed, o.placed(t), c.mover.faces, samples);
  ClearanceFrontier frontier;
  ClearanceOptions warm;
  warm.tolerance = tol;
  warm.frontier = &frontier;
  certify_clearance(c.fixed, c.mover, c.comps, o, t + Vec3(0.01, -0.02, 0.015), warm);
  const ClearanceResult w = certify_clearance(c.fixed, c.mover, c.comps, o, t, warm);
  SCOPED_TRACE(::testing::Message() << std::setprecision(17) << "t = (" << t.x() << ", " << t.y() << ", " << t.z()
                                    << ")");
  for (const ClearanceResult* x : {&r, &w}) {
    EXPECT_TRUE(x->tolerance_reached);
    EXPECT_LE(x->clearance.lo, ref.hi) << x->clearance.lo << " " << x->clearance.hi << " vs " << ref.lo << " " << ref.hi;
    EXPECT_GE(x->clearance.hi, ref.lo) << x->clearance.lo << " " << x->clearance.hi << " vs " << ref.lo << " " << ref.hi;
    EXPECT_LE(x->clearance.width(), x->separated ? 1e-12 : tol * 1.001);
  }
  return {r, w};
}

// Cells far outside F are set aside by a lower bound of their centre's distance alone
// (BranchAndBound::set_aside_far): inside a thin-walled pipe most of a mover's cells lie in the
// hollow, far from the wall. Cold and warm certificates agree with dense sampling, and the far
// cells were used.
TEST(Clearance, FarCellsInAHollowPipeAgreeWithDenseSampling) {
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Case c(make_tube(0.9, 1.0, 2.0, 32), make_torus(0.6, 0.12, 16, 8));
  int penetrating = 0;
  std::uint64_t far = 0;
  const int poses = test_scale::cases(12);
  for (int k = 0; k < poses; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    // Off the axis, the torus reaching into the wall on one side.
    const double rho = 0.3 + 0.1 * u(rng), phi = 3.14159 * u(rng);
    const Vec3 t = Vec3(rho * std::cos(phi), rho * std::sin(phi), 1.0 + 0.3 * u(rng));
    SCOPED_TRACE("case " + std::to_string(k));
    const auto both = expect_cold_and_warm_agree(c, R, t, 1e-6, 24);
    far += both[0].far_cells + both[1].far_cells;
    penetrating += !both[0].separated;
  }
  EXPECT_GE(penetrating, poses / 3);  // (half the poses under the sanitizers: test_scale)
  EXPECT_GT(far, static_cast<std::uint64_t>(poses));
}

// A mover of needle triangles (a thin torus with few segments along its length: edges about 20
// times longer than its short ones), whose cells are split across their length into three
// (BranchAndBound's needle split): cold and warm certificates agree with dense sampling.
TEST(Clearance, NeedleCellsAgreeWithDenseSampling) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Case c(make_torus(1.0, 0.4, 24, 12), make_torus(0.6, 0.03, 6, 12));
  int penetrating = 0;
  const int poses = test_scale::cases(16);
  for (int k = 0; k < poses; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const Vec3 t = Vec3(1.0, 0.0, 0.0) + 0.45 * Vec3{u(rng), u(rng), u(rng)};
    SCOPED_TRACE("case " + std::to_string(k));
    penetrating += !expect_cold_and_warm_agree(c, R, t, 1e-6, 48)[0].separated;
  }
  EXPECT_GT(penetrating, 6 * poses / 16);
}

// F's supporting planes in the branch and bound (ClearanceOptions::hull): a finely faceted tube
// moved against itself, nearly coaxial and pushed into its own wall, so that the mover's wall
// slivers run along F's across the long edges of its facets. Certificates with the planes are
// rigorous (they meet the certificates without them and dense sampling) and need fewer cells.
TEST(Clearance, HullPlanesCertifyAFacetedTubeWithFewerCells) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Case c(make_tube(0.95, 1.0, 0.6, 48), make_tube(0.95, 1.0, 0.6, 48));
  const std::shared_ptr<const SupportPlanes> hull = hull_planes_for(c.fixed.mesh());
  ASSERT_NE(hull, nullptr);
  EXPECT_FALSE(hull->convex());
  std::uint64_t with = 0, without = 0;
  const int poses = test_scale::cases(6);
  for (int k = 0; k < poses; ++k) {
    const double tilt = 0.01 * u(rng);
    const Vec3 tilt_axis = Vec3{u(rng), u(rng), 0.0}.normalized();
    const double spin = 3.14159 * u(rng);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(tilt, tilt_axis).toRotationMatrix() *
                              Eigen::AngleAxisd(spin, Vec3::UnitZ()).toRotationMatrix();
    const double phi = 3.14159 * u(rng), shift = 0.006 + 0.003 * u(rng);
    const Vec3 t(shift * std::cos(phi), shift * std::sin(phi), 0.05 * u(rng));
    const MoverOrientation o = make_mover_orientation(c.mover, R);
    ClearanceOptions opt;
    opt.tolerance = 1e-6;
    const ClearanceResult a = certify_clearance(c.fixed, c.mover, c.comps, o, t, opt);
    opt.hull = hull.get();
    const ClearanceResult b = certify_clearance(c.fixed, c.mover, c.comps, o, t, opt);
    const Interval ref = sampled_enclosure(c.fixed, o.placed(t), c.mover.faces, 12);
    SCOPED_TRACE(::testing::Message() << std::setprecision(17) << "case " << k << " t = (" << t.x() << ", " << t.y()
                                      << ", " << t.z() << ")");
    ASSERT_TRUE(a.tolerance_reached && b.tolerance_reached);
    EXPECT_LT(b.clearance.hi, -0.001);  // into the wall
    EXPECT_LE(b.clearance.lo, a.clearance.hi);
    EXPECT_GE(b.clearance.hi, a.clearance.lo);
    EXPECT_LE(b.clearance.lo, ref.hi);
    EXPECT_GE(b.clearance.hi, ref.lo);
    EXPECT_LE(b.clearance.width(), 1e-6 * 1.001);
    EXPECT_LE(b.cells, a.cells);
    with += b.cells;
    without += a.cells;
  }
  // 18 % fewer on the first three poses (the sanitizers' share: test_scale), 42 % on all six.
  EXPECT_LT(10 * with, 9 * without) << "with the planes " << with << " cells, without " << without;
}

// The pair-distance path's budget (ClearanceOptions::pair_budget): past it the branch and bound
// decides. Apart, crossing and touching-close poses of two faceted tubes with a budget of one pair:
// every certificate reaches the tolerance, none is decided by the distance path, and each interval
// meets the unbudgeted one and the dense-sampling enclosure (all hold the same c); a budget the
// path stays within changes nothing.
TEST(Clearance, PairBudgetHandsOverToTheBranchAndBound) {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Case c(make_tube(0.95, 1.0, 0.6, 48), make_tube(0.95, 1.0, 0.6, 48));
  const int poses = test_scale::cases(6);
  int apart = 0, crossing = 0;
  for (int k = 0; k < poses; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const Vec3 d = random_direction(rng);
    const double shift = k % 2 == 0 ? 2.2 : 1.7 + 0.2 * u(rng);  // even: apart (the tubes' spheres)
    const Vec3 t = shift * d;
    const MoverOrientation o = make_mover_orientation(c.mover, R);
    ClearanceOptions opt;
    opt.tolerance = 1e-6;
    const ClearanceResult a = certify_clearance(c.fixed, c.mover, c.comps, o, t, opt);
    opt.pair_budget = a.pair_tests + 1;
    const ClearanceResult same = certify_clearance(c.fixed, c.mover, c.comps, o, t, opt);
    opt.pair_budget = 1;
    const ClearanceResult b = certify_clearance(c.fixed, c.mover, c.comps, o, t, opt);
    const Interval ref = sampled_enclosure(c.fixed, o.placed(t), c.mover.faces, 12);
    SCOPED_TRACE(::testing::Message() << std::setprecision(17) << "case " << k << " t = (" << t.x() << ", " << t.y()
                                      << ", " << t.z() << "), pair tests " << a.pair_tests);
    ASSERT_TRUE(a.tolerance_reached && b.tolerance_reached);
    EXPECT_EQ(same.clearance.lo, a.clearance.lo);
    EXPECT_EQ(same.clearance.hi, a.clearance.hi);
    EXPECT_FALSE(b.separated);
    EXPECT_LE(b.pair_tests, 2u);
    EXPECT_LE(b.clearance.lo, a.clearance.hi);
    EXPECT_GE(b.clearance.hi, a.clearance.lo);
    EXPECT_LE(b.clearance.lo, ref.hi);
    EXPECT_GE(b.clearance.hi, ref.lo);
    EXPECT_LE(b.clearance.width(), 1e-6 * 1.001);
    (a.separated ? apart : crossing) += 1;
  }
  EXPECT_GT(apart, 0);
  EXPECT_GT(crossing, 0);
}

// At a penetrating target, a hinted mover point strictly inside F skips the pair-distance path (it
// could only find a crossing pair and hand over): no pair tested, and the same interval as the
// branch and bound alone from that hint. A hint outside F, or a target >= 0, still runs the path.
// Two thin tubes across each other (the pair path's worst case: overlapping slivers).
TEST(Clearance, HintInsideFSkipsThePairPathAtPenetratingTargets) {
  std::mt19937_64 rng(31);
  Case c(make_tube(0.95, 1.0, 0.6, 48), make_tube(0.95, 1.0, 0.6, 48));
  int skipped = 0, ran = 0;
  for (int k = 0; k < 12 && skipped < 3; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const Vec3 t = 1.75 * random_direction(rng);
    const MoverOrientation o = make_mover_orientation(c.mover, R);
    const std::vector<Vec3> P = o.placed(t);
    std::int64_t in = -1, out = -1;  // faces whose placed centroid is inside / outside F
    for (std::size_t f = 0; f < c.mover.faces.size(); ++f) {
      const Face& q = c.mover.faces[f];
      const int side = c.fixed.side((P[q[0]] + P[q[1]] + P[q[2]]) / 3.0);
      if (side < 0 && in < 0) in = static_cast<std::int64_t>(f);
      if (side > 0 && out < 0) out = static_cast<std::int64_t>(f);
    }
    if (in < 0 || out < 0) continue;
    SCOPED_TRACE(::testing::Message() << std::setprecision(17) << "case " << k << " t = (" << t.x() << ", " << t.y()
                                      << ", " << t.z() << "), inside face " << in);
    ClearanceOptions opt;
    opt.tolerance = 1e-6;
    opt.target = -0.01;
    opt.hint_face = in;
    const ClearanceResult hinted = certify_clearance(c.fixed, c.mover, c.comps, o, t, opt);
    opt.try_distance_path = false;
    const ClearanceResult alone = certify_clearance(c.fixed, c.mover, c.comps, o, t, opt);
    EXPECT_EQ(hinted.pair_tests, 0u);
    EXPECT_EQ(hinted.clearance.lo, alone.clearance.lo);
    EXPECT_EQ(hinted.clearance.hi, alone.clearance.hi);
    EXPECT_LT(hinted.clearance.hi, 0.0);
    const Interval ref = sampled_enclosure(c.fixed, P, c.mover.faces, 12);
    EXPECT_LE(hinted.clearance.lo, ref.hi);
    EXPECT_GE(hinted.clearance.hi, ref.lo);
    ++skipped;
    opt.try_distance_path = true;
    opt.hint_face = out;
    EXPECT_GT(certify_clearance(c.fixed, c.mover, c.comps, o, t, opt).pair_tests, 0u);
    opt.hint_face = in;
    opt.target = 0.0;
    EXPECT_GT(certify_clearance(c.fixed, c.mover, c.comps, o, t, opt).pair_tests, 0u);
    ++ran;
  }
  EXPECT_EQ(skipped, 3);
  EXPECT_EQ(ran, 3);
}

// A branch and bound warm-started from the previous pose's frontier (shifted bounds, and the cells'
// translated depth bounds) must give a rigorous certificate too: along approaches into a torus,
// chained warm certificates agree with cold ones and with the dense-sampling enclosure; steps must
// use the warm start and its depth bounds.
TEST(Clearance, WarmStartFromTheLastFrontierStaysRigorous) {
  std::mt19937_64 rng(21);
  Case c(make_torus(1.0, 0.4, 24, 12), make_icosphere(0.5, 1));
  int warm_runs = 0, with_depth_bounds = 0;
  for (int k = 0; k < 6; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const Vec3 dir = random_direction(rng);
    const MoverOrientation o = make_mover_orientation(c.mover, R);
    ClearanceFrontier frontier;
    ClearanceOptions warm;
    warm.tolerance = 1e-6;
    warm.frontier = &frontier;
    for (int step = 0; step < 8; ++step) {
      // From touching the tube's outside towards its core, in steps of varying length.
      const Vec3 t = Vec3(1.0, 0.0, 0.0) + (0.9 - 0.07 * step - 0.01 * (step % 3)) * dir;
      const bool had_frontier = frontier.valid;
      const ClearanceResult w = certify_clearance(c.fixed, c.mover, c.comps, o, t, warm);
      const ClearanceResult cold = c.run(R, t, 1e-6);
      warm_runs += had_frontier && !w.separated;
      with_depth_bounds += had_frontier && !frontier.depth.empty();  // translated depth bounds were kept
      SCOPED_TRACE("case " + std::to_string(k) + " step " + std::to_string(step));
      EXPECT_TRUE(w.tolerance_reached);
      EXPECT_LE(w.clearance.lo, cold.clearance.hi) << w.clearance.lo << " " << w.clearance.hi;
      EXPECT_GE(w.clearance.hi, cold.clearance.lo) << w.clearance.lo << " " << w.clearance.hi;
      const Interval ref = sampled_enclosure(c.fixed, o.placed(t), c.mover.faces, 8);
      EXPECT_LE(w.clearance.lo, ref.hi);
      EXPECT_GE(w.clearance.hi, ref.lo);
      EXPECT_LE(w.clearance.width(), w.separated ? 1e-12 : 1e-6 * 1.001);
    }
  }
  EXPECT_GT(warm_runs, 10);
  EXPECT_GT(with_depth_bounds, 10);
}

// The branch and bound keeps its storage per thread between runs: a run must leave nothing behind.
// The same cold certificate before and after a long warm-started sequence is the same to the bit,
// and so is the frontier it exports.
TEST(Clearance, RunsLeaveNothingBehindInTheirStorage) {
  std::mt19937_64 rng(5);
  Case c(make_torus(1.0, 0.4, 24, 12), make_icosphere(0.5, 1));
  const Eigen::Matrix3d R = random_rotation(rng);
  const Vec3 dir = random_direction(rng);
  const MoverOrientation o = make_mover_orientation(c.mover, R);
  const Vec3 t0 = Vec3(1.0, 0.0, 0.0) + 0.6 * dir;
  const auto cold = [&](ClearanceFrontier* f) {
    ClearanceOptions opt;
    opt.tolerance = 1e-6;
    opt.frontier = f;
    return certify_clearance(c.fixed, c.mover, c.comps, o, t0, opt);
  };
  ClearanceFrontier before, after;
  const ClearanceResult a = cold(&before);
  ASSERT_FALSE(a.separated);
  ClearanceFrontier frontier;
  ClearanceOptions warm;
  warm.tolerance = 1e-7;
  warm.frontier = &frontier;
  for (int step = 0; step < 6; ++step)
    (void)certify_clearance(c.fixed, c.mover, c.comps, o, Vec3(1.0, 0.0, 0.0) + (0.9 - 0.05 * step) * dir, warm);
  EXPECT_GT(frontier.cells.size(), before.cells.size());
  const ClearanceResult b = cold(&after);
  EXPECT_EQ(a.clearance.lo, b.clearance.lo);
  EXPECT_EQ(a.clearance.hi, b.clearance.hi);
  EXPECT_EQ(a.cells, b.cells);
  ASSERT_EQ(before.cells.size(), after.cells.size());
  for (std::size_t i = 0; i < before.cells.size(); ++i) {
    EXPECT_EQ(before.cells[i].lower, after.cells[i].lower) << i;
    EXPECT_EQ(before.cells[i].id, after.cells[i].id) << i;
  }
  EXPECT_EQ(before.depth.size(), after.depth.size());
}

TEST(PlacePose, PlannedStarts) {
  const double band = 0.25;
  const auto S = PoseStart::Surface, F = PoseStart::Far, O = PoseStart::Offset;
  // Default policy: the surface at or below 0, far above; the band plays no part.
  EXPECT_EQ(planned_start(-3.0, true, StartPolicy::NoOffsets, band), S);
  EXPECT_EQ(planned_start(0.0, true, StartPolicy::NoOffsets, band), S);
  EXPECT_EQ(planned_start(0.1, true, StartPolicy::NoOffsets, band), F);
  // Offsets: every target but 0, except penetrating ones within kNearSurfaceBands bands.
  EXPECT_EQ(planned_start(0.0, true, StartPolicy::Offsets, band), S);
  EXPECT_EQ(planned_start(0.01, true, StartPolicy::Offsets, band), O);
  EXPECT_EQ(planned_start(-0.01, true, StartPolicy::Offsets, band), S);
  EXPECT_EQ(planned_start(-0.99 * kNearSurfaceBands * band, true, StartPolicy::Offsets, band), S);
  EXPECT_EQ(planned_start(-kNearSurfaceBands * band, true, StartPolicy::Offsets, band), O);
  EXPECT_EQ(planned_start(-3.0, true, StartPolicy::Offsets, band), O);
  // Without polishing the level's own offset is the pose, however near the surface.
  EXPECT_EQ(planned_start(-0.01, false, StartPolicy::Offsets, band), O);
  EXPECT_EQ(planned_start(-0.01, false, StartPolicy::NoOffsets, band), O);
  EXPECT_EQ(planned_start(0.0, false, StartPolicy::Offsets, band), S);
}

// Long faces (a quarter of the bounding-box diagonal or longer): a finely faceted rod's side
// slivers are, a sphere's faces are not; a pose against or with such a part keeps the sweep trees.
TEST(PlacePose, LongFacesKeepTheSweepTrees) {
  const TriangleMesh rod = make_cylinder(0.05, 10.0, 64);  // 128 side slivers, 62 fan faces per cap
  const TriangleMesh sphere = make_icosphere(1.0, 2);
  EXPECT_GE(long_face_share(rod), 0.25);
  EXPECT_LT(long_face_share(rod), 1.0);  // the caps' faces are short
  EXPECT_EQ(long_face_share(sphere), 0.0);
  EXPECT_EQ(long_face_share(TriangleMesh()), 0.0);
  const SignedDistance rod_sd(rod), sphere_sd(sphere);
  EXPECT_TRUE(make_approach_setup(rod_sd, rod).keep_sweep_trees);
  EXPECT_TRUE(make_approach_setup(rod_sd, sphere).keep_sweep_trees);
  EXPECT_TRUE(make_approach_setup(sphere_sd, rod).keep_sweep_trees);
  EXPECT_FALSE(make_approach_setup(sphere_sd, sphere).keep_sweep_trees);
}

// A mover of at least 2^18 faces gets, per orientation, its own sweep tree's shape as the box
// tree, refitted to the rotated vertices (make_orientation_frame): the same nodes and order, every
// leaf's box exactly its triangle's rotated corners', every parent's box the union of its
// children's; and poses placed from that frame are certified on target.
TEST(PlacePose, LargeMoversGetTheirOwnTreeRefitted) {
  const TriangleMesh sphere = make_icosphere(1.0, 2);
  const SignedDistance fixed(sphere);
  const TriangleMesh mover = make_icosphere(0.3, 7);  // 327,680 faces
  ASSERT_GE(mover.faces.size(), std::size_t(1) << 18);
  const ApproachSetup setup = make_approach_setup(fixed, mover);
  const SweepMesh level0 = make_sweep_mesh(sphere.vertices, sphere.faces);
  std::mt19937_64 rng(3);
  const OrientationFrame frame = make_orientation_frame(setup, random_rotation(rng));
  const Bvh<Aabb>& boxes = frame.orientation.boxes;
  const auto& own = setup.mover_sweep->tree;
  ASSERT_EQ(boxes.nodes.size(), own.nodes.size());
  ASSERT_EQ(boxes.order, own.order);
  for (std::size_t k = 0; k < boxes.nodes.size(); ++k) {
    const auto& n = boxes.nodes[k];
    ASSERT_EQ(n.first, own.nodes[k].first);
    ASSERT_EQ(n.count, own.nodes[k].count);
    Aabb expected;
    if (n.count > 0) {
      for (std::uint32_t i = 0; i < n.count; ++i)
        for (std::uint32_t v : mover.faces[boxes.order[n.first + i]]) expected.extend(frame.orientation.rotated[v]);
    } else {
      expected.extend(boxes.nodes[n.first].bv);
      expected.extend(boxes.nodes[n.first + 1].bv);
    }
    ASSERT_TRUE(n.bv.lo == expected.lo && n.bv.hi == expected.hi) << k;
  }
  PoseOptions opt;
  opt.tolerance = 1e-6;
  for (double target : {0.0, 0.05, -0.1}) {
    const PoseOutcome p = place_pose(setup, frame, &level0, random_direction(rng), target, opt);
    ASSERT_TRUE(p.contact);
    EXPECT_TRUE(p.certified);
    EXPECT_TRUE(p.on_target) << target << ": [" << p.clearance.lo << ", " << p.clearance.hi << "]";
  }
}

TEST(PlacePose, PolishedPosesHitTheTarget) {
  const TriangleMesh sphere = make_icosphere(1.0, 2);
  const SignedDistance fixed(sphere);
  const ApproachSetup setup = make_approach_setup(fixed, sphere);
  const SweepMesh level0 = make_sweep_mesh(sphere.vertices, sphere.faces);
  PoseOptions opt;
  opt.tolerance = 1e-6;
  std::mt19937_64 rng(5);
  for (int k = 0; k < 6; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const OrientationFrame frame = make_orientation_frame(setup, R);
    const Vec3 dir = random_direction(rng);
    for (double target : {0.0, 0.1, -0.2}) {
      // Raw placement against the surface itself, so polishing to a negative target starts from a
      // pose before the crossing, and to a positive one from far away.
      const PoseOutcome p = place_pose(setup, frame, &level0, dir, target, opt);
      ASSERT_TRUE(p.contact);
      EXPECT_TRUE(p.certified);
      EXPECT_TRUE(p.on_target) << target << ": [" << p.clearance.lo << ", " << p.clearance.hi << "] steps " << p.steps;
      EXPECT_GE(p.clearance.lo, target - opt.tolerance);
      EXPECT_LE(p.clearance.hi, target + opt.tolerance);
    }
  }
}

// Separated targets beyond the separated advance's reach step by certificates at
// kSeparatedStepRelativeTolerance, whatever wider width the options give: polished with the default
// width and with that one, such a pose does the same work and lands at the same place. A
// penetrating target takes the options' width as it is (its work differs), and both reach the target.
TEST(PlacePose, SeparatedTargetsBeyondTheAdvanceStepByTighterCertificates) {
  const Scene scene(make_icosphere(1.0, 2), make_icosphere(0.25, 1));
  const ApproachSetup& setup = scene.setup;
  PoseOptions opt;
  opt.tolerance = 1e-7;
  opt.support_planes = false;  // the sphere is convex: its planes would certify without cells
  const double beyond = 2.0 * setup.advance_target_limit + 0.05;
  ASSERT_GT(setup.advance_target_limit, 0.0);
  EXPECT_TRUE(separated_steps_by_certificates(setup, beyond, opt));
  EXPECT_FALSE(separated_steps_by_certificates(setup, 0.5 * setup.advance_target_limit, opt));
  EXPECT_FALSE(separated_steps_by_certificates(setup, -0.1, opt));
  PoseOptions no_advance = opt;
  no_advance.separated_advance = false;
  EXPECT_TRUE(separated_steps_by_certificates(setup, 0.5 * setup.advance_target_limit, no_advance));
  ASSERT_LT(kSeparatedStepRelativeTolerance, kStepRelativeTolerance);
  std::mt19937_64 rng(29);
  std::uint64_t penetrating_cells[2] = {0, 0};
  for (int k = 0; k < 3; ++k) {
    const OrientationFrame frame = make_orientation_frame(setup, random_rotation(rng));
    const Vec3 dir = random_direction(rng);
    for (double target : {beyond, -0.1}) {
      PoseOutcome at[2];
      for (int w = 0; w < 2; ++w) {
        PoseOptions o = opt;
        o.start = target > 0.0 ? PoseStart::Far : PoseStart::Surface;
        o.step_relative_tolerance = w == 0 ? kStepRelativeTolerance : kSeparatedStepRelativeTolerance;
        at[w] = place_pose(setup, frame, &scene.surface, dir, target, o);
        ASSERT_TRUE(at[w].contact);
        EXPECT_TRUE(at[w].certified && at[w].on_target) << target << " " << w << " " << at[w].reason;
      }
      if (target > 0.0) {
        EXPECT_EQ(at[0].clearance_cells, at[1].clearance_cells) << target;
        EXPECT_EQ(at[0].lambda, at[1].lambda) << target;
        EXPECT_GT(at[0].steps, 1) << "certificate steps are what this test is about";
      } else {
        penetrating_cells[0] += at[0].clearance_cells;
        penetrating_cells[1] += at[1].clearance_cells;
        EXPECT_NEAR(at[0].lambda, at[1].lambda, 4 * opt.tolerance);
      }
    }
  }
  EXPECT_NE(penetrating_cells[0], penetrating_cells[1]) << "a penetrating target takes the options' width";
}

// Every start (the surface itself for targets <= 0, far away for any target) reaches the target
// with a certified clearance, and the polished poses of one approach agree within the tolerances
// (the clearance is monotone near a head-on first crossing of a convex shape). A line that misses
// the fixed object gives no pose from either start.
TEST(PlacePose, SurfaceAndFarStartsReachTheTarget) {
  const TriangleMesh sphere = make_icosphere(1.0, 2);
  const SignedDistance fixed(sphere);
  const TriangleMesh mover = make_icosphere(0.25, 1);
  const ApproachSetup setup = make_approach_setup(fixed, mover);
  const SweepMesh surface = make_sweep_mesh(sphere.vertices, sphere.faces);
  PoseOptions opt;
  opt.tolerance = 1e-7;
  std::mt19937_64 rng(11);
  for (int k = 0; k < 4; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const OrientationFrame frame = make_orientation_frame(setup, R);
    const Vec3 dir = random_direction(rng);
    for (double target : {0.0, -0.1, 0.15}) {
      opt.start = PoseStart::Far;
      const PoseOutcome far = place_pose(setup, frame, nullptr, dir, target, opt);
      ASSERT_TRUE(far.contact);
      EXPECT_TRUE(far.on_target) << target << ": [" << far.clearance.lo << ", " << far.clearance.hi << "]";
      EXPECT_GT(far.steps, 0);
      if (target > 0.0) continue;
      opt.start = PoseStart::Surface;
      const PoseOutcome near = place_pose(setup, frame, &surface, dir, target, opt);
      ASSERT_TRUE(near.contact);
      EXPECT_TRUE(near.on_target) << target << ": [" << near.clearance.lo << ", " << near.clearance.hi << "]";
      if (target == 0.0) {
        EXPECT_EQ(near.steps, 0);  // the exact first contact is on target
      }
      // Both are on the first crossing of a sphere by a sphere, head-on: lambda within a few tolerances.
      EXPECT_NEAR(near.lambda, far.lambda, 1e-5) << target;
    }
  }
  // A mover offset sideways by more than both radii never reaches the fixed sphere.
  ApproachSetup aside = setup;
  aside.fixed_ref = setup.fixed_ref + Vec3(0.0, 3.0, 0.0);
  const OrientationFrame frame = make_orientation_frame(aside, Eigen::Matrix3d::Identity());
  for (PoseStart start : {PoseStart::Far, PoseStart::Surface}) {
    opt.start = start;
    const PoseOutcome p = place_pose(aside, frame, &surface, Vec3(1, 0, 0), -0.1, opt);
    EXPECT_FALSE(p.contact) << to_string(start);
    EXPECT_EQ(p.reason, "no-contact");
  }
  // A target > 0 from far away, by certified steps and by the separated advance (which proves the
  // whole line in one traversal).
  opt.start = PoseStart::Far;
  for (bool separated_advance : {false, true}) {
    opt.separated_advance = separated_advance;
    const PoseOutcome p = place_pose(aside, frame, nullptr, Vec3(1, 0, 0), 0.15, opt);
    EXPECT_FALSE(p.contact) << separated_advance;
    EXPECT_EQ(p.reason, "no-contact");
    if (separated_advance) {
      EXPECT_LE(p.steps, 1);
    }
  }
}

// Long steps proved from both ends (where c is flat) never pass an earlier crossing: along each
// approach into a torus (c dips at the tube, rises in the hole, dips again), no pose between the
// polished one and the far start is certified below the target. Checked with long steps on and
// off; the long steps must actually be tried, and some rejected ones kept after the plain step
// (3 of 66 tries at the default scale).
TEST(PlacePose, LongStepsNeverPassAnEarlierCrossing) {
  const TriangleMesh torus = make_torus(1.0, 0.35, 24, 12);
  const SignedDistance fixed(torus);
  const TriangleMesh mover = make_icosphere(0.2, 1);
  const ApproachSetup setup = make_approach_setup(fixed, mover);
  const SweepMesh surface = make_sweep_mesh(torus.vertices, torus.faces);
  ApproachSetup with_trees = setup;
  attach_surface_sweep(with_trees, surface);
  PoseOptions opt;
  opt.tolerance = 1e-6;
  opt.start = PoseStart::Far;
  std::mt19937_64 rng(23);
  int tries = 0, kept = 0, placed = 0;
  const int lines = test_scale::cases(12);
  for (int k = 0; k < lines; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const OrientationFrame frame = make_orientation_frame(setup, R);
    // Mostly grazing lines: along the torus' plane, offset from the centre.
    Vec3 dir = random_direction(rng);
    if (k % 2 == 0) dir = Vec3(dir.x(), dir.y(), 0.1 * dir.z()).normalized();
    for (double target : {-0.15, -0.1, 0.05}) {
      // Long steps, plain certified steps, and (targets > 0) the separated advance.
      // Mode 3: the separated advance and the pair-distance path on the sweep trees.
      for (int mode = 0; mode < 4; ++mode) {
        opt.two_sided_steps = mode == 0;
        opt.separated_advance = mode >= 2;
        const PoseOutcome p = place_pose(mode == 3 ? with_trees : setup, frame, nullptr, dir, target, opt);
        tries += p.two_sided_tries;
        kept += p.kept_tries;
        if (!p.contact) continue;
        ++placed;
        EXPECT_TRUE(p.on_target);
        SCOPED_TRACE("mode " + std::to_string(mode));
        expect_no_earlier_crossing(fixed, mover, frame, dir, setup, p.lambda, target, opt.tolerance, 300);
      }
    }
  }
  EXPECT_GT(placed, 20 * lines / 12) << placed;
  EXPECT_GT(tries, 10 * lines / 12) << tries;
  if (!test_scale::kSanitized) {
    EXPECT_GT(kept, 0) << kept << " of " << tries;  // 3 here, 1 in half the lines
  }
}

// A convex F's supporting planes (distance/support_planes.h): the certificate from them agrees with
// the branch and bound's at penetrating poses (both rigorous: their intervals meet) and is as tight
// as asked; polishing by their steps lands on the first crossing (every pose sampled between it and
// the start certified at or above the target by the branch and bound alone) in far fewer steps.
TEST(SupportPlanes, CertificatesAgreeWithTheBranchAndBound) {
  for (const TriangleMesh& F : {make_box(Vec3(-1, -0.5, -0.7), Vec3(1, 0.5, 0.7)), make_icosphere(1.0, 1)}) {
    Case c(F, make_icosphere(0.3, 1));
    const SupportPlanes S = SupportPlanes::build(F);
    ASSERT_TRUE(S.convex());
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-0.9, 0.9);
    int by_planes = 0;
    for (int k = 0; k < 40; ++k) {
      const MoverOrientation o = make_mover_orientation(c.mover, random_rotation(rng));
      const Vec3 t{u(rng), 0.6 * u(rng), 0.7 * u(rng)};
      ClearanceOptions plain, planes;
      plain.tolerance = planes.tolerance = 1e-8;
      planes.support = &S;
      const ClearanceResult a = certify_clearance(c.fixed, c.mover, c.comps, o, t, plain);
      const ClearanceResult b = certify_clearance(c.fixed, c.mover, c.comps, o, t, planes);
      ASSERT_TRUE(a.tolerance_reached && b.tolerance_reached);
      EXPECT_LE(std::max(a.clearance.lo, b.clearance.lo), std::min(a.clearance.hi, b.clearance.hi))
          << std::setprecision(17) << "t " << t.transpose() << ": [" << a.clearance.lo << ", " << a.clearance.hi
          << "] against [" << b.clearance.lo << ", " << b.clearance.hi << "]";
      EXPECT_LE(b.clearance.width(), 1e-8 + 4 * b.transform_error + 1e-15);
      if (b.cells == 0 && b.pair_tests == 0) ++by_planes;
    }
    // The mover penetrates at most of these poses, where the planes decide alone.
    EXPECT_GT(by_planes, 20);
  }
}

// The walk over the mover's box tree (least_halfspace_bound) loses nothing by pruning: it finds the
// least triangle bound that a loop over every triangle finds, up to rounding. (It may find a few
// ulps more: a node set aside by its own bound, which is valid for all its triangles, may hold a
// triangle whose bound rounds a little lower.)
TEST(SupportPlanes, TreeWalkFindsTheLeastTriangleBound) {
  Case c(make_box(Vec3(-1, -0.5, -0.7), Vec3(1, 0.5, 0.7)), make_icosphere(0.4, 2));
  const SupportPlanes S = SupportPlanes::build(c.fixed.mesh());
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (int k = 0; k < 30; ++k) {
    const MoverOrientation o = make_mover_orientation(c.mover, random_rotation(rng));
    const Vec3 t{u(rng), u(rng), u(rng)};
    const HalfspaceMinimum walk = least_halfspace_bound(S, o, t);
    const PlacedView P = o.placed_view(t);
    double least = HUGE_VAL;
    for (const Face& f : c.mover.faces) {
      const std::array<Vec3, 3> v{P[f[0]], P[f[1]], P[f[2]]};
      least = std::min(least, halfspace_bound(S, v.data(), 3, Vec3::Zero()).lower);
    }
    EXPECT_GE(walk.lower, least) << std::setprecision(17) << "t " << t.transpose();
    EXPECT_LE(walk.lower - least, 1e-12) << std::setprecision(17) << "t " << t.transpose() << " walk " << walk.lower
                                         << " loop " << least;
  }
}

// The walk on the mover's sweep tree (oriented boxes, placed at another pose t0 and moved to t),
// on a finely faceted rod crossing a copy of itself at random tilts, where the world-aligned boxes
// of its long side slivers are loose: its least bound is the least triangle bound (fails if the
// shift to t is left out: nodes would be bounded where the mover is not), it is a lower end of s
// at points of the placed mover, and its steps keep c at or above the target (certificates along
// each step).
TEST(SupportPlanes, WalkOnOrientedBoxesAlongARotatedRod) {
  const TriangleMesh rod = make_cylinder(0.05, 2.0, 200);
  Case c(rod, rod);
  const SupportPlanes S = SupportPlanes::build(rod);
  ASSERT_TRUE(S.convex());
  const SweepMesh own = make_sweep_mesh(rod.vertices, rod.faces);
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int stepped = 0, penetrating = 0;
  for (int k = 0; k < test_scale::cases(12); ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const MoverOrientation o = make_mover_orientation(rod, R);
    // The mover's middle near F's axis, its axis tilted: the two rods cross.
    const Vec3 t = Vec3{0.045 * u(rng), 0.045 * u(rng), 1.0} - R * Vec3(0.0, 0.0, 1.0);
    const Vec3 t0 = t + Vec3(0.3, -0.2, 0.1);
    const SweepMesh at_t0 = placed_sweep_mesh(own, R, t0, o.placed(t0), o.transform_error(t0));
    const SweepTrees trees{nullptr, &at_t0, t0};
    const PlacedView P = o.placed_view(t);
    double least = HUGE_VAL;
    for (const Face& f : rod.faces) {
      const std::array<Vec3, 3> v{P[f[0]], P[f[1]], P[f[2]]};
      least = std::min(least, halfspace_bound(S, v.data(), 3, Vec3::Zero()).lower);
    }
    const HalfspaceMinimum walk = least_halfspace_bound(S, o, t, nullptr, &trees, static_cast<std::int64_t>(k));
    EXPECT_GE(walk.lower, least) << std::setprecision(17) << "case " << k;
    EXPECT_LE(walk.lower - least, 1e-12) << std::setprecision(17) << "case " << k << " walk " << walk.lower
                                         << " loop " << least;
    penetrating += walk.lower < 0.0;
    for (std::size_t f = 0; f < rod.faces.size(); f += 7) {
      const Face& face = rod.faces[f];
      const Vec3 x = (P[face[0]] + P[face[1]] + P[face[2]]) / 3.0;
      ASSERT_LE(walk.lower, c.fixed.signed_distance(x).hi) << std::setprecision(17) << "case " << k << " face " << f;
    }
    // A step towards a deeper target, along a random direction.
    const Vec3 dir = random_direction(rng);
    ClearanceOptions copt;
    copt.tolerance = 1e-9;
    const ClearanceResult c0 = certify_clearance(c.fixed, rod, c.comps, o, t, copt);
    const double target = c0.clearance.lo - 0.01;
    const double slack = 8.0 * 0x1p-52 * (t.cwiseAbs().maxCoeff() + 4.0);
    const HalfspaceAdvance a = halfspace_advance(S, o, t, dir, target, slack, 4.0, nullptr, &trees, walk.face);
    ASSERT_GE(a.h, 0.0);
    if (!(a.h > 0.0)) continue;
    ++stepped;
    for (double at : {1.0, 0.5, 0.5 * (1.0 + u(rng))}) {
      const double mu = at * a.h;
      const Vec3 t2(t[0] - mu * dir[0], t[1] - mu * dir[1], t[2] - mu * dir[2]);
      const ClearanceResult r = certify_clearance(c.fixed, rod, c.comps, o, t2, copt);
      ASSERT_GE(r.clearance.hi, target) << std::setprecision(17) << "case " << k << " h " << a.h << " at " << at
                                        << " clearance [" << r.clearance.lo << ", " << r.clearance.hi << "]";
    }
  }
  EXPECT_GT(penetrating, test_scale::cases(12) / 2);
  EXPECT_GT(stepped, test_scale::cases(12) / 2);
}

// Polishing to a tight tolerance from the given start (the supporting planes' place_pose tests).
PoseOptions tight_options(PoseStart start) {
  PoseOptions o;
  o.tolerance = 1e-7;
  o.start = start;
  return o;
}

// At separated targets a finely faceted rod's planes step first (ApproachSetup::separated_planes):
// poses on target and on the first crossing, as without the planes: every pose sampled in the 0.1
// before it (densest near it) and at a few farther ones certified at or above the target. (The
// lambdas of the two may differ by more than the tolerance where c falls slowly: each is within
// the tolerance of the target in c, not of the other in lambda.)
TEST(SupportPlanes, SeparatedStepsOnAFinelyFacetedRod) {
  const TriangleMesh rod = make_cylinder(0.05, 1.0, 260);
  const Scene scene(rod, rod);
  ASSERT_TRUE(scene.setup.support);
  ASSERT_TRUE(scene.setup.separated_planes);
  const ApproachSetup setup = scene.attached();
  PoseOptions opt = tight_options(PoseStart::Far);
  std::mt19937_64 rng(41);
  int placed = 0;
  const int cases = test_scale::cases(6);
  for (int k = 0; k < cases; ++k) {
    const OrientationFrame frame = make_orientation_frame(setup, random_rotation(rng));
    const Vec3 dir = random_direction(rng);
    for (double target : {0.002, 0.02}) {
      for (bool planes : {false, true}) {
        opt.support_planes = planes;
        const PoseOutcome p = place_pose(setup, frame, nullptr, dir, target, opt);
        if (!p.contact) continue;
        placed += planes;
        EXPECT_TRUE(p.on_target && p.certified) << target;
        // On the sweep trees: the rods' oriented boxes part the slivers' pairs.
        const SweepTrees trees{&scene.surface, &frame.swept, frame.t0};
        ClearanceOptions copt;
        copt.tolerance = 1e-4;
        copt.sweep_trees = &trees;
        for (int i = 1; i <= 24; ++i) {
          const double x = i <= 20 ? 0.1 * (i / 20.0) * (i / 20.0) : 0.1 + 0.3 * (i - 20);
          const ClearanceResult c = certify_clearance(scene.fixed, scene.mover, setup.components, frame.orientation,
                                                      pose_translation(frame, dir, p.lambda + x), copt);
          ASSERT_GE(c.clearance.hi, target - opt.tolerance)
              << std::setprecision(17) << "case " << k << " target " << target << " planes " << planes
              << " pose lambda " << p.lambda << " passed a crossing at lambda " << p.lambda + x;
        }
      }
    }
  }
  EXPECT_GT(placed, cases);
}

TEST(SupportPlanes, StepsLandOnTheFirstCrossing) {
  // A box against a box, and an icosahedron against a 320-face sphere (the mover's tree walked).
  for (int pair = 0; pair < 2; ++pair) {
    const Scene scene(pair ? make_icosphere(1.0, 0) : make_box(Vec3(-1, -0.5, -0.7), Vec3(1, 0.5, 0.7)),
                      pair ? make_icosphere(0.3, 2) : make_box(Vec3(-0.3, -0.1, -0.2), Vec3(0.3, 0.1, 0.2)));
    ASSERT_TRUE(scene.setup.support);
    const ApproachSetup setup = scene.attached();
    PoseOptions opt = tight_options(PoseStart::Surface);
    std::mt19937_64 rng(17);
    int steps_with = 0, steps_without = 0;
    for (int k = 0; k < test_scale::cases(10); ++k) {
      const OrientationFrame frame = make_orientation_frame(setup, random_rotation(rng));
      const Vec3 dir = random_direction(rng);
      for (double target : {-0.02, -0.2, -0.45}) {
        opt.support_planes = false;
        const PoseOutcome plain = place_pose(setup, frame, &scene.surface, dir, target, opt);
        opt.support_planes = true;
        const PoseOutcome p = place_pose(setup, frame, &scene.surface, dir, target, opt);
        ASSERT_EQ(p.contact, plain.contact);
        if (!p.contact) continue;
        EXPECT_TRUE(p.on_target && p.certified) << target;
        steps_with += p.steps;
        steps_without += plain.steps;
        expect_no_earlier_crossing(scene.fixed, scene.mover, frame, dir, setup, p.lambda, target, opt.tolerance, 300);
      }
    }
    EXPECT_LT(2 * steps_with, steps_without) << steps_with << " against " << steps_without;
  }
}

// The separated advance's step (placement/advance.h): from separated poses around a torus, every
// pose up to the step, including its end, has a clearance certified at or above the target (the
// certificate's upper end; its lower end may sit a few ulps below from its own widening), and the
// steps go well beyond the Lipschitz step c_lo - target where the mover comes at a face.
TEST(SeparatedAdvance, StepsKeepTheClearanceAboveTheTarget) {
  Case c(make_torus(1.0, 0.35, 24, 12), make_icosphere(0.2, 1));
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> w(0.0, 1.0);
  int stepped = 0, beyond_lipschitz = 0, landed_near = 0;
  for (int k = 0; k < 40; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    // Placed out from the tube along `out`, coming back along -dir, mostly at a slant.
    const Vec3 out = random_direction(rng);
    const Vec3 dir = (out + (k % 4 ? 0.9 : 0.0) * random_direction(rng)).normalized();
    if (!(dir.dot(out) > 0.3)) continue;
    const MoverOrientation o = make_mover_orientation(c.mover, R);
    const double target = k % 3 == 0 ? 1e-3 : 0.05 + 0.1 * w(rng);
    const Vec3 t = Vec3(1.0, 0.0, 0.0) + (0.8 + 0.8 * w(rng)) * out;
    ClearanceOptions copt;
    copt.tolerance = 1e-9;
    const ClearanceResult c0 = certify_clearance(c.fixed, c.mover, c.comps, o, t, copt);
    if (!(c0.clearance.lo > target)) continue;
    const double h_max = 10.0;
    const double slack = 8.0 * 0x1p-52 * (t.cwiseAbs().maxCoeff() + h_max);
    // On the box trees, and on the sweep trees (the mover's placed at another pose t0, so that the
    // shift between the two poses is part of what is checked).
    const SweepMesh surface = make_sweep_mesh(c.fixed.mesh().vertices, c.fixed.mesh().faces);
    const Vec3 t0 = t + Vec3(0.3, -0.2, 0.1);
    const SweepMesh own = make_sweep_mesh(c.mover.vertices, c.mover.faces);
    const SweepMesh mover_at_t0 = placed_sweep_mesh(own, R, t0, o.placed(t0), o.transform_error(t0));
    const SweepTrees trees{&surface, &mover_at_t0, t0};
    for (const SweepTrees* with : {static_cast<const SweepTrees*>(nullptr), &trees}) {
      const SeparatedAdvance a = separated_advance(c.fixed, o, t, dir, target, slack, h_max, -1, -1, with);
      ASSERT_GE(a.h, 0.0);
      ASSERT_LE(a.h, h_max);
      if (!(a.h > 0.0) || a.h >= h_max) continue;
      ++stepped;
      beyond_lipschitz += a.h > 1.2 * (c0.clearance.lo - target);
      for (double at : {1.0, 0.5, w(rng), w(rng)}) {
        const double mu = at * a.h;
        const Vec3 t2(t[0] - mu * dir[0], t[1] - mu * dir[1], t[2] - mu * dir[2]);
        const ClearanceResult r = certify_clearance(c.fixed, c.mover, c.comps, o, t2, copt);
        ASSERT_GE(r.clearance.hi, target) << std::setprecision(17) << "case " << k << " target " << target << " h "
                                          << a.h << " at " << at << " clearance [" << r.clearance.lo << ", "
                                          << r.clearance.hi << "]" << (with ? " (sweep trees)" : "");
        if (at == 1.0) landed_near += r.clearance.lo - target < 0.01 * (c0.clearance.lo - target);
        // The pair-distance path on the sweep trees encloses the same clearance.
        ClearanceOptions on_trees = copt;
        on_trees.sweep_trees = &trees;
        const ClearanceResult r2 = certify_clearance(c.fixed, c.mover, c.comps, o, t2, on_trees);
        ASSERT_TRUE(r2.clearance.lo <= r.clearance.hi && r.clearance.lo <= r2.clearance.hi)
            << std::setprecision(17) << "case " << k << ": [" << r.clearance.lo << ", " << r.clearance.hi << "] and ["
            << r2.clearance.lo << ", " << r2.clearance.hi << "]";
        EXPECT_LE(r2.clearance.hi - r2.clearance.lo, 2 * copt.tolerance + 1e-12);
      }
    }
  }
  EXPECT_GT(stepped, 30);
  EXPECT_GT(beyond_lipschitz, 10);
  EXPECT_GT(landed_near, 6);
}

// A thin fin standing on a long slab, approached along the slab at a constant height: c is flat
// (the slab), then dips at the fin. A long step from the flat part could land beyond the fin with
// c above the target there; the proof from both ends must refuse it, and the pose must be the
// first crossing, in front of the fin.
TEST(PlacePose, LongStepsStopInFrontOfAThinFin) {
  const TriangleMesh fixed_mesh =
      merge_meshes(make_box(Vec3(-2, -0.5, -0.2), Vec3(2, 0.5, 0)), make_box(Vec3(0.95, -0.5, 0.02), Vec3(0.96, 0.5, 1.5)));
  const SignedDistance fixed(fixed_mesh);
  const TriangleMesh mover = make_icosphere(0.05, 1);
  ApproachSetup setup = make_approach_setup(fixed, mover);
  // The mover's path: z = 0.65 (0.6 above the slab), through the fin at x in [0.95, 0.96].
  setup.fixed_ref = Vec3(0.0, 0.0, 0.65);
  const OrientationFrame frame = make_orientation_frame(setup, Eigen::Matrix3d::Identity());
  PoseOptions opt;
  opt.tolerance = 1e-7;
  opt.start = PoseStart::Far;
  const double target = 0.05;
  int tries = 0;
  // Certified steps (long ones where c is flat, or not), and the separated advance's reach bounds.
  for (int mode = 0; mode < 3; ++mode) {
    opt.two_sided_steps = mode == 0;
    opt.separated_advance = mode == 2;
    const PoseOutcome p = place_pose(setup, frame, nullptr, Vec3(1, 0, 0), target, opt);
    tries += p.two_sided_tries;
    ASSERT_TRUE(p.contact);
    EXPECT_TRUE(p.on_target);
    // In front of the fin: the mover's centre (x = lambda, up to the icosphere's facets) at about
    // 0.96 + 0.05 + 0.05 (a long step from the flat part lands at about 0.82, beyond the fin).
    EXPECT_GT(p.lambda, 1.04) << "mode " << mode;
    EXPECT_LT(p.lambda, 1.07) << "mode " << mode;
  }
  EXPECT_GT(tries, 0);
}

// A slide: a small sphere enters the top face of a slab reaching to x = slab_end at a grazing
// angle (c falls at `slope` of the advance), lambda = 0 with its lowest point 0.15 deep; the pose at
// `target` with steps over a segment (first) and without (second). Both on target and at the first
// crossing (every pose sampled between it and the far start certified at or above the target).
std::array<PoseOutcome, 2> slide_with_and_without_segments(double slab_end, double slope, double target) {
  const SignedDistance fixed(make_box(Vec3(-1, -1, -1), Vec3(slab_end, 1, 0)));
  const TriangleMesh mover = make_icosphere(0.05, 0);
  ApproachSetup setup = make_approach_setup(fixed, mover);
  setup.fixed_ref = Vec3(0.0, 0.0, -0.1);
  const OrientationFrame frame = make_orientation_frame(setup, Eigen::Matrix3d::Identity());
  const Vec3 dir = Vec3(1.0, 0.0, slope).normalized();
  PoseOptions opt;
  opt.tolerance = 1e-7;
  opt.start = PoseStart::Far;
  opt.support_planes = false;  // a convex F: its planes' Newton steps would cross the slide at once
  std::array<PoseOutcome, 2> p;
  for (int mode = 0; mode < 2; ++mode) {
    opt.segment_steps = mode == 0;
    p[mode] = place_pose(setup, frame, nullptr, dir, target, opt);
    SCOPED_TRACE("mode " + std::to_string(mode));
    EXPECT_TRUE(p[mode].contact);
    EXPECT_TRUE(p[mode].on_target);
    if (p[mode].contact)
      expect_no_earlier_crossing(fixed, mover, frame, dir, setup, p[mode].lambda, target, opt.tolerance, 200);
  }
  // The same first crossing (c falls at about `slope` per unit of lambda there).
  EXPECT_NEAR(p[0].lambda, p[1].lambda, 4.0 * opt.tolerance / slope);
  EXPECT_GT(p[0].segment_tries, 0);
  EXPECT_EQ(p[1].segment_tries, 0);
  return p;
}

// Slope 0.05 from 0 to the target over two units: two-sided steps prove twice the gap each, steps
// proved over a whole segment (check_segment_above) many gaps, in far fewer steps.
TEST(PlacePose, SegmentStepsCrossASlideToTheFirstCrossing) {
  const auto p = slide_with_and_without_segments(6.0, 0.05, -0.1);
  EXPECT_LT(3 * p[0].steps, p[1].steps) << p[0].steps << " " << p[1].steps;
}

// A slower slide: c falls at 0.01 of the advance, below the band of the two-step secant's gate
// (1/64), over five units to the target. The slope over a span of poses (a gap four times the
// present one back) still finds it a slide, and segments cross it in a fraction of the two-sided
// steps (66 steps; 689 without segments, 588 with the two-step gate alone).
TEST(PlacePose, SegmentStepsCrossASlowSlideBySlopesOverASpan) {
  const auto p = slide_with_and_without_segments(20.0, 0.01, -0.05);
  EXPECT_LT(4 * p[0].steps, p[1].steps) << p[0].steps << " " << p[1].steps;
}

// The polishing's trace (PoseOptions::trace) reports every certificate, with what it was for, and
// every segment tried, and changes nothing: on the slide above, the traced pose is the untraced
// one, its certificates' cells add up to the pose's, its segment and two-sided events are the
// pose's tries, and its last certificate is the pose's.
TEST(PlacePose, TraceReportsEveryCertificateAndSegmentTry) {
  const SignedDistance fixed(make_box(Vec3(-1, -1, -1), Vec3(6.0, 1, 0)));
  const TriangleMesh mover = make_icosphere(0.05, 0);
  ApproachSetup setup = make_approach_setup(fixed, mover);
  setup.fixed_ref = Vec3(0.0, 0.0, -0.1);
  const OrientationFrame frame = make_orientation_frame(setup, Eigen::Matrix3d::Identity());
  const Vec3 dir = Vec3(1.0, 0.0, 0.05).normalized();
  const double target = -0.1;
  PoseOptions opt;
  opt.tolerance = 1e-7;
  opt.start = PoseStart::Far;
  opt.support_planes = false;
  const PoseOutcome plain = place_pose(setup, frame, nullptr, dir, target, opt);
  std::vector<PolishEvent> events;
  const PolishTrace trace = [&](const PolishEvent& e) { events.push_back(e); };
  opt.trace = &trace;
  const PoseOutcome traced = place_pose(setup, frame, nullptr, dir, target, opt);
  ASSERT_TRUE(traced.on_target);
  EXPECT_EQ(traced.lambda, plain.lambda);
  EXPECT_EQ(traced.clearance.lo, plain.clearance.lo);
  EXPECT_EQ(traced.clearance.hi, plain.clearance.hi);
  EXPECT_EQ(traced.steps, plain.steps);
  std::uint64_t cells = 0;
  int segments = 0, two_sided = 0, certificates = 0;
  const PolishEvent* last = nullptr;
  for (const PolishEvent& e : events) {
    EXPECT_EQ(e.target, target);
    if (e.kind == PolishEvent::Kind::certificate) {
      ++certificates;
      cells += e.work;
      two_sided += e.purpose == PolishPurpose::two_sided;
      last = &e;
    } else if (e.kind == PolishEvent::Kind::segment) {
      ++segments;
      EXPECT_LT(e.to, e.lambda);  // towards F
      EXPECT_LE(e.work, e.budget + 1);
    }
  }
  ASSERT_NE(last, nullptr);
  EXPECT_EQ(events.front().purpose, PolishPurpose::far_start);
  EXPECT_EQ(cells, traced.clearance_cells);
  EXPECT_EQ(segments, traced.segment_tries);
  EXPECT_GT(segments, 0);
  EXPECT_EQ(two_sided, traced.two_sided_tries);
  EXPECT_GT(two_sided, 0);
  EXPECT_GE(certificates, traced.steps);
  EXPECT_EQ(last->lambda, traced.lambda);
  EXPECT_EQ(last->clearance.lo, traced.clearance.lo);
  EXPECT_EQ(last->clearance.hi, traced.clearance.hi);
}

// Segments of poses proved above a floor (check_segment_above) agree with certificates of poses
// sampled along them. Along chords inside a sphere the middle lies deeper than the ends (the depth
// inside a convex solid is concave): among the floors tried are ones both ends' certificates clear
// while the middle's is below, which a bound taken at the ends' poses alone would pass.
TEST(Clearance, SegmentsProvedAboveAFloorAgreeWithSampledPoses) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Case c(make_icosphere(1.0, 3), make_icosphere(0.05, 1));
  int above = 0, dips = 0;
  const int n = test_scale::cases(16);
  for (int k = 0; k < n; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const MoverOrientation o = make_mover_orientation(c.mover, R);
    const Vec3 a = random_direction(rng);
    Vec3 side = random_direction(rng);
    side = (side - side.dot(a) * a).normalized();
    const double angle = 0.02 + 0.1 * u(rng), radius = 0.8 + 0.1 * u(rng);
    const Vec3 ta = radius * a, tb = radius * (std::cos(angle) * a + std::sin(angle) * side);
    ClearanceFrontier frontier;
    ClearanceOptions opt;
    opt.tolerance = 1e-6;
    opt.frontier = &frontier;
    const ClearanceResult ca = certify_clearance(c.fixed, c.mover, c.comps, o, ta, opt);
    const ClearanceResult cb = c.run(R, tb, 1e-6), cm = c.run(R, 0.5 * (ta + tb), 1e-6);
    const double ends = std::min(ca.clearance.lo, cb.clearance.lo);
    const double pad = 2.0 * std::max(o.transform_error(ta), o.transform_error(tb));
    for (double floor : {cm.clearance.hi + 0.25 * (ends - cm.clearance.hi), cm.clearance.lo - 2e-2}) {
      const bool dip = floor > cm.clearance.hi && floor < ends;
      dips += dip;
      const SegmentCheck check = check_segment_above(c.fixed, o, frontier, ta, tb, pad, floor, 20000);
      if (check.verdict != SegmentVerdict::above) continue;
      ++above;
      SCOPED_TRACE(::testing::Message() << std::setprecision(17) << "case " << k << " floor " << floor << " ta "
                                      << ta.transpose() << " tb " << tb.transpose());
      EXPECT_FALSE(dip);
      for (int i = 0; i <= 32; ++i) {
        const ClearanceResult r = c.run(R, ta + (i / 32.0) * (tb - ta), 1e-4);
        ASSERT_GT(r.clearance.hi, floor) << "at " << i << "/32";
      }
    }
  }
  EXPECT_GT(dips, n / 4);  // the faceted sphere makes some short chords shallower in the middle
  EXPECT_GT(above, n / 2);
}

// The leaves of a segment proved above a floor, at its end (check_segment_above's `end`): they cover
// the mover's surface once (a node's faces whole, each face's cells adding up to it), each cell's
// bound holds at every sampled point of the cell placed at the end pose, and a certificate there
// warm-started from them agrees with a cold one and with dense sampling. Chords inside a sphere
// (the depth concave along them), across a torus's tube (the depth along them rises and falls), and
// along a sphere's surface with the mover's cap inside (faces entering F, whose parts of the segment
// are split along it).
TEST(Clearance, SegmentLeavesAtTheEndBoundEveryCellThere) {
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int above = 0, leaves = 0, warm_checked = 0;
  for (int shape = 0; shape < 3; ++shape) {
    Case c(shape == 1 ? make_torus(1.0, 0.4, 24, 12) : make_icosphere(1.0, 3),
           shape == 1 ? make_icosphere(0.12, 1) : make_icosphere(0.05, 1));
    const int n = test_scale::cases(10);
    for (int k = 0; k < n; ++k) {
      const Eigen::Matrix3d R = random_rotation(rng);
      const MoverOrientation o = make_mover_orientation(c.mover, R);
      Vec3 ta, tb;
      if (shape == 0) {
        const Vec3 a = random_direction(rng);
        Vec3 side = random_direction(rng);
        side = (side - side.dot(a) * a).normalized();
        const double angle = 0.02 + 0.1 * u(rng), radius = 0.8 + 0.1 * u(rng);
        ta = radius * a;
        tb = radius * (std::cos(angle) * a + std::sin(angle) * side);
      } else if (shape == 1) {  // about the tube's core circle, tilted out of its plane
        const double phi = 6.283185307179586 * u(rng), dphi = 0.05 + 0.1 * u(rng);
        ta = Vec3(std::cos(phi), std::sin(phi), 0.1 * (u(rng) - 0.5));
        tb = Vec3(std::cos(phi + dphi), std::sin(phi + dphi), 0.1 * (u(rng) - 0.5));
      } else {  // along the sphere's surface, the mover's cap inside F (its faces far outside at ta
                // come near the floor only about tb: their parts of the segment are split along it)
        const Vec3 a = random_direction(rng);
        Vec3 side = random_direction(rng);
        side = (side - side.dot(a) * a).normalized();
        ta = (1.04 + 0.009 * u(rng)) * a;
        const double out = 1.03 + 0.01 * u(rng);
        tb = out * (a + (0.08 + 0.04 * u(rng)) * side).normalized();
      }
      ClearanceFrontier frontier, end;
      ClearanceOptions opt;
      opt.tolerance = 1e-6;
      opt.frontier = &frontier;
      const ClearanceResult ca = certify_clearance(c.fixed, c.mover, c.comps, o, ta, opt);
      const ClearanceResult cb = c.run(R, tb, 1e-6), cm = c.run(R, 0.5 * (ta + tb), 1e-6);
      const double least = std::min({ca.clearance.lo, cb.clearance.lo, cm.clearance.lo});
      const double pad = 2.0 * std::max(o.transform_error(ta), o.transform_error(tb));
      for (double floor : {least - 1e-3, least - 3e-2}) {
        const SegmentCheck check = check_segment_above(c.fixed, o, frontier, ta, tb, pad, floor, 50000, &end);
        SCOPED_TRACE(::testing::Message() << std::setprecision(17) << "shape " << shape << " case " << k << " floor "
                                          << floor << " ta " << ta.transpose() << " tb " << tb.transpose());
        ASSERT_EQ(end.valid, check.verdict == SegmentVerdict::above);
        if (!end.valid) continue;
        ++above;
        ASSERT_EQ(end.t, tb);
        const std::vector<Vec3> P = o.placed(tb);
        std::vector<double> area(c.mover.faces.size(), 0.0);
        // Every sampled point of a mover face's part (barycentric corners b) at tb is at least `lower`.
        const auto sample = [&](std::uint32_t f, const std::array<std::array<double, 2>, 3>& b, double lower) {
          const Vec3 &p0 = P[c.mover.faces[f][0]], e1 = P[c.mover.faces[f][1]] - p0, e2 = P[c.mover.faces[f][2]] - p0;
          constexpr int m = 6;
          for (int i = 0; i <= m; ++i)
            for (int j = 0; i + j <= m; ++j) {
              const double w1 = double(i) / m, w2 = double(j) / m, w0 = 1.0 - w1 - w2;
              const double beta = w0 * b[0][0] + w1 * b[1][0] + w2 * b[2][0];
              const double gamma = w0 * b[0][1] + w1 * b[1][1] + w2 * b[2][1];
              const double s = c.fixed.signed_distance(p0 + beta * e1 + gamma * e2).hi;
              ASSERT_GE(s, lower) << "face " << f << " at (" << beta << ", " << gamma << ")";
            }
        };
        const std::array<std::array<double, 2>, 3> whole = {{{0, 0}, {1, 0}, {0, 1}}};
        for (const ClearanceFrontier::Cell& cell : end.cells) {
          ASSERT_GT(cell.lower, -1e300);
          if (!cell.is_node) {
            const auto& b = cell.bary;
            area[cell.id] += 0.5 * std::abs((b[1][0] - b[0][0]) * (b[2][1] - b[0][1]) -
                                            (b[2][0] - b[0][0]) * (b[1][1] - b[0][1]));
            sample(cell.id, b, cell.lower);
            continue;
          }
          std::vector<std::uint32_t> stack{cell.id};
          while (!stack.empty()) {
            const auto& node = o.boxes.nodes[stack.back()];
            stack.pop_back();
            if (node.count == 0) {
              stack.push_back(node.first);
              stack.push_back(node.first + 1);
              continue;
            }
            for (std::uint32_t i = 0; i < node.count; ++i) {
              const std::uint32_t f = o.boxes.order[node.first + i];
              area[f] += 0.5;
              sample(f, whole, cell.lower);
            }
          }
        }
        for (std::size_t f = 0; f < area.size(); ++f) ASSERT_NEAR(area[f], 0.5, 1e-12) << "face " << f;
        leaves += static_cast<int>(end.cells.size());
        ClearanceOptions warm;
        warm.tolerance = 1e-6;
        warm.frontier = &end;
        const ClearanceResult w = certify_clearance(c.fixed, c.mover, c.comps, o, tb, warm);
        const Interval ref = sampled_enclosure(c.fixed, P, c.mover.faces, 8);
        EXPECT_TRUE(w.tolerance_reached);
        EXPECT_LE(w.clearance.lo, cb.clearance.hi);
        EXPECT_GE(w.clearance.hi, cb.clearance.lo);
        EXPECT_LE(w.clearance.lo, ref.hi);
        EXPECT_GE(w.clearance.hi, ref.lo);
        EXPECT_GT(w.clearance.lo, floor);
        ++warm_checked;
      }
    }
  }
  EXPECT_GT(above, 10);
  EXPECT_GT(leaves, 10 * above);
  EXPECT_EQ(warm_checked, above);
}

// Without polishing, the raw pose against the surface itself is the exact first contact: its
// certified clearance must be 0 up to the rounding of the stored translation and the tolerance
// (an independent check of the sweep against the clearance certificate).
TEST(PlacePose, RawFirstContactWithTheSurfaceTouches) {
  const Scene scene(make_torus(1.0, 0.4, 24, 12), make_icosphere(0.3, 2));
  const ApproachSetup& setup = scene.setup;
  const SweepMesh& level0 = scene.surface;
  PoseOptions opt;
  opt.tolerance = 1e-9;
  opt.polish = false;
  std::mt19937_64 rng(8);
  int touching = 0;
  for (int k = 0; k < 20; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const OrientationFrame frame = make_orientation_frame(setup, R);
    const Vec3 dir = random_direction(rng);
    const PoseOutcome p = place_pose(setup, frame, &level0, dir, 0.0, opt);
    if (!p.contact) continue;  // the line through the torus hole may miss
    ++touching;
    EXPECT_EQ(p.steps, 0);
    EXPECT_LE(p.clearance.lo, 1e-12) << k;
    EXPECT_GE(p.clearance.hi, -1e-12) << k;
    EXPECT_LE(p.clearance.width(), 1e-9 * 1.001) << k;
  }
  EXPECT_GT(touching, 10);
}

// With the fixed surface's sweep attached, the touching pose is certified by the exact sweep
// itself: the same pose as without, a few-ulp interval that overlaps the branch and bound's
// certificate (both enclose c) and lies within the tolerance; the penetrating levels that continue
// from it still reach their targets on the first crossing. A sweep mesh that is not F is refused.
TEST(PlacePose, TouchingPoseFromTheSweepAgreesWithTheCertificate) {
  const Scene scene(make_torus(1.0, 0.4, 24, 12), make_icosphere(0.3, 2));
  ApproachSetup attached = scene.attached();
  PoseOptions opt;
  opt.tolerance = 1e-9;
  opt.start = PoseStart::Surface;
  std::mt19937_64 rng(47);
  int touching = 0, deep_poses = 0;
  for (int k = 0; k < 16; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const OrientationFrame frame = make_orientation_frame(scene.setup, R);
    const Vec3 dir = random_direction(rng);
    const PoseOutcome bb = place_pose(scene.setup, frame, &scene.surface, dir, 0.0, opt);
    ApproachMemo memo;
    const PoseOutcome sw = place_pose(attached, frame, &scene.surface, dir, 0.0, opt, &memo);
    ASSERT_EQ(bb.contact, sw.contact);
    if (!sw.contact) continue;
    ++touching;
    SCOPED_TRACE("case " + std::to_string(k));
    EXPECT_EQ(sw.lambda, bb.lambda);
    EXPECT_TRUE(sw.certified && sw.on_target);
    EXPECT_LE(sw.clearance.lo, bb.clearance.hi);
    EXPECT_GE(sw.clearance.hi, bb.clearance.lo);
    EXPECT_LT(sw.clearance.width(), 1e-13);
    EXPECT_LE(sw.clearance.lo, 0.0);
    EXPECT_GE(sw.clearance.hi, 0.0);
    const PoseOutcome deep = place_pose(attached, frame, &scene.surface, dir, -0.1, opt, &memo);
    // A grazing line may never reach that depth: then neither way finds a pose.
    EXPECT_EQ(deep.contact, place_pose(scene.setup, frame, &scene.surface, dir, -0.1, opt).contact);
    if (!deep.contact) continue;
    ++deep_poses;
    EXPECT_TRUE(deep.on_target);
    expect_no_earlier_crossing(scene.fixed, scene.mover, frame, dir, scene.setup, deep.lambda, -0.1, opt.tolerance, 100);
  }
  EXPECT_GT(touching, 8);
  EXPECT_GT(deep_poses, 5);
  const SweepMesh other = make_sweep_mesh(scene.mover.vertices, scene.mover.faces);
  EXPECT_THROW(attach_surface_sweep(attached, other), std::invalid_argument);
}

// A relative tolerance (advance steps; in the branch and bound and in the pair-distance path) and
// skipping the pair-distance path only change the work:
// every certificate still encloses the clearance (against a tight cold one and dense sampling),
// and the loose width is within max(tolerance, rel (upper - target)).
TEST(Clearance, RelativeToleranceAndNoDistancePathStayRigorous) {
  std::mt19937_64 rng(31);
  Case c(make_torus(1.0, 0.4, 24, 12), make_icosphere(0.5, 1));
  int loose_cheaper = 0, checked = 0;
  for (int k = 0; k < 6; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const Vec3 dir = random_direction(rng);
    const MoverOrientation o = make_mover_orientation(c.mover, R);
    for (int step = 0; step < 6; ++step) {
      // From separated (step 0: 0.3 outside the tube's surface) to deep inside.
      const Vec3 t = Vec3(1.0, 0.0, 0.0) + (1.2 - 0.2 * step) * dir;
      const ClearanceResult tight = c.run(R, t, 1e-7);
      const Interval ref = sampled_enclosure(c.fixed, o.placed(t), c.mover.faces, 8);
      for (bool distance_path : {true, false}) {
        ClearanceOptions opt;
        opt.tolerance = 1e-7;
        opt.relative_tolerance = 0.125;
        opt.target = tight.clearance.lo - 0.05;
        opt.try_distance_path = distance_path;
        const ClearanceResult r = certify_clearance(c.fixed, c.mover, c.comps, o, t, opt);
        SCOPED_TRACE("case " + std::to_string(k) + " step " + std::to_string(step) + " distance path " +
                     std::to_string(distance_path));
        ++checked;
        EXPECT_TRUE(r.tolerance_reached);
        EXPECT_LE(r.clearance.lo, tight.clearance.hi);
        EXPECT_GE(r.clearance.hi, tight.clearance.lo);
        EXPECT_LE(r.clearance.lo, ref.hi);
        EXPECT_GE(r.clearance.hi, ref.lo);
        EXPECT_LE(r.clearance.width(), std::max(1e-7, 0.125 * (r.clearance.hi - opt.target)) * 1.001 + 1e-12);
        loose_cheaper += r.separated ? r.pair_tests < tight.pair_tests : r.cells < tight.cells;
        if (!distance_path) {
          EXPECT_FALSE(r.separated);
        }
      }
    }
  }
  EXPECT_EQ(checked, 72);
  EXPECT_GT(loose_cheaper, 10);
}

// A thin tube's 4-long slivers about a finely faceted sphere, at a penetrating target with a
// step's relative tolerance (a deep-zone jump's landing): the pair-distance path on the sweep
// trees, whose oriented boxes fit the slivers, encloses the same clearance as on each orientation's
// box trees and as a tight certificate, from apart to penetrating poses, and visits fewer pairs
// where the tube lies apart (place_pose runs it there on the sweep trees; doc/performance.md,
// "Landings apart on the sweep trees").
TEST(Clearance, SliverPairsApartOnTheSweepTreesAgreeWithTheBoxTrees) {
  std::mt19937_64 rng(59);
  std::uniform_real_distribution<double> w(0.0, 1.0);
  Case c(make_icosphere(0.5, 3), make_tube(0.09, 0.1, 4.0, 48));
  const SweepMesh surface = make_sweep_mesh(c.fixed.mesh().vertices, c.fixed.mesh().faces);
  const SweepMesh own = make_sweep_mesh(c.mover.vertices, c.mover.faces);
  std::uint64_t box_pairs = 0, sweep_pairs = 0;
  int apart = 0, inside = 0;
  for (int k = 0; k < 16; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const MoverOrientation o = make_mover_orientation(c.mover, R);
    // The tube's axis passes the sphere's centre at `gap` beyond its radius (the wall's outer
    // face at gap - 0.1 from it), its middle beside the centre.
    const Vec3 axis = R.col(2);
    Vec3 n = axis.cross(random_direction(rng)).normalized();
    const double gap = k % 4 == 3 ? 0.05 * w(rng) : 0.1 + 0.3 * w(rng);
    const Vec3 t = (0.5 + gap) * n - 2.0 * axis + (0.4 * w(rng) - 0.2) * axis;
    const Vec3 t0 = t + Vec3(0.2, -0.1, 0.3);
    const SweepMesh mover_at_t0 = placed_sweep_mesh(own, R, t0, o.placed(t0), o.transform_error(t0));
    const SweepTrees trees{&surface, &mover_at_t0, t0};
    ClearanceOptions tight;
    tight.tolerance = 1e-7;
    const ClearanceResult ref = certify_clearance(c.fixed, c.mover, c.comps, o, t, tight);
    ClearanceOptions opt;
    opt.tolerance = 1e-7;
    opt.relative_tolerance = 0.25;
    opt.target = -0.1;
    const ClearanceResult on_boxes = certify_clearance(c.fixed, c.mover, c.comps, o, t, opt);
    opt.sweep_trees = &trees;
    const ClearanceResult on_sweep = certify_clearance(c.fixed, c.mover, c.comps, o, t, opt);
    SCOPED_TRACE("case " + std::to_string(k));
    for (const ClearanceResult* r : {&on_boxes, &on_sweep}) {
      EXPECT_TRUE(r->tolerance_reached);
      EXPECT_LE(r->clearance.lo, ref.clearance.hi) << std::setprecision(17) << r->clearance.lo << " " << ref.clearance.hi;
      EXPECT_GE(r->clearance.hi, ref.clearance.lo) << std::setprecision(17) << r->clearance.hi << " " << ref.clearance.lo;
      EXPECT_LE(r->clearance.width(), std::max(1e-7, 0.25 * (r->clearance.hi - opt.target)) * 1.001 + 1e-12);
    }
    EXPECT_EQ(on_boxes.separated, on_sweep.separated);
    if (ref.clearance.lo > 0.0) {
      EXPECT_TRUE(on_sweep.separated);
      ++apart;
      box_pairs += on_boxes.pair_tests;
      sweep_pairs += on_sweep.pair_tests;
    } else {
      inside += ref.clearance.hi < 0.0;
    }
  }
  EXPECT_GT(apart, 8);
  EXPECT_GT(inside, 1);
  EXPECT_LT(2 * sweep_pairs, box_pairs) << sweep_pairs << " against " << box_pairs;
}

// The levels of one approach placed in descending target order with a shared memo: the raw contact
// is computed once and reused as is (its certificate the first surface level's), lower targets
// continue from the last pose on target, and
// every pose is still on target and on the first crossing (no pose between it and the far start
// certified below the target). Ascending order is refused.
TEST(PlacePose, LevelsOfOneApproachShareTheContactAndContinueEachOther) {
  const Scene scene(make_torus(1.0, 0.35, 24, 12), make_icosphere(0.2, 1));
  const ApproachSetup& setup = scene.setup;
  const SweepMesh& surface = scene.surface;
  PoseOptions opt;
  opt.tolerance = 1e-6;
  std::mt19937_64 rng(41);
  int chained = 0, placed = 0;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const OrientationFrame frame = make_orientation_frame(setup, R);
    Vec3 dir = random_direction(rng);
    if (k % 2 == 0) dir = Vec3(dir.x(), dir.y(), 0.1 * dir.z()).normalized();
    ApproachMemo memo;
    std::optional<Interval> first_raw;  // the raw certificate of the first level started at the surface
    for (double target : {0.08, 0.03, 0.0, -0.05, -0.12}) {
      opt.start = target > 0.0 ? PoseStart::Far : PoseStart::Surface;
      const bool had_pose = memo.last.has_value();
      const PoseOutcome p = place_pose(setup, frame, &surface, dir, target, opt, &memo);
      const PoseOutcome alone = place_pose(setup, frame, &surface, dir, target, opt);
      SCOPED_TRACE("case " + std::to_string(k) + " target " + std::to_string(target));
      ASSERT_EQ(p.contact, alone.contact);
      if (!p.contact) continue;
      ++placed;
      chained += had_pose && p.continued;
      EXPECT_FALSE(alone.continued);
      EXPECT_TRUE(p.on_target) << p.clearance.lo << " " << p.clearance.hi;
      EXPECT_EQ(p.lambda_raw, alone.lambda_raw);
      if (opt.start == PoseStart::Far) {
        EXPECT_EQ(p.raw_clearance.lo, alone.raw_clearance.lo);
        EXPECT_EQ(p.raw_clearance.hi, alone.raw_clearance.hi);
      } else if (!first_raw) {
        first_raw = p.raw_clearance;
      } else {
        // The first surface level's certificate as it was; alone, the same contact's, computed
        // for this target (its far cells' margins depend on it), so valid and overlapping.
        EXPECT_EQ(p.raw_clearance.lo, first_raw->lo);
        EXPECT_EQ(p.raw_clearance.hi, first_raw->hi);
        EXPECT_LE(alone.raw_clearance.lo, p.raw_clearance.hi);
        EXPECT_GE(alone.raw_clearance.hi, p.raw_clearance.lo);
      }
      EXPECT_NEAR(p.lambda, alone.lambda, 1e-4);  // both on the first crossing, within tolerances
      expect_no_earlier_crossing(scene.fixed, scene.mover, frame, dir, setup, p.lambda, target, opt.tolerance, 200);
    }
    opt.start = PoseStart::Far;
    if (memo.last) {
      EXPECT_THROW(place_pose(setup, frame, &surface, dir, 0.1, opt, &memo), std::invalid_argument);
    }
  }
  EXPECT_GT(placed, 25);
  EXPECT_GT(chained, 5);
}

// The request's tolerance: 1e-6 of spool's diagonal.
constexpr double kSpoolTolerance = 1.506100827590238e-06;

// An approach of `cdbench poses`' 20 x 2 request with spool (CGAL's data) fixed and `mover` moving:
// spool's maximum penetration, the levels +1/4, 0, -1/4 and 1 times `target` in descending order,
// each advance continuing from the previous level's pose; the deepest level's outcome. `ab` sets
// the option compared. Empty without the data.
std::optional<PoseOutcome> place_against_spool(const TriangleMesh& mover, const Eigen::Matrix3d& R, int direction,
                                               double target, const std::function<void(PoseOptions&)>& ab) {
  const std::string path = std::string(CDBENCH_DATA_DIR) + "/cgal/meshes/spool.off";
  if (!std::ifstream(path)) return std::nullopt;
  // As `cdbench poses` reads it (validate_mesh may reorient and weld).
  const TriangleMesh spool = validate_mesh(read_polygon_soup(path)).mesh;
  const SignedDistance fixed(spool);
  ApproachSetup setup = make_approach_setup(fixed, mover);
  const SweepMesh surface = make_sweep_mesh(spool.vertices, spool.faces);
  attach_surface_sweep(setup, surface);
  const OrientationFrame frame = make_orientation_frame(setup, R);
  constexpr double max_penetration = 0.22954648657740523;
  PoseOptions base;
  base.tolerance = kSpoolTolerance;
  const Eigen::Vector3d dir = sphere_fibonacci(20)[static_cast<std::size_t>(direction)];
  ApproachMemo memo;
  PoseOutcome p;
  for (const double t : {-0.25 * target, 0.0, 0.25 * target, target}) {
    const LevelDeepZone zone = make_level_deep_zone(fixed, t, max_penetration, true, 40);  // outlives opt
    PoseOptions opt = zone.options(base);
    opt.start = t > 0.0 ? PoseStart::Far : PoseStart::Surface;
    ab(opt);
    p = place_pose(setup, frame, &surface, dir, t, opt, &memo);
  }
  EXPECT_TRUE(p.certified);
  EXPECT_TRUE(p.on_target);
  return p;
}

// The request's two orientations.
Eigen::Matrix3d spool_request_orientation(int k) {
  Eigen::Matrix3d R;
  if (k == 0)
    R << -0.36663014408024175, 0.37126857953801656, 0.85307794444559659, -0.85321984596295519, -0.49975781510094963,
        -0.14919122192835482, 0.37094235658205943, -0.7825610315453666, 0.5;
  else
    R << -0.30194638756089098, 0.5861832480735002, 0.75180953619712054, 0.44967321794848331, 0.78295055768342436,
        -0.42986325881967458, -0.84060833691962877, 0.20827295528036283, -0.5;
  return R;
}

// Segments tried again after every failure (once the gap has halved since), not once per pose: a
// thin tube (1,024 slivers 4 long, wall 2 % of its radius) moving against spool at -18 %
// (orientation 1, direction 5), where segment searches still run out of their budget. Until
// session 89 the test placed pinion against spool, whose segment searches have not run out since
// they split needle cells across their length (both rules then give the same advance there); until
// session 91 orientation 1, direction 11, where since segments hand their leaves to the certificate
// at their end both rules advance alike; until session 97 orientation 0, direction 8, where since
// a rejected two-sided try may be kept after the plain step both rules advance alike (of the 40
// approaches, 5 differ, each in favour of retries).
TEST(PlacePose, SegmentsTriedAgainAfterEveryFailureCrossATubeSlide) {
  const TriangleMesh tube = validate_mesh(make_tube(0.98, 1.0, 4.0, 128)).mesh;
  const Eigen::Matrix3d R = spool_request_orientation(1);
  constexpr double target = -0.041318367583932938;
  const auto every = place_against_spool(tube, R, 5, target, [](PoseOptions& o) { o.segment_retries = -1; });
  if (!every) GTEST_SKIP() << "no CGAL data (scripts/fetch-cgal-data.sh)";
  const auto once = place_against_spool(tube, R, 5, target, [](PoseOptions& o) { o.segment_retries = 1; });
  // The same first crossing: c falls slowly there, so poses within the tolerance of the target
  // may lie tens of tolerances apart along the line.
  EXPECT_NEAR(every->lambda, once->lambda, 40 * kSpoolTolerance);
  // 27 steps (7 segments tried) against 38 (2).
  EXPECT_GT(every->segment_tries, once->segment_tries + 1);
  EXPECT_LT(every->steps, once->steps) << every->steps << " " << once->steps;
}

// Pinion moving against spool at -20 %, orientation 1, direction 7: after its landing c slides
// along a wall a little above the target. The loose certificates' midpoints scatter by up to 3/8
// of the gap, so no span of poses resolves the slope and the two-step secants read it as anything
// from 0 to 0.6: segments are seldom due and two-sided steps cross most of it. A slope fitted over
// eight poses gates and aims them (a fit of about 0 aims at 32 gaps): 18 steps instead of 43,
// 1,044 cells and cubes instead of 6,894. Until session 97 orientation 0, direction 4 (a slide at
// about 1/100 of the advance: 20 steps instead of 62), where since a two-sided try's search goes
// on to its floor the secants' advance takes 22 steps against the fit's 19.
TEST(PlacePose, SegmentsAimedByAFittedSlopeCrossAWallSlide) {
  const std::string dir = std::string(CDBENCH_DATA_DIR) + "/cgal/meshes/";
  if (!std::ifstream(dir + "pinion.off")) GTEST_SKIP() << "no CGAL data (scripts/fetch-cgal-data.sh)";
  const TriangleMesh pinion = validate_mesh(read_polygon_soup(dir + "pinion.off")).mesh;
  const Eigen::Matrix3d R = spool_request_orientation(1);
  constexpr double target = -0.045909297315481046;
  const auto fit = place_against_spool(pinion, R, 7, target, [](PoseOptions& o) { o.fitted_segments = true; });
  if (!fit) GTEST_SKIP() << "no CGAL data (scripts/fetch-cgal-data.sh)";
  const auto secants = place_against_spool(pinion, R, 7, target, [](PoseOptions& o) { o.fitted_segments = false; });
  EXPECT_NEAR(fit->lambda, secants->lambda, 40 * kSpoolTolerance);
  EXPECT_LT(2 * fit->steps, secants->steps) << fit->steps << " " << secants->steps;
  EXPECT_LT(fit->clearance_cells + fit->zone_cubes, secants->clearance_cells + secants->zone_cubes);
}

// The thin tube against spool at -18 % (orientation 0, direction 0): c falls steeply onto a floor a
// few per cent of |target| above the target (the tube's part in a wall at its saturated depth) and
// rests there until the tube meets the deep zone. Asked for the zone's contact once c has been
// flat over eight poses after such a fall, instead of after 20 flat steps: 22 steps instead of 50,
// 5,416 certificate cells and cubes instead of 13,856, the same first crossing. (Over the 40
// approaches of both orientations: 371,000 against 424,000, none worse.)
TEST(PlacePose, FloorAfterAFallAsksTheDeepZoneSooner) {
  const TriangleMesh tube = validate_mesh(make_tube(0.98, 1.0, 4.0, 128)).mesh;
  const Eigen::Matrix3d R = spool_request_orientation(0);
  constexpr double target = -0.041318367583932938;
  const auto sooner = place_against_spool(tube, R, 0, target, [](PoseOptions& o) { o.floor_queries = true; });
  if (!sooner) GTEST_SKIP() << "no CGAL data (scripts/fetch-cgal-data.sh)";
  const auto later = place_against_spool(tube, R, 0, target, [](PoseOptions& o) { o.floor_queries = false; });
  EXPECT_NEAR(sooner->lambda, later->lambda, 40 * kSpoolTolerance);
  EXPECT_GE(sooner->cover_jumps, 1);
  EXPECT_LT(3 * sooner->steps, 2 * later->steps) << sooner->steps << " " << later->steps;
  EXPECT_LT(2 * (sooner->clearance_cells + sooner->zone_cubes), later->clearance_cells + later->zone_cubes)
      << sooner->clearance_cells << " + " << sooner->zone_cubes << " against " << later->clearance_cells << " + "
      << later->zone_cubes;
}

}  // namespace
}  // namespace cdbench
