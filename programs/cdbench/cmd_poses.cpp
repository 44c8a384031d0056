// cdbench poses MESH --levels LIST --directions N --orientations K -o DIR: a certified pose set.
#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "commands.h"
#include "number_text.h"
#include "distance/max_penetration.h"
#include "mesh/read_mesh.h"
#include "mesh_loading.h"
#include "offset/level_list.h"
#include "offset_set.h"
#include "placement/place_pose.h"
#include "poseset/pose_csv.h"
#include "poseset_summary.h"
#include "sampling/sampling.h"
#include "util/atomic_file.h"
#include "util/dynamic_parallel.h"
#include "util/error.h"
#include "util/progress.h"
#include "util/sha256.h"
#include "util/timer.h"

namespace cdbench::cli {
namespace {

struct PosesCliOptions {
  std::string mesh, mover, levels, out;
  std::size_t directions = 100, orientations = 10;
  std::string direction_sampling = "fibonacci", orientation_sampling = "super-fibonacci";
  std::uint64_t seed = 1;
  int threads = 0;
  std::string shard = "0/1";
  bool resume = false, no_polish = false;
  std::string start = "auto";
  double tolerance = 1e-6;       // certification tolerance, relative to the fixed mesh's diagonal
  double band_tolerance = 1e-3;  // offsets' band tolerance, relative
  double max_penetration_tolerance = 1e-6;
  int max_steps = 400;
  std::string command_line;
};

struct Shard {
  std::uint64_t index = 0, count = 1;
};

Shard parse_shard(const std::string& s) {
  const auto slash = s.find('/');
  Shard r;
  try {
    if (slash == std::string::npos) throw std::invalid_argument("");
    std::size_t a = 0, b = 0;
    r.index = std::stoull(s.substr(0, slash), &a);
    r.count = std::stoull(s.substr(slash + 1), &b);
    if (a != slash || b != s.size() - slash - 1) throw std::invalid_argument("");
  } catch (const std::exception&) {
    throw InputError("--shard: expected I/N with 0 <= I < N, found '" + s + "'");
  }
  if (r.count == 0 || r.index >= r.count) throw InputError("--shard: expected I/N with 0 <= I < N, found '" + s + "'");
  return r;
}

TriangleMesh read_certified_offset(const std::string& path) {
  const PolygonSoup soup = read_polygon_soup(path);
  TriangleMesh m;
  m.vertices = soup.points;
  for (const auto& p : soup.polygons) {
    if (p.size() != 3) throw InputError(path + ": offset mesh has a non-triangular face");
    m.faces.push_back({static_cast<std::uint32_t>(p[0]), static_cast<std::uint32_t>(p[1]), static_cast<std::uint32_t>(p[2])});
  }
  return m;
}

nlohmann::json mesh_json(const std::string& path, const std::string& sha, const TriangleMesh& m, const Vec3& ref) {
  return {{"path", path},
          {"sha256", sha},
          {"vertices", m.vertices.size()},
          {"faces", m.faces.size()},
          {"diagonal", m.bbox().diagonal()},
          {"reference_point", {ref.x(), ref.y(), ref.z()}}};
}

// Rows of the journal (complete lines only; a line cut by an interruption is dropped).
std::map<std::uint64_t, std::string> read_journal(const std::string& path, std::size_t levels) {
  std::map<std::uint64_t, std::string> rows;
  std::ifstream in(path, std::ios::binary);
  std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t start = 0;
  std::size_t line_no = 0;
  while (start < content.size()) {
    const std::size_t end = content.find('\n', start);
    if (end == std::string::npos) break;  // cut short
    const std::string line = content.substr(start, end - start + 1);
    start = end + 1;
    ++line_no;
    try {
      const PoseRow r = parse_pose_row(line, path + ":" + std::to_string(line_no));
      rows[r.pose] = line;
    } catch (const InputError&) {
      // A damaged line: its approach is recomputed.
    }
  }
  // Keep whole approaches only (an approach's rows are written together).
  std::map<std::uint64_t, std::size_t> per_approach;
  for (const auto& [pose, line] : rows) ++per_approach[pose / levels];
  for (auto it = rows.begin(); it != rows.end();)
    it = per_approach[it->first / levels] == levels ? std::next(it) : rows.erase(it);
  return rows;
}

int run_poses(const PosesCliOptions& opt) {
  std::unique_ptr<tbb::global_control> threads;
  if (opt.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, opt.threads);
  // Option errors before any work.
  const std::vector<LevelSpec> specs = parse_level_list(opt.levels);
  const Shard shard = parse_shard(opt.shard);
  if (opt.direction_sampling != "fibonacci" && opt.direction_sampling != "grid")
    throw InputError("--direction-sampling: expected 'fibonacci' or 'grid', found '" + opt.direction_sampling + "'");
  if (opt.orientation_sampling != "super-fibonacci" && opt.orientation_sampling != "random")
    throw InputError("--orientation-sampling: expected 'super-fibonacci' or 'random', found '" + opt.orientation_sampling + "'");
  {
    std::set<std::string> seen;
    for (const LevelSpec& l : specs)
      if (!seen.insert(l.text).second) throw InputError("--levels: level '" + l.text + "' is listed twice");
  }
  Timer total;

  const LoadedMesh fixed_loaded = load_mesh(opt.mesh);
  if (!report_if_not_solid(fixed_loaded)) return kExitInvalidMesh;
  const std::string mover_path = opt.mover.empty() ? opt.mesh : opt.mover;
  LoadedMesh mover_loaded;
  if (!opt.mover.empty()) {
    mover_loaded = load_mesh(opt.mover);
    if (!report_if_not_solid(mover_loaded)) return kExitInvalidMesh;
  }
  const TriangleMesh& mover = opt.mover.empty() ? fixed_loaded.validated.mesh : mover_loaded.validated.mesh;
  const std::string fixed_sha = sha256_file(opt.mesh);
  const std::string mover_sha = opt.mover.empty() ? fixed_sha : sha256_file(opt.mover);

  std::error_code ec;
  std::filesystem::create_directories(opt.out, ec);
  if (!std::filesystem::is_directory(opt.out)) throw InputError(opt.out + ": cannot create the output directory");
  const std::string journal_path = opt.out + "/poses.journal";
  const std::string journal_key_path = opt.out + "/poses.journal.json";

  const SignedDistance sdf(fixed_loaded.validated.mesh);
  const double diag = sdf.bbox().diagonal();
  double seconds_mp = 0.0;
  const MaxPenetrationResult mp = timed_max_penetration(sdf, opt.max_penetration_tolerance, &seconds_mp);
  const bool polish = !opt.no_polish;
  const double tol = opt.tolerance * diag;

  // Levels: targets and where their poses start (doc/poses.md): the exact first contact with the
  // surface itself (level 0; d < 0 by default), far away (d > 0 by default), or the first contact
  // with a certified offset at d + 2 band (--start offset) or at d (no polishing).
  const std::size_t L = specs.size();
  std::vector<double> targets(L), swept(L);
  std::vector<PoseStart> start(L);
  for (std::size_t l = 0; l < L; ++l) {
    targets[l] = level_distance(specs[l], mp.depth.lo);
    start[l] = planned_start(targets[l], polish, opt.start == "offset" ? StartPolicy::Offsets : StartPolicy::NoOffsets);
    swept[l] = start[l] == PoseStart::Offset && polish ? targets[l] + 2.0 * opt.band_tolerance * diag : targets[l];
  }

  // Run identity: a resumed run must be the same run.
  nlohmann::json run_key = {{"fixed_sha256", fixed_sha},
                            {"mover_sha256", mover_sha},
                            {"levels", opt.levels},
                            {"directions", opt.directions},
                            {"orientations", opt.orientations},
                            {"direction_sampling", opt.direction_sampling},
                            {"orientation_sampling", opt.orientation_sampling},
                            {"seed", opt.seed},
                            {"tolerance", opt.tolerance},
                            {"band_tolerance", opt.band_tolerance},
                            {"polish", polish},
                            {"start", opt.start},
                            {"max_steps", opt.max_steps},
                            {"shard", opt.shard},
                            {"generator", std::string("cdbench ") + CDBENCH_VERSION}};
  std::map<std::uint64_t, std::string> done_rows;
  if (std::filesystem::exists(journal_path)) {
    if (!opt.resume)
      throw InputError(opt.out + " holds an interrupted run (poses.journal): pass --resume to continue it, or remove "
                       "the journal to start over");
    std::ifstream kin(journal_key_path);
    nlohmann::json old;
    try {
      old = nlohmann::json::parse(kin);
    } catch (const std::exception&) {
      throw InputError(journal_key_path + ": unreadable; cannot tell which run the journal belongs to");
    }
    if (old != run_key)
      throw InputError("--resume: the journal in " + opt.out + " belongs to a run with other inputs or options (" +
                       journal_key_path + ")");
    done_rows = read_journal(journal_path, L);
  }

  // Offsets of the levels that start from one (reused across runs by their own manifest).
  OffsetSetRequest req = make_offset_request(fixed_loaded, sdf, mp, opt.max_penetration_tolerance, seconds_mp, fixed_sha,
                                            opt.out + "/offsets");
  std::vector<std::ptrdiff_t> offset_of(L, -1);  // index in the offset set
  for (std::size_t l = 0; l < L; ++l) {
    if (start[l] != PoseStart::Offset) continue;
    offset_of[l] = static_cast<std::ptrdiff_t>(req.distances.size());
    req.names.push_back(polish ? specs[l].text + "+2band" : specs[l].text);
    req.distances.push_back(swept[l]);
  }
  req.options.tolerance_relative = opt.band_tolerance;
  req.log_prefix = "cdbench poses: ";
  std::cerr << "cdbench poses: max penetration [" << number_text(mp.depth.lo) << ", " << number_text(mp.depth.hi)
            << "]; " << (req.distances.empty() ? std::string("no offset meshes needed (--start ") + opt.start + ")"
                                                : "offsets for " + std::to_string(req.distances.size()) + " of " +
                                                      std::to_string(L) + " level(s) in " + req.out_dir)
            << std::endl;
  Timer t_offsets;
  const OffsetSetResult offsets = write_offset_set(req);
  const double seconds_offsets = t_offsets.seconds();
  std::vector<std::unique_ptr<SweepMesh>> level_mesh(L);
  std::vector<std::string> level_state(L), level_note(L);
  for (std::size_t l = 0; l < L; ++l) {
    if (offset_of[l] < 0) continue;
    const std::size_t i = static_cast<std::size_t>(offset_of[l]);
    const std::string status = offsets.manifest["levels"][i]["status"].get<std::string>();
    level_state[l] = status;
    if (status == "certified") {
      const TriangleMesh m = read_certified_offset(req.out_dir + "/" + offsets.files[i]);
      level_mesh[l] = std::make_unique<SweepMesh>(make_sweep_mesh(m.vertices, m.faces));
    } else if (status == "failed") {
      // The level's poses must not depend on an offset that could not be certified.
      if (fallback_start(targets[l], polish, &start[l])) {
        level_note[l] = std::string("offset failed; conservative advance from the ") +
                        (start[l] == PoseStart::Surface ? "first contact with the surface" : "far start");
        std::cerr << "cdbench poses: note: level " << specs[l].text << ": " << level_note[l] << std::endl;
      }
    }
    // "empty": no point that deep (or far) exists on this side; its rows say so.
  }
  std::unique_ptr<SweepMesh> surface;
  if (std::count(start.begin(), start.end(), PoseStart::Surface) > 0)
    surface = std::make_unique<SweepMesh>(
        make_sweep_mesh(fixed_loaded.validated.mesh.vertices, fixed_loaded.validated.mesh.faces));
  // The surface a level's poses are swept against (none for a far start).
  const auto swept_surface = [&](std::size_t l) -> const SweepMesh* {
    return start[l] == PoseStart::Surface ? surface.get() : level_mesh[l].get();
  };

  // Sampling.
  const std::vector<Vec3> dirs =
      opt.direction_sampling == "grid" ? sphere_grid(opt.directions) : sphere_fibonacci(opt.directions);
  const std::vector<Eigen::Quaterniond> rots = opt.orientation_sampling == "random"
                                                   ? rotations_random(opt.orientations, opt.seed)
                                                   : rotations_super_fibonacci(opt.orientations);
  const std::uint64_t N = dirs.size(), K = rots.size();
  const std::uint64_t approaches = N * K;
  const std::uint64_t first = approaches * shard.index / shard.count;
  const std::uint64_t last = approaches * (shard.index + 1) / shard.count;

  const ApproachSetup setup = make_approach_setup(sdf, mover);
  PoseOptions po;
  po.tolerance = tol;
  po.polish = polish;
  po.max_steps = opt.max_steps;

  write_file_atomically(journal_key_path, [&](std::ostream& out) { out << std::setw(2) << run_key << "\n"; });
  std::ofstream journal(journal_path, std::ios::app | std::ios::binary);
  if (!journal) throw InputError(journal_path + ": cannot open for writing");

  // Pending approaches in order; an orientation's frame is built by the first thread that needs it
  // and freed after its last approach.
  std::vector<std::uint64_t> pending;
  for (std::uint64_t a = first; a < last; ++a)
    if (!done_rows.count(a * L)) pending.push_back(a);
  if (!done_rows.empty())
    std::cerr << "cdbench poses: resuming: " << (last - first - pending.size()) << " of " << (last - first)
              << " approaches already certified" << std::endl;
  struct LazyFrame {
    std::once_flag once;
    std::unique_ptr<OrientationFrame> frame;
    std::atomic<std::uint64_t> left{0};
  };
  std::vector<LazyFrame> frames(K);
  for (std::uint64_t a : pending) ++frames[a / N].left;
  Progress progress("poses", pending.size() * L);
  std::vector<std::atomic<std::uint64_t>> level_ns(L);  // thread time per level
  Timer t_poses;
  std::mutex journal_mutex;
  std::uint64_t approaches_written = 0;
  // For the resume test only: die (as from a kill or power loss) after this many journal writes.
  const char* kill_env = std::getenv("CDBENCH_TEST_KILL_AFTER_APPROACHES");
  const std::uint64_t kill_after = kill_env ? std::strtoull(kill_env, nullptr, 10) : 0;
  parallel_for_dynamic(pending.size(), [&](std::size_t i) {
    const std::uint64_t a = pending[i], o = a / N;
    LazyFrame& lazy = frames[o];
    std::call_once(lazy.once, [&] {
      lazy.frame = std::make_unique<OrientationFrame>(make_orientation_frame(setup, rots[o].toRotationMatrix()));
    });
    const OrientationFrame& frame = *lazy.frame;
    const Vec3& dir = dirs[a % N];
    std::vector<std::string> lines(L);
    for (std::size_t l = 0; l < L; ++l) {
      PoseRow row;
      row.pose = a * L + l;
      row.level = static_cast<int>(l);
      row.target = targets[l];
      row.R = frame.orientation.R;
      row.dir = dir;
      row.orientation = o;
      row.direction = a % N;
      // A row without a pose: its values are NaN, its status says why.
      const auto unplaced = [&row](const std::string& reason) {
        const double nan = std::numeric_limits<double>::quiet_NaN();
        row.t = Vec3::Constant(nan);
        row.clearance_lo = row.clearance_hi = row.raw_clearance_lo = row.raw_clearance_hi = row.lambda = nan;
        row.status = "uncertified:" + reason;
      };
      const SweepMesh* swept_against = swept_surface(l);
      if (!swept_against && start[l] != PoseStart::Far) {
        unplaced("offset-" + level_state[l]);
      } else {
        PoseOptions level_po = po;
        level_po.start = start[l];
        Timer t_pose;
        const PoseOutcome p = place_pose(setup, frame, swept_against, dir, targets[l], level_po);
        level_ns[l] += static_cast<std::uint64_t>(t_pose.seconds() * 1e9);
        if (!p.contact) {
          unplaced(p.reason);  // "no-contact"
        } else {
          row.t = p.t;
          row.lambda = p.lambda;
          row.clearance_lo = p.clearance.lo;
          row.clearance_hi = p.clearance.hi;
          row.raw_clearance_lo = p.raw_clearance.lo;
          row.raw_clearance_hi = p.raw_clearance.hi;
          row.polish_steps = p.steps;
          row.status = p.reason.empty() ? "certified" : "uncertified:" + p.reason;
        }
      }
      lines[l] = format_pose_row(row);
      progress.advance();
    }
    if (--lazy.left == 0) lazy.frame.reset();
    // One write and flush per approach: an interruption loses at most the approaches in flight.
    std::lock_guard<std::mutex> lock(journal_mutex);
    for (std::size_t l = 0; l < L; ++l) {
      journal << lines[l];
      done_rows[a * L + l] = std::move(lines[l]);
    }
    journal.flush();
    if (!journal) throw InputError(journal_path + ": write failed (disk full?)");
    if (kill_after > 0 && ++approaches_written >= kill_after) std::raise(SIGKILL);  // tests: a hard interruption
  });
  const std::uint64_t computed = pending.size() * L;
  progress.finish();
  const double seconds_poses = t_poses.seconds();
  journal.close();

  // poses.csv: every row of this shard, in pose order.
  std::uint64_t expected = (last - first) * L, rows_written = 0;
  std::vector<PoseRow> shard_rows;
  write_file_atomically(opt.out + "/poses.csv", [&](std::ostream& out) {
    out << kPoseCsvHeader << "\n";
    for (const auto& [pose, line] : done_rows) {
      if (pose < first * L || pose >= last * L) continue;
      out << line;
      ++rows_written;
      shard_rows.push_back(parse_pose_row(line, journal_path));
    }
  });
  if (rows_written != expected)
    throw InputError("internal: " + std::to_string(rows_written) + " rows for " + std::to_string(expected) + " poses");

  const std::vector<LevelSummary> summary = summarize_levels(shard_rows, L, tol);
  nlohmann::json ps;
  ps["format"] = "cdbench-poseset";
  ps["format_version"] = 1;
  ps["fixed"] = mesh_json(opt.mesh, fixed_sha, fixed_loaded.validated.mesh, setup.fixed_ref);
  ps["mover"] = mesh_json(mover_path, mover_sha, mover, setup.mover_ref);
  ps["mover_is_fixed"] = opt.mover.empty();
  ps["max_penetration"] = {{"interval", {mp.depth.lo, mp.depth.hi}},
                           {"point", {mp.point.x(), mp.point.y(), mp.point.z()}},
                           {"relative_tolerance", opt.max_penetration_tolerance}};
  ps["levels"] = nlohmann::json::array();
  for (std::size_t l = 0; l < L; ++l) {
    const LevelSummary& x = summary[l];
    nlohmann::json swept_offset;  // null: the level's poses use no offset
    if (offset_of[l] >= 0) {
      const std::size_t i = static_cast<std::size_t>(offset_of[l]);
      const nlohmann::json& e = offsets.manifest["levels"][i];
      swept_offset = {{"d", swept[l]},
                      {"status", level_state[l]},
                      {"file", offsets.files[i].empty() ? nlohmann::json() : nlohmann::json("offsets/" + offsets.files[i])},
                      {"epsilon", e["epsilon"]},
                      {"faces", e["faces"]}};
    }
    ps["levels"].push_back({{"index", l},
                            {"spec", specs[l].text},
                            {"target", targets[l]},
                            {"fraction_of_max_penetration", targets[l] / mp.depth.lo},
                            {"target_over_diagonal", targets[l] / diag},
                            {"start", to_string(start[l])},
                            {"start_note", level_note[l]},
                            {"swept_offset", swept_offset},
                            {"poses", x.poses},
                            {"certified", x.certified},
                            {"on_target", x.on_target},
                            {"no_contact", x.no_contact},
                            {"raw_placement_error",
                             {{"max", x.raw_error_max}, {"mean", x.placed() ? x.raw_error_sum / x.placed() : 0.0}}},
                            {"mean_polish_steps", x.placed() ? x.steps_sum / x.placed() : 0.0}});
  }
  ps["sampling"] = {{"directions", {{"kind", opt.direction_sampling}, {"count", N}}},
                    {"orientations", {{"kind", opt.orientation_sampling}, {"count", K}, {"seed", opt.seed}}},
                    {"pose_index", "(orientation * directions + direction) * levels + level"}};
  ps["shard"] = {{"index", shard.index}, {"count", shard.count}, {"first_approach", first}, {"end_approach", last}};
  ps["certification"] = {{"tolerance_relative", opt.tolerance}, {"tolerance", tol}, {"diagonal", diag}};
  ps["polishing"] = {{"enabled", polish},
                     {"max_steps", opt.max_steps},
                     {"band_tolerance_relative", opt.band_tolerance},
                     {"swept_offset_shift", polish ? 2.0 * opt.band_tolerance * diag : 0.0}};
  ps["placement"] = {{"reference_point", "bounding-box centre"},
                     {"transform", "x_world = R x + t, R row-major"},
                     {"approach", "mover from +dir moving along -dir"}};
  ps["generator"] = {{"name", "cdbench"}, {"version", CDBENCH_VERSION}, {"command_line", opt.command_line}};
  ps["run_key"] = run_key;
  nlohmann::json level_timings = nlohmann::json::array();
  for (std::size_t l = 0; l < L; ++l) {
    const double sec = 1e-9 * static_cast<double>(level_ns[l].load());
    const double n = static_cast<double>(pending.size());
    level_timings.push_back({{"spec", specs[l].text},
                             {"thread_seconds", sec},
                             {"poses_per_thread_second", sec > 0 ? n / sec : 0.0}});
  }
  ps["timings"] = {{"max_penetration", seconds_mp},
                   {"levels", level_timings},
                   {"offsets", seconds_offsets},
                   {"poses", seconds_poses},
                   {"poses_computed", computed},
                   {"poses_per_second", seconds_poses > 0 ? computed / seconds_poses : 0.0},
                   {"total", total.seconds()}};
  write_file_atomically(opt.out + "/poseset.json", [&](std::ostream& out) { out << std::setw(2) << ps << "\n"; });
  std::filesystem::remove(journal_path, ec);
  std::filesystem::remove(journal_key_path, ec);

  std::cout << "fixed:           " << opt.mesh << " (" << fixed_loaded.validated.mesh.faces.size() << " faces, diagonal "
            << std::setprecision(9) << diag << ")\n";
  std::cout << "mover:           " << mover_path << (opt.mover.empty() ? " (the fixed mesh)" : "") << "\n";
  std::cout << "max penetration: [" << number_text(mp.depth.lo) << ", " << number_text(mp.depth.hi) << "]\n";
  std::cout << "poses:           " << N << " directions x " << K << " orientations x " << L << " levels"
            << (shard.count > 1 ? ", shard " + opt.shard : std::string()) << "; tolerance " << tol << " ("
            << opt.tolerance << " x diagonal); polishing " << (polish ? "on" : "off") << "\n";
  print_level_table(std::cout, ps, diag);
  std::cout << "time:            " << std::fixed << std::setprecision(1) << total.seconds() << " s (offsets "
            << seconds_offsets << " s, poses " << seconds_poses << " s, " << std::setprecision(1)
            << (seconds_poses > 0 ? computed / seconds_poses : 0.0) << " poses/s)" << std::defaultfloat << "\n";
  std::cout << "pose set:        " << opt.out << "/poses.csv, " << opt.out << "/poseset.json\n";
  return kExitOk;
}

}  // namespace

void register_poses(CLI::App& app, int& exit_code, const std::string& command_line) {
  auto opt = std::make_shared<PosesCliOptions>();
  opt->command_line = command_line;
  CLI::App* cmd = app.add_subcommand(
      "poses",
      "A certified pose set: for every orientation x approach direction x level, the mover (rotated about its "
      "bbox centre, centres together) comes from far along +dir and moves along -dir to its first contact with the "
      "level's certified offset surface (exact sweeps on sphere trees), is then polished by conservative advancement "
      "until its certified clearance is within the tolerance of the target, and gets a rigorous clearance interval "
      "against the original surface. Writes DIR/poses.csv, DIR/poseset.json and DIR/offsets/ "
      "(format: doc/pose-set-format.md). An interrupted run continues with --resume.");
  cmd->add_option("mesh", opt->mesh, "the fixed closed mesh")->required();
  cmd->add_option("--mover", opt->mover, "the moving closed mesh (default: the fixed mesh)");
  cmd->add_option("--levels", opt->levels,
                  "comma-separated target clearances: absolute (-0.5), % of the certified maximum penetration "
                  "(-25%), ranges FROM:TO:STEP; 0 = touching")
      ->required();
  cmd->add_option("--directions", opt->directions, "approach directions on S^2")->capture_default_str()->check(CLI::Range(1, 10000000));
  cmd->add_option("--orientations", opt->orientations, "orientations in SO(3)")->capture_default_str()->check(CLI::Range(1, 10000000));
  cmd->add_option("--direction-sampling", opt->direction_sampling, "fibonacci (low discrepancy) or grid (latitude-longitude)")
      ->capture_default_str();
  cmd->add_option("--orientation-sampling", opt->orientation_sampling, "super-fibonacci (deterministic, uniform) or random (seeded)")
      ->capture_default_str();
  cmd->add_option("--seed", opt->seed, "seed of random orientations")->capture_default_str();
  cmd->add_option("--tolerance", opt->tolerance, "certification and polishing tolerance, relative to the fixed mesh's diagonal")
      ->capture_default_str()
      ->check(CLI::Range(1e-12, 1e-1));
  cmd->add_option("--band-tolerance", opt->band_tolerance, "offset surfaces' band tolerance, relative to the diagonal")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 0.1));
  cmd->add_option("--start", opt->start,
                  "where the conservative advance of each pose starts. auto: level 0 and penetrating levels at the "
                  "exact first contact with the surface itself, separated levels far away (no offset meshes). "
                  "offset: every level != 0 at the exact first contact with a certified offset at level + 2 bands "
                  "(computed into DIR/offsets, reused across runs). Without polishing, levels != 0 always use "
                  "their own offset")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "offset"}));
  cmd->add_flag("--no-polish", opt->no_polish, "keep the raw placement (first contact with the level's own offset)");
  cmd->add_option("--max-steps", opt->max_steps, "polishing steps per pose before it is reported as stalled")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--shard", opt->shard, "compute only part I of N (0 <= I < N) of the approaches; 'cdbench merge' joins shards")
      ->capture_default_str();
  cmd->add_flag("--resume", opt->resume, "continue an interrupted run in DIR (same inputs and options)");
  cmd->add_option("--threads", opt->threads, "worker threads (0: all cores)")->capture_default_str()->check(CLI::Range(0, 1024));
  cmd->add_option("-o,--output", opt->out, "output directory")->required();
  cmd->callback([opt, &exit_code]() { exit_code = run_poses(*opt); });
}

}  // namespace cdbench::cli
