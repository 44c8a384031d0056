#pragma once
// Parsing of --levels lists: signed distances, absolute ("-0.5,0.2") or as a percentage of the
// certified maximum penetration ("-80%"), and ranges "FROM:TO:STEP" in either unit ("-25%:25%:5%").
#include <string>
#include <vector>

namespace cdbench {

struct LevelSpec {
  double value = 0.0;     // as written: an absolute distance, or a percentage when `percent`
  bool percent = false;
  std::string text;       // the item as it appears in the list (for messages and manifests)
};

// Throws InputError naming the offending item. Ranges include TO when it is hit within 1e-9 of a step.
std::vector<LevelSpec> parse_level_list(const std::string& list);

// InputError naming the first level whose text is listed twice (a pose set's levels must differ).
void check_distinct_levels(const std::vector<LevelSpec>& levels);

// Absolute signed distance of a level given the maximum penetration.
double level_distance(const LevelSpec& level, double max_penetration);

// InputError naming the first two levels at the same signed distance (distances[i] for levels[i]):
// "0" and "0%", or percentages of a maximum penetration whose certified lower end is 0. Their poses
// would be one, and a pose set's levels are placed in strictly descending order.
void check_distinct_distances(const std::vector<LevelSpec>& levels, const std::vector<double>& distances);

// How tightly the maximum penetration M must be certified (width relative to the diagonal) for a
// pose set whose percentage levels p are placed to `tolerance` (relative to the diagonal): a level
// at p·M is then known to |p|·width <= tolerance of p times the true M. Never below `floor` (the
// default width), nor above kReportedMaxPenetrationWidth unless `floor` is: a coarse --tolerance
// (0.1 at -20 %: a width of half the diagonal) would otherwise leave M's lower end at 0, and every
// percentage level at d = 0. When no level is a percentage no target depends on M, which is then only
// reported (the solid's scale, and absolute levels as fractions of it): kReportedMaxPenetrationWidth,
// or `floor` if wider. M is only the levels' scale: a thin tube's M has a 2-D plateau of deepest
// points that costs ~1/width^0.7 cells to certify (pipe: 1e-6 not reached in 67 s; 1e-4 in 1.3 s).
constexpr double kReportedMaxPenetrationWidth = 1e-4;
double max_penetration_tolerance_for(const std::vector<LevelSpec>& levels, double tolerance, double floor);

// A note for a maximum penetration certified only to [lo, hi], wider than asked (its search stopped
// at its memory bound: sheet-like parts), when some level is a nonzero percentage of it: such
// targets are p times lo(M), and M may be up to hi/lo times that. Empty when the tolerance was
// reached or no level depends on M.
std::string max_penetration_scale_note(const std::vector<LevelSpec>& levels, double lo, double hi,
                                       bool tolerance_reached, double asked_width);

// A note for percentage levels that the tolerance does not resolve: the nearest such level to the
// surface lies within twice the tolerance `tol` of it (a solid thinner than the tolerance, e.g. a
// sheet 1e-6 of its diagonal thick), so its poses are hardly told from the surface's; names the
// level and the relative --tolerance (`diagonal`) that would resolve it to a tenth. Empty otherwise.
std::string percentage_resolution_note(const std::vector<LevelSpec>& levels, const std::vector<double>& distances,
                                       double tol, double diagonal);

// How far from the surface a pose set's level may lie: |d| <= kMaxLevelDiagonals x diagonal.
// Farther away every triangle pair is at nearly the same distance and a certificate costs ever more
// (knot1, two poses: d = 1e5 (68,000 diagonals) 0.1 s, 1e6 4 s, 1e7 34 s, 1e12 not done in 2
// minutes), and near 2^44 tolerances doubles no longer hold the target to the tolerance. Throws an
// InputError naming the level.
constexpr double kMaxLevelDiagonals = 1e4;
void check_level_reach(const LevelSpec& level, double d, double diagonal);

// Whether an offset level can be meshed: an outward level set lies in the ball of radius R + d
// about the box's centre (R: half the diagonal), and far out it is nearly that ball's sphere, which
// the mesher covers with facets of Delaunay radius at most r (--mesher-radius x diagonal): about
// 4 pi (R + d)^2 / r^2 faces (knot1: 176,000 estimated, 170,172 meshed at d = 1; 818,000 and
// 958,956 at d = 3, 183 s and 1.3 GB). Levels estimated above kMaxOffsetFaces are refused with an
// InputError that names the level, the estimate and the farthest level that fits.
constexpr double kMaxOffsetFaces = 5e6;
double estimated_offset_faces(double d, double diagonal, double radius_relative);
void check_offset_level_size(const std::string& name, double d, double diagonal, double radius_relative);

}  // namespace cdbench
