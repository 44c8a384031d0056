#include "offset/offset_level.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "offset/certify_band.h"
#include "offset/certify_completeness.h"
#include "offset/fast_signed_distance.h"
#include "offset/mesh_level_set.h"
#include "offset/refine_offset.h"
#include "util/timer.h"

namespace cdbench {
namespace {

std::string num(double x) {
  std::ostringstream os;
  os.precision(6);
  os << x;
  return os.str();
}

// The first line of a message (CGAL's failures span several), for one-line attempt messages.
std::string first_line(const std::string& s) {
  const std::size_t end = s.find_first_of("\r\n");
  return end == std::string::npos ? s : s.substr(0, end);
}

// Runs `work` (a sequential mesher) on this thread while `prefetch` is extended on threads that
// would otherwise idle; it stops when the work ends or throws. The prefetch runs in an arena of
// its own at low priority: threads that the other levels' work needs go there first, and a thread
// waiting for that work never picks the prefetch up (it would stay in it until this mesher ends).
// With one thread the prefetch does nothing.
template <class Work>
void while_prefetching(CompletenessPrefetch& prefetch, Work&& work) {
  if (prefetch.finished()) {
    work();
    return;
  }
  tbb::task_arena arena(tbb::this_task_arena::max_concurrency(), 1, tbb::task_arena::priority::low);
  std::atomic<bool> stop{false};
  tbb::task_group group;
  // A prefetch that fails (out of memory) leaves facts that are known or not, never half known:
  // the searches compute the rest. It must not throw from the wait below, in a destructor.
  arena.execute([&] {
    group.run([&] {
      try {
        prefetch.run(stop);
      } catch (...) {
      }
    });
  });
  struct Join {
    tbb::task_arena& arena;
    std::atomic<bool>& stop;
    tbb::task_group& group;
    ~Join() {
      stop = true;
      arena.execute([&] { group.wait(); });
    }
  } join{arena, stop, group};
  work();
}

// Local repair of a candidate whose band misses the tolerance on few faces (refine_offset.h):
// rounds of splitting the faces above the tolerance, each new vertex moved onto the level set by
// the fast distance; the new faces' bands are certified, the kept faces keep theirs (the band is a
// per-face certificate). Gives up, leaving `v` and `band` as they were, when too many faces are
// wide (a finer re-mesh is then the better candidate), the rounds stop making progress or the
// refined mesh is not valid (with `creases`: not valid after its folds were mended).
bool repair_band_with(const SignedDistance& sdf, const FastSignedDistance& fast, double d, double tol,
                      const BandOptions& bo, ValidatedMesh& v, BandResult& band, OffsetLevel& level,
                      const std::function<void(const std::string&)>& log, bool creases) {
  // Up to 8 rounds while the number of wide faces or the widest face's band (by 5 %) keeps falling:
  // a fourth round that leaves a handful of faces a hair above the tolerance (armadillo -10 %: 3
  // faces, band 1.005 x tol) is worth a fifth rather than a whole re-mesh, and a round that splits a
  // face into four faces still wide but narrower makes progress too.
  constexpr int kRounds = 8;
  std::size_t previous_count = std::numeric_limits<std::size_t>::max();
  bool mended_last = false;  // the last round mended folds: its faces at midpoints are still wide
  double previous_epsilon = std::numeric_limits<double>::infinity();
  // A new vertex moves from its edge's midpoint to the level set, first along the distance's
  // gradient (to the nearest point of the level set), and if the refined mesh is not valid then
  // along the edge's normal. Neither rule keeps every mesh valid: where the level set is a sheet
  // thinner than the band (thin parts' inward levels) its nearest point may lie on the sheet's other
  // side, and the new faces fold through the old ones (boeing -20 %: 4 pairs of faces intersected,
  // and a whole re-mesh followed); the normal's rule folds faces elsewhere (mpi +5 %: 15 pairs).
  // A vertex that no rule places on the level stays at the midpoint, and every face around it
  // stays above the tolerance however often it is split (pinion -20 % from a candidate meshed with
  // twice the distance bound: 22 faces stuck at 1.10 tolerances beside a crease, then a re-mesh);
  // point_on_level_close also searches around the midpoint where the gradient points past a crease.
  const auto near_or_around = [&](const Vec3& m) {
    Vec3 on;
    return point_on_level_close(fast, d, m, on) ? on : m;
  };
  // Where the gradients at the edge's ends differ by more than 45 degrees a crease of the level set
  // likely lies between them (an inward level of a convex edge or corner of F): a vertex on one
  // side of it leaves the faces across it wide however often they are split (elephant -13 %: the
  // band 1.09 tolerances after 8 rounds, then a re-mesh), so the vertex on the crease above the
  // edge is taken instead where it gives the flatter half-edges.
  const auto by_gradient = [&](const Vec3& a, const Vec3& b, const Vec3&) {
    const Vec3 x = near_or_around(0.5 * (a + b));
    Vec3 c;
    if (!creases || !point_on_crease_across(fast, d, a, b, c)) return x;
    // The flatter pair of half-edges: the larger deviation of their midpoints from the level.
    const auto off = [&](const Vec3& y) {
      return std::max(std::abs(fast(0.5 * (a + y)) - d), std::abs(fast(0.5 * (y + b)) - d));
    };
    return off(c) < off(x) ? c : x;
  };
  const auto by_normal = [&](const Vec3& a, const Vec3& b, const Vec3& normal) {
    const Vec3 m = 0.5 * (a + b);
    Vec3 on;
    const double len = normal.norm();
    if (len > 1e-3) {
      const Vec3 u = (fast(m) - d < 0 ? 1.0 : -1.0) / len * normal;
      if (point_on_level_along(fast, d, m, u, (b - a).norm(), on)) return on;
    }
    return near_or_around(m);
  };
  const PlaceEdgeVertex rules[] = {by_gradient, by_normal};
  // Validation must accept the refined mesh as it is (no welding, reorientation or reordering), so
  // that the kept faces' bands still belong to the same faces.
  const auto as_is = [](const ValidatedMesh& rv, const RefinedMesh& r) {
    return rv.mesh.faces == r.mesh.faces && rv.mesh.vertices == r.mesh.vertices;
  };
  // Folds mended where they are (the second way only): a new vertex of a face that intersects
  // another is placed again, along its edge's normal if the rule did not, then at its edge's
  // midpoint. At the midpoint it lies on the split faces, which did not intersect, so the folds go
  // once every vertex involved is there; its faces keep (at most) the split face's band and are
  // split again next round. Each pass validates the whole mesh again. Returns how many vertices
  // moved.
  const auto unfold = [&](std::size_t rule, RefinedMesh& r, ValidatedMesh& rv) -> std::size_t {
    std::vector<char> stage(r.new_vertex_edge.size(), rule == 0 ? 0 : 1);  // 1: along the normal; 2: midpoint
    std::size_t moved = 0;
    for (int pass = 0; pass < 8; ++pass) {
      if (rv.report.errors.size() != 1 || rv.report.errors[0].kind != "self-intersection" || !as_is(rv, r)) return moved;
      std::vector<std::size_t> involved;
      for (const auto& [f, g] : rv.report.intersecting_faces)
        for (const std::size_t face : {f, g})
          for (const std::uint32_t vertex : r.mesh.faces[face])
            if (vertex >= r.first_new_vertex && stage[vertex - r.first_new_vertex] < 2)
              involved.push_back(vertex - r.first_new_vertex);
      std::sort(involved.begin(), involved.end());
      involved.erase(std::unique(involved.begin(), involved.end()), involved.end());
      if (involved.empty()) return moved;
      tbb::parallel_for(std::size_t{0}, involved.size(), [&](std::size_t i) {
        const std::size_t k = involved[i];
        const Vec3& a = r.mesh.vertices[r.new_vertex_edge[k][0]];
        const Vec3& b = r.mesh.vertices[r.new_vertex_edge[k][1]];
        Vec3& x = r.mesh.vertices[r.first_new_vertex + k];
        x = ++stage[k] == 1 ? by_normal(a, b, r.new_vertex_normal[k]) : Vec3(0.5 * (a + b));
      });
      moved += involved.size();
      Timer t_validate;
      rv = validate_mesh(r.mesh);
      level.seconds_mesh += t_validate.seconds();
      if (rv.report.valid() && as_is(rv, r)) return moved;
    }
    return moved;
  };
  ValidatedMesh current = v;
  BandResult current_band = band;
  for (int round = 1; round <= kRounds; ++round) {
    const std::size_t n = current.mesh.faces.size();
    std::vector<char> wide(n, 0);
    std::size_t count = 0;
    for (std::size_t i = 0; i < n; ++i) count += wide[i] = current_band.face_epsilon[i] > tol;
    if (count == 0) break;
    if (count >= previous_count && !(current_band.epsilon < 0.95 * previous_epsilon) && !mended_last) {
      log("repair round " + std::to_string(round) + ": " + std::to_string(count) + " faces still above the tolerance");
      return false;
    }
    previous_count = count;
    previous_epsilon = current_band.epsilon;
    if (count > std::max<std::size_t>(2000, n / 10)) {
      log("repair: " + std::to_string(count) + " faces above the tolerance, too many to split locally");
      return false;
    }
    RefinedMesh r;
    ValidatedMesh rv;
    bool accepted = false;
    std::size_t unfolded = 0;
    for (std::size_t rule = 0; rule < std::size(rules) && !accepted; ++rule) {
      unfolded = 0;  // only the accepted rule's mending counts
      Timer t_split;
      r = refine_faces(current.mesh, wide, rules[rule]);
      rv = validate_mesh(r.mesh);
      level.seconds_mesh += t_split.seconds();
      accepted = rv.report.valid() && as_is(rv, r);
      if (accepted) break;
      const std::string problem = rv.report.valid() ? std::string() : ": " + rv.report.errors[0].message;
      if (creases) unfolded = unfold(rule, r, rv);
      accepted = rv.report.valid() && as_is(rv, r);
      log("repair round " + std::to_string(round) + ": the refined mesh is not valid with new vertices placed " +
          (rule == 0 ? "by the gradient" : "along the edges' normals") + problem +
          (unfolded == 0 ? std::string()
                         : std::string(accepted ? "; mended" : "; not mended") + " by placing " +
                               std::to_string(unfolded) + " of its vertices again"));
    }
    if (!accepted) return false;
    Timer t_band;
    TriangleMesh fresh;
    fresh.vertices = r.mesh.vertices;
    for (std::size_t i = 0; i < r.mesh.faces.size(); ++i)
      if (r.is_new[i]) fresh.faces.push_back(r.mesh.faces[i]);
    const BandResult nb = certify_band(sdf, fresh, d, bo);
    BandResult merged;
    merged.face_epsilon.resize(r.mesh.faces.size());
    merged.pieces = nb.pieces;
    for (std::size_t i = 0, j = 0; i < r.mesh.faces.size(); ++i)
      merged.face_epsilon[i] = r.is_new[i] ? nb.face_epsilon[j++] : current_band.face_epsilon[r.kept_from[i]];
    set_band_maximum(merged);
    level.seconds_band += t_band.seconds();
    level.band_pieces += nb.pieces;
    log("repair round " + std::to_string(round) + ": split " + std::to_string(count) + " faces (" +
        std::to_string(r.split_edges) + " edges, " + std::to_string(r.mesh.faces.size()) + " faces now), band " +
        num(merged.epsilon / sdf.bbox().diagonal()) + " x diagonal");
    current = std::move(rv);
    current_band = std::move(merged);
    mended_last = unfolded > 0;
  }
  if (current_band.epsilon > tol) return false;
  v = std::move(current);
  band = std::move(current_band);
  return true;
}

// The repair as it was first, and where it fails, once more from the same candidate with new
// vertices on creases and folds mended (`creases`), before the caller re-meshes the level. The
// second way alone, tried on every level, failed where the first succeeds (spool -20 %: folds in
// five rounds, then a re-mesh) and succeeded where it fails (elephant -13 %, tet-shuffled,
// dino +2.5 %); in this order a level the first way repairs is unchanged.
bool repair_band(const SignedDistance& sdf, const FastSignedDistance& fast, double d, double tol, const BandOptions& bo,
                 ValidatedMesh& v, BandResult& band, OffsetLevel& level,
                 const std::function<void(const std::string&)>& log, bool creases) {
  if (repair_band_with(sdf, fast, d, tol, bo, v, band, level, log, false)) return true;
  if (!creases) return false;
  log("repair: again, with new vertices on creases and folds mended");
  return repair_band_with(sdf, fast, d, tol, bo, v, band, level, log, true);
}

// Seeds on the level set at and around each point of `missed` (the ring too: a small closed
// component, a pocket between an offset's folds or an island of a deep level, needs several for
// the mesher to find facets on it). Returns how many were appended.
std::size_t seeds_at(const FastSignedDistance& fast, double d, const std::vector<Vec3>& missed, std::vector<Vec3>& seeds,
                     int max_doublings = 12) {
  const std::size_t before = seeds.size();
  for (const Vec3& x : missed) {
    Vec3 s;
    if (point_on_level_near(fast, d, x, s)) seeds.push_back(s);
    points_on_level_around(fast, d, x, seeds, max_doublings);
  }
  return seeds.size() - before;
}

// Thrown by the evaluator of a meshing whose budget of distance evaluations is spent.
struct MeshingBudgetSpent {};

// The completeness search found regions of the level set outside the candidate. Where they are
// components of their own (islands of a deep level that no seed reached: boeing -20 %'s engines),
// meshing them alone and adding them costs a fraction of a re-mesh of the whole level. The union
// is a candidate like any other: validated in full (a region that belongs to a component already
// meshed gives a second copy of it, which meets the first: rejected, and the caller re-meshes),
// the added faces' band certified (the kept faces keep theirs), completeness searched again. On
// success `v`, `band` and `comp` describe the union.
// Such a region is often a lobe of a component already meshed (femur and homer +5 %, rotor -20 %):
// the mesher then meshes that whole component again, as many faces as the candidate, before the
// union is rejected. So it may evaluate the distance at most `max_evaluations` times (the caller:
// a third of the candidate's meshing, at least 50,000, about a quarter of a second).
bool add_missed_regions(const SignedDistance& sdf, const FastSignedDistance& fast,
                        const std::function<double(const Vec3&)>& f, const Vec3& center, double radius, double d,
                        double tol, const LevelSetMeshOptions& mo, const OffsetOptions& options,
                        std::uint64_t max_evaluations, ValidatedMesh& v, BandResult& band, CompletenessResult& comp,
                        CompletenessCheckpoint& checkpoint, CompletenessPrefetch& prefetch,
                        const CompletenessOptions& co, OffsetLevel& level,
                        const std::function<void(const std::string&)>& log) {
  // Rings within 8 |s - d| of each missed point: farther sign changes are mostly on components
  // already meshed, which the island's mesher would then mesh again.
  std::vector<Vec3> seeds;
  seeds_at(fast, d, comp.missed, seeds, 3);
  if (seeds.size() < 4) return false;
  Timer t_mesh;
  TriangleMesh island;
  std::atomic<std::uint64_t> evaluations{0};
  const std::function<double(const Vec3&)> g = [&](const Vec3& p) {
    if (evaluations.fetch_add(1, std::memory_order_relaxed) >= max_evaluations) throw MeshingBudgetSpent{};
    return f(p);
  };
  // Always Surface_mesher, on this thread: the budget stops it by an exception, which Mesh_3's
  // parallel mode does not survive (a task that throws while holding a cell lock leaves the others
  // waiting for it: the test hung), and an island is too small to share out.
  try {
    while_prefetching(prefetch, [&] { island = mesh_level_set(g, center, radius, seeds, mo); });
  } catch (const MeshingBudgetSpent&) {
    level.seconds_mesh += t_mesh.seconds();
    log("the missed regions alone: more than " + std::to_string(max_evaluations) +
        " distance evaluations after " + num(t_mesh.seconds()) + " s: not an island");
    return false;
  } catch (const std::exception& e) {
    level.seconds_mesh += t_mesh.seconds();
    log("the missed regions alone: the mesher failed: " + first_line(e.what()));
    return false;
  }
  // Oriented alone first (as a mesher's output always is), so that the union's validation has
  // nothing to change unless the parts meet or nest.
  const ValidatedMesh iv = validate_mesh(island);
  if (iv.report.valid()) island = iv.mesh;
  TriangleMesh both = v.mesh;
  const std::uint32_t base = static_cast<std::uint32_t>(both.vertices.size());
  both.vertices.insert(both.vertices.end(), island.vertices.begin(), island.vertices.end());
  for (const Face& t : island.faces) both.faces.push_back({t[0] + base, t[1] + base, t[2] + base});
  ValidatedMesh uv = validate_mesh(both);
  level.seconds_mesh += t_mesh.seconds();
  const std::string what = "the missed regions alone: " + std::to_string(island.faces.size()) + " faces (" +
                           std::to_string(seeds.size()) + " seeds, " + std::to_string(evaluations.load()) +
                           " distance evaluations) in " + num(t_mesh.seconds()) + " s";
  // Validation must keep the union as it is, so that the kept faces' bands still belong to them.
  if (island.faces.empty() || !uv.report.valid() || uv.mesh.faces != both.faces || uv.mesh.vertices != both.vertices) {
    std::string why = "nothing meshed";
    if (!island.faces.empty())
      why = !uv.report.valid() ? "the union is not valid: " + uv.report.errors[0].message
            : uv.mesh.vertices != both.vertices ? std::string("validation changed the union's vertices")
                                                : std::string("validation reoriented the union's faces (nested parts)");
    log(what + ", not added: " + why);
    return false;
  }
  Timer t_band;
  const BandOptions bo = offset_band_options(tol);
  const BandResult ib = certify_band(sdf, island, d, bo);
  level.seconds_band += t_band.seconds();
  level.band_pieces += ib.pieces;
  BandResult merged = band;
  merged.pieces += ib.pieces;
  merged.face_epsilon.insert(merged.face_epsilon.end(), ib.face_epsilon.begin(), ib.face_epsilon.end());
  set_band_maximum(merged);
  merged.faces_touching += ib.faces_touching;
  log(what + ", added; band " + num(merged.epsilon / sdf.bbox().diagonal()) + " x diagonal");
  const bool repaired = merged.epsilon > tol;  // then faces get split: the union is no longer the two parts
  if (repaired &&
      !(options.local_repair && repair_band(sdf, fast, d, tol, bo, uv, merged, level, log, options.repair_creases)))
    return false;
  // The search that found the regions is taken up where it stopped: only the cells near the added
  // faces are examined again (boeing -20 %: 0.9 s instead of a second search of 17 s).
  Timer t_comp;
  const double eps_c = std::max(merged.epsilon, 1e-9 * sdf.bbox().diagonal());
  CompletenessResult uc = repaired ? certify_completeness(sdf, uv.mesh, d, eps_c, co)
                                   : resume_completeness(sdf, uv.mesh, island, d, eps_c, checkpoint, co);
  level.seconds_completeness += t_comp.seconds();
  level.completeness_cells += uc.cells;
  log(std::string(uc.complete ? "complete" : "NOT complete") + " with the missed regions added (" +
      std::to_string(uc.cells) + " cells" + (uc.resumed ? " more, the search resumed" : "") + ", " +
      std::to_string(uc.missed.size()) + " missed, " + std::to_string(uc.unresolved.size()) + " unresolved) in " +
      num(t_comp.seconds()) + " s");
  v = std::move(uv);
  band = std::move(merged);
  comp = std::move(uc);
  return true;
}

}  // namespace

BandOptions offset_band_options(double tol) {
  BandOptions bo;
  bo.target = 0.75 * tol;
  bo.second_pass_above = tol;
  return bo;
}

OffsetLevel compute_offset_level(const SignedDistance& sdf, const MaxPenetrationResult& mp, double d,
                                 const OffsetOptions& options) {
  OffsetLevel level;
  level.d = d;
  const Aabb box = sdf.bbox();
  const double diag = box.diagonal();
  const double tol = options.tolerance_relative * diag;
  if (d < -mp.depth.hi) {  // no interior point is that deep: the level set is empty (certified)
    level.status = OffsetStatus::Empty;
    level.complete = true;
    level.message = "deeper than the certified maximum penetration " + num(mp.depth.hi);
    return level;
  }
  // d = 0, or within the tolerance of the surface: F itself is a certified offset (doc/offsets.md,
  // step 1): s = 0 on F, so its band is exactly |d| <= tol, and F separates {s < 0} from {s > 0},
  // which hold A = {s < d - |d|} and B = {s > d + |d|}. A mesh of {s = d} there runs within one
  // band of F, where faces cannot be proven off F: armadillo at +-tol/2 failed four attempts in 100 s.
  if (std::abs(d) <= tol) {
    level.status = OffsetStatus::Original;
    level.mesh = sdf.mesh();
    level.epsilon = std::abs(d);
    level.complete = true;
    if (d != 0.0) level.message = "within the tolerance " + num(tol) + " of the surface: the input itself, band |d|";
    return level;
  }
  const FastSignedDistance fast(sdf);
  const std::function<double(const Vec3&)> f = [&](const Vec3& p) { return fast(p) - d; };
  // The deepest point is inside every nonempty level set: f < 0 there.
  const Vec3 center = mp.point;
  double radius = 0.0;
  for (int k = 0; k < 8; ++k) radius = std::max(radius, (box.corner(k) - center).norm());
  radius += std::max(d, 0.0) + 0.01 * diag;
  std::vector<Vec3> seeds = d < -mp.depth.lo ? std::vector<Vec3>{} : level_set_seeds(f, center, radius, options.seeds);

  LevelSetMeshOptions mo;
  mo.radius_bound = options.radius_relative * diag;
  mo.distance_bound = options.distance_over_tolerance * tol;
  // Vertices land within 1e-6 x radius (about 1e-6 x diagonal) of the level: far below the
  // tolerance, and about a quarter fewer evaluations than CGAL's finer default bisection. (A
  // twentieth of the tolerance made pinion's mesher 15 % faster but changed the candidates, and
  // boeing -20 % and rotor -20 % then needed more repair: 35 -> 61 s and 11 -> 19 s.)
  mo.bisection_relative_error = 1e-6;
  mo.lipschitz = 1.0;  // f = s - d in doubles: 1-Lipschitz up to rounding (the mesher's margin covers it)
  std::vector<Vec3> carried;  // vertices of the last candidate that failed the completeness search
  // The completeness search's part about F alone, made while the mesher runs (doc/offsets.md, "The
  // search's part about F ahead"); every search of the level uses it, with the same domain.
  CompletenessPrefetch prefetch(sdf, d, tol);
  CompletenessOptions co;
  co.band_bound = tol;
  co.prefetch = &prefetch;
  for (int attempt = 1; attempt <= options.max_attempts; ++attempt) {
    level.attempts = attempt;
    level.distance_bound = mo.distance_bound;
    auto log = [&](const std::string& what) {
      if (options.log) options.log("level " + num(d) + ", attempt " + std::to_string(attempt) + ": " + what);
    };
    Timer t_mesh;
    TriangleMesh mesh;
    LevelSetMeshStats stats;
    std::string mesher_failure;
    if (seeds.size() >= 4) {
      try {
        std::vector<Vec3> all = seeds;
        all.insert(all.end(), carried.begin(), carried.end());
        if (options.parallel_mesher) mesh = mesh_level_set_parallel(f, center, radius, all, mo, &stats);
        else while_prefetching(prefetch, [&] { mesh = mesh_level_set(f, center, radius, all, mo, &stats); });
      } catch (const std::exception& e) {
        // CGAL's mesher refuses some configurations with an assertion (e.g. a refinement point
        // rounded onto a vertex): a failed attempt, not a failed run; the next one meshes finer.
        mesher_failure = first_line(e.what());
      }
    }
    ValidatedMesh v = validate_mesh(mesh);
    level.seconds_mesh += t_mesh.seconds();
    if (!mesher_failure.empty()) {
      level.message = "attempt " + std::to_string(attempt) + ": the mesher failed: " + mesher_failure;
      log("the mesher failed: " + mesher_failure);
      mo.distance_bound *= 0.7;
      continue;
    }
    log("meshed " + std::to_string(mesh.faces.size()) + " faces (distance bound " + num(mo.distance_bound) + ", " +
        std::to_string(seeds.size()) + " seeds" +
        (carried.empty() ? std::string() : ", " + std::to_string(carried.size()) + " vertices of the last candidate") +
        ") in " + num(t_mesh.seconds()) + " s: " + std::to_string(stats.evaluations) +
        " distance evaluations for " + std::to_string(stats.calls) + " signs (" + std::to_string(stats.lipschitz) +
        " by the Lipschitz bound)");
    if (!mesh.faces.empty() && !v.report.valid()) {
      level.message = "attempt " + std::to_string(attempt) + ": mesher output invalid: " + v.report.errors[0].message;
      mo.distance_bound *= 0.7;
      continue;
    }
    double eps = 0.0;
    BandResult band;
    if (!v.mesh.faces.empty()) {
      Timer t_band;
      const BandOptions bo = offset_band_options(tol);
      band = certify_band(sdf, v.mesh, d, bo);
      level.seconds_band += t_band.seconds();
      level.band_pieces += band.pieces;
      const auto wide = std::count_if(band.face_epsilon.begin(), band.face_epsilon.end(), [&](double e) { return e > tol; });
      log("band " + num(band.epsilon / diag) + " x diagonal in " + num(t_band.seconds()) + " s (" +
          std::to_string(wide) + " faces above the tolerance" +
          (band.faces_touching ? ", " + std::to_string(band.faces_touching) + " not proved off F" : std::string()) + ")");
      if (options.local_repair && band.epsilon > tol &&
          repair_band(sdf, fast, d, tol, bo, v, band, level, log, options.repair_creases))
        ++level.repairs;
      eps = band.epsilon;
      if (eps > tol) {
        const Face& w = v.mesh.faces[band.worst_face];
        const Vec3 at = (v.mesh.vertices[w[0]] + v.mesh.vertices[w[1]] + v.mesh.vertices[w[2]]) / 3.0;
        std::ostringstream os;
        os.precision(9);
        os << "attempt " << attempt << ": band " << eps << " (" << eps / diag << " x diagonal) exceeds the tolerance "
           << tol << ", worst at face " << band.worst_face << " near (" << at.x() << ", " << at.y() << ", " << at.z()
           << ")";
        level.message = os.str();
        mo.distance_bound *= 0.7;
        continue;
      }
    }
    // Completeness for the certified band (at least a tiny positive width for an empty mesh).
    Timer t_comp;
    const double eps_c = std::max(eps, 1e-9 * diag);
    CompletenessCheckpoint checkpoint;
    CompletenessResult comp =
        certify_completeness(sdf, v.mesh, d, eps_c, co, options.mesh_missed_regions_alone ? &checkpoint : nullptr);
    level.seconds_completeness += t_comp.seconds();
    level.completeness_cells += comp.cells;
    log(std::string(comp.complete ? "complete" : "NOT complete") + " (" + std::to_string(comp.cells) + " cells, " +
        std::to_string(comp.prefetched) + " of them prefetched of " + std::to_string(prefetch.cells()) + ", " +
        std::to_string(comp.missed.size()) + " missed, " + std::to_string(comp.unresolved.size()) + " unresolved) in " +
        num(t_comp.seconds()) + " s");
    const std::uint64_t island_budget = std::max<std::uint64_t>(stats.evaluations / 3, 50000);
    if (!comp.complete && !comp.missed.empty() && !v.mesh.faces.empty() && options.mesh_missed_regions_alone &&
        add_missed_regions(sdf, fast, f, center, radius, d, tol, mo, options, island_budget, v, band, comp, checkpoint,
                           prefetch, co, level, log))
      eps = band.epsilon;
    if (!comp.complete) {
      // The next candidate starts from this one's vertices as well as the seeds: it keeps the parts
      // of the level set this one found. A fresh mesh with the new seeds found the missed part but
      // lost another, reached through a narrow neck (boeing -20 %: one wing per attempt, 4 attempts).
      carried = v.mesh.vertices;
      const std::size_t added = seeds_at(fast, d, comp.missed, seeds);
      std::ostringstream os;
      os.precision(9);
      if (!comp.missed.empty()) {
        os << "attempt " << attempt << ": " << comp.missed.size() << " region(s) of the level set missed, e.g. near ("
           << comp.missed[0].x() << ", " << comp.missed[0].y() << ", " << comp.missed[0].z() << "); " << added
           << " seed(s) added";
      } else {
        os << "attempt " << attempt << ": completeness unresolved near (" << comp.unresolved[0].x() << ", "
           << comp.unresolved[0].y() << ", " << comp.unresolved[0].z() << ")" << budget_note(comp);
      }
      level.message = os.str();
      if (added == 0) mo.distance_bound *= 0.7;
      continue;
    }
    level.mesh = std::move(v.mesh);
    level.report = std::move(v.report);
    level.epsilon = eps;
    level.complete = true;
    level.status = level.mesh.faces.empty() ? OffsetStatus::Empty : OffsetStatus::Certified;
    if (level.status == OffsetStatus::Empty) level.message = "empty (certified by the completeness search)";
    else level.message.clear();
    return level;
  }
  level.status = OffsetStatus::Failed;
  return level;
}

}  // namespace cdbench
