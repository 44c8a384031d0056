#include "placement/place_pose.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace cdbench {
namespace {

Vec3 bbox_centre(const std::vector<Vec3>& v) {
  Aabb b;
  for (const Vec3& p : v) b.extend(p);
  return b.center();
}

double max_distance(const std::vector<Vec3>& v, const Vec3& c) {
  double r = 0.0;
  for (const Vec3& p : v) r = std::max(r, (p - c).norm());
  return r * (1.0 + 1e-12);
}

}  // namespace

Vec3 pose_translation(const OrientationFrame& f, const Vec3& dir, double lambda) {
  return Vec3(f.t0[0] + lambda * dir[0], f.t0[1] + lambda * dir[1], f.t0[2] + lambda * dir[2]);
}

ApproachSetup make_approach_setup(const SignedDistance& fixed, const TriangleMesh& mover) {
  ApproachSetup s;
  s.fixed = &fixed;
  s.mover = &mover;
  s.components = component_representatives(mover);
  s.fixed_ref = bbox_centre(fixed.mesh().vertices);
  s.mover_ref = bbox_centre(mover.vertices);
  s.fixed_radius = max_distance(fixed.mesh().vertices, s.fixed_ref);
  s.mover_radius = max_distance(mover.vertices, s.mover_ref);
  return s;
}

OrientationFrame make_orientation_frame(const ApproachSetup& setup, const Eigen::Matrix3d& R) {
  OrientationFrame f;
  f.orientation = make_mover_orientation(*setup.mover, R);
  const Vec3 rc = R * setup.mover_ref;
  f.t0 = setup.fixed_ref - rc;
  f.swept = make_sweep_mesh(f.orientation.placed(f.t0), setup.mover->faces);
  return f;
}

const char* to_string(PoseStart s) {
  switch (s) {
    case PoseStart::Offset: return "offset";
    case PoseStart::Surface: return "surface";
    case PoseStart::Far: return "far";
  }
  return "?";
}

PoseStart planned_start(double target, bool polish, StartPolicy policy) {
  if (target == 0.0) return PoseStart::Surface;
  if (!polish || policy == StartPolicy::Offsets) return PoseStart::Offset;
  return target < 0.0 ? PoseStart::Surface : PoseStart::Far;
}

bool fallback_start(double target, bool polish, PoseStart* start) {
  if (!polish) return false;
  *start = planned_start(target, polish, StartPolicy::NoOffsets);
  return true;
}

PoseOutcome place_pose(const ApproachSetup& setup, const OrientationFrame& frame, const SweepMesh* swept,
                       const Vec3& dir, double target, const PoseOptions& options) {
  PoseOutcome out;
  // Where the bounding spheres are apart by more than |target| and separating further: every
  // farther pose has c > target, so the advance may start there.
  const double lambda_far =
      setup.fixed_radius + setup.mover_radius + std::abs(target) + 1e-3 * (setup.fixed_radius + setup.mover_radius);
  const bool far_start = options.start == PoseStart::Far;
  if (far_start && !options.polish) throw std::invalid_argument("place_pose: a far start needs polishing");
  if (!far_start) {
    if (swept == nullptr) throw std::invalid_argument("place_pose: no surface to sweep against");
    const Vec3 v = -dir;
    const MeshContact mc = first_contact_along_line(*swept, frame.swept, v);
    out.sphere_tests = mc.sphere_tests;
    out.triangle_sweeps = mc.triangle_sweeps;
    if (!mc.hit) {
      out.reason = "no-contact";
      return out;
    }
    // The swept mover sits at t0 + t_contact v = t0 - t_contact d.
    const mpq_class lambda_exact = -exact_contact_time(*swept, frame.swept, v, mc);
    out.lambda_raw = out.lambda = lambda_exact.get_d();
  } else {
    out.lambda_raw = out.lambda = lambda_far;
  }
  out.contact = true;
  ClearanceOptions copt;
  copt.tolerance = 0.5 * options.tolerance;  // leaves room for the target band below
  copt.max_cells = options.max_cells;
  ClearanceFrontier frontier;  // the previous certificate's search, a warm start for the next pose
  copt.frontier = &frontier;
  const auto certify = [&](double lambda, double tolerance) {
    copt.tolerance = tolerance;
    const Vec3 t = pose_translation(frame, dir, lambda);
    const ClearanceResult r = certify_clearance(*setup.fixed, *setup.mover, setup.components, frame.orientation, t, copt);
    out.clearance_cells += r.cells;
    if (r.argmin_face >= 0) {  // the next, nearby pose starts from this minimum
      copt.hint_face = r.argmin_face;
      copt.hint_beta = r.argmin_beta;
      copt.hint_gamma = r.argmin_gamma;
    }
    return r;
  };
  const double final_tol = copt.tolerance;
  // While far from the target an advance step needs only a loose lower bound (a width of 1/8 of
  // the remaining gap costs at most 1/8 of the step); the final poses get the full tolerance.
  const auto step_tolerance = [&](const Interval& previous) {
    return std::max(final_tol, 0.125 * (previous.lo - target));
  };
  ClearanceResult c = certify(out.lambda, final_tol);
  out.raw_clearance = c.clearance;
  const auto within = [&](const Interval& x) {
    return x.lo >= target - options.tolerance && x.hi <= target + options.tolerance;
  };
  if (options.polish) {
    if (!within(c.clearance) && !(c.clearance.lo > target)) {
      // Neither on target nor provably before the crossing: start far away.
      out.lambda = lambda_far;
      c = certify(out.lambda, final_tol);
    }
    double current_tol = final_tol;
    // The previous pose of the advance, for the slope of c (a heuristic: it only picks steps).
    double prev_lambda = 0.0, prev_mid = 0.0;
    bool have_prev = false;
    // The absolute margin for the rounding of t at poses with |lambda| up to `magnitude`.
    const auto rounding_slack = [&](double magnitude) {
      return 8.0 * 0x1p-52 * (frame.t0.cwiseAbs().maxCoeff() + magnitude);
    };
    while (!within(c.clearance) && out.steps < options.max_steps) {
      // The clearance is 1-Lipschitz in lambda (|d| = 1 up to rounding, covered by the relative
      // margin; the rounding of t by the absolute one): stepping by c_lo - target cannot pass the
      // first crossing.
      const double slack = rounding_slack(std::abs(out.lambda));
      const double gap = c.clearance.lo - target;
      const double step = gap * (1.0 - 1e-9) - slack;
      if (!(step > 0.0)) {
        if (current_tol > final_tol) {  // a loose certificate: tighten it before giving up
          c = certify(out.lambda, current_tol = final_tol);
          continue;
        }
        break;
      }
      const double mid = 0.5 * (c.clearance.lo + c.clearance.hi);
      const double slope = have_prev ? std::max(0.0, (prev_mid - mid) / (prev_lambda - out.lambda)) : 1.0;
      const double tol_next = step_tolerance(c.clearance);
      prev_lambda = out.lambda;
      prev_mid = mid;
      have_prev = true;
      bool advanced = false;
      if (options.two_sided_steps && slope < 0.5) {
        // Where c is flat, a step of up to twice the gap, proved from both ends: on [l - h, l],
        // c >= max(c(l) - (l - x), c(l - h) - (x - l + h)) > target when the two gaps add up to
        // more than h (same margins as one step, for both ends).
        // The aim: h where the two gaps, predicted with the slope, add up to h / 0.9.
        const double h = 0.9 * 2.0 * gap / (1.0 + slope);
        if (h > 1.2 * step && out.lambda - h >= -lambda_far) {
          const double slack2 = rounding_slack(std::abs(out.lambda) + h);
          const ClearanceResult c2 = certify(out.lambda - h, tol_next);
          ++out.two_sided_tries;
          if ((gap + (c2.clearance.lo - target)) * (1.0 - 1e-9) - 2.0 * slack2 >= h) {
            out.lambda -= h;
            c = c2;
            advanced = true;
          }
        }
      }
      current_tol = tol_next;
      if (!advanced) {
        out.lambda -= step;
        if (out.lambda < -lambda_far) {
          // Passed the fixed object without reaching the target: c > target on the whole line.
          out.contact = false;
          out.reason = "no-contact";
          return out;
        }
        c = certify(out.lambda, current_tol);
      }
      ++out.steps;
      if (c.clearance.hi <= target + options.tolerance && current_tol > final_tol)
        c = certify(out.lambda, current_tol = final_tol);  // near the end: the reported certificate
    }
  }
  out.t = pose_translation(frame, dir, out.lambda);
  out.clearance = c.clearance;
  out.certified = c.tolerance_reached;
  out.on_target = within(c.clearance);
  if (!out.certified) out.reason = "tolerance-not-reached";
  else if (options.polish && !out.on_target) out.reason = "polish-stalled";
  return out;
}

}  // namespace cdbench
