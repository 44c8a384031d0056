// cdbench offset MESH --levels LIST -o DIR: certified offset surfaces at signed distances.
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

#include "commands.h"
#include "number_text.h"
#include "offset/offset_set.h"
#include "distance/max_penetration.h"
#include "mesh/write_mesh.h"
#include "mesh_loading.h"
#include "offset/level_list.h"
#include "offset/offset_level.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/progress.h"
#include "util/sha256.h"
#include "util/timer.h"

namespace cdbench::cli {
namespace {

struct OffsetCliOptions {
  std::string mesh, levels, out;
  double tolerance = 1e-3;
  double max_penetration_tolerance = 1e-6;
  int threads = 0;
  bool verbose = false;
  OffsetOptions offset;
};

int run_offset(const OffsetCliOptions& opt) {
  std::unique_ptr<tbb::global_control> threads;
  if (opt.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, opt.threads);
  const std::vector<LevelSpec> specs = parse_level_list(opt.levels);  // option errors before any work
  Timer total;
  const LoadedMesh loaded = load_mesh(opt.mesh);
  if (!report_if_not_solid(loaded)) return kExitInvalidMesh;
  prepare_output_directory(opt.out);
  const std::string input_sha = sha256_file(opt.mesh);
  const SignedDistance sdf(loaded.validated.mesh);
  const double diag = sdf.bbox().diagonal();
  double seconds_mp = 0.0;
  const MaxPenetrationResult mp = timed_max_penetration(sdf, opt.max_penetration_tolerance, &seconds_mp);
  const std::string scale_note =
      max_penetration_scale_note(specs, mp.depth.lo, mp.depth.hi, mp.tolerance_reached, opt.max_penetration_tolerance);
  if (!scale_note.empty()) std::cerr << "cdbench offset: note: " << scale_note << std::endl;

  OffsetSetRequest req = make_offset_request(mesh_source(loaded), sdf, mp, opt.max_penetration_tolerance, seconds_mp, input_sha,
                                            opt.out);
  for (const LevelSpec& l : specs) {
    req.names.push_back(l.text);
    req.distances.push_back(level_distance(l, mp.depth.lo));
  }
  check_distinct_distances(specs, req.distances);
  req.options = opt.offset;
  req.options.tolerance_relative = opt.tolerance;
  req.verbose = opt.verbose;
  const OffsetSetResult set = write_offset_set(req);
  const nlohmann::json& manifest = set.manifest;
  const OffsetOptions& oo = req.options;
  const std::size_t n = specs.size();
  const std::string manifest_path = opt.out + "/manifest.json";
  std::cout << "input:           " << opt.mesh << " (" << loaded.validated.mesh.faces.size() << " faces, diagonal "
            << std::setprecision(9) << diag << ")\n";
  std::cout << "max penetration: [" << number_text(mp.depth.lo) << ", " << number_text(mp.depth.hi) << "]\n";
  std::cout << "tolerance:       " << oo.tolerance_relative * diag << " (" << oo.tolerance_relative << " x diagonal)\n";
  std::size_t width = 8;
  for (const LevelSpec& l : specs) width = std::max(width, l.text.size() + 2);
  std::cout << std::left << std::setw(static_cast<int>(width)) << "level" << std::setw(14) << "d" << std::setw(11) << "status"
            << std::setw(10) << "faces" << std::setw(7) << "genus" << std::setw(6) << "comp" << std::setw(14)
            << "eps/diag" << std::setw(9) << "seconds" << "file\n";
  for (std::size_t i = 0; i < n; ++i) {
    const nlohmann::json& e = manifest["levels"][i];
    std::cout << std::left << std::setw(static_cast<int>(width)) << specs[i].text << std::setw(14) << std::setprecision(6)
              << e["d"].get<double>() << std::setw(11) << to_string(set.levels[i].status) << std::setw(10)
              << e["faces"].get<std::size_t>() << std::setw(7) << (e.contains("genus") ? e["genus"].dump() : "-")
              << std::setw(6) << (e.contains("components") ? e["components"].dump() : "-") << std::setw(14)
              << std::setprecision(3) << e["epsilon_over_diagonal"].get<double>() << std::setw(9) << std::fixed
              << std::setprecision(1) << set.levels[i].seconds << std::defaultfloat
              << (e["file"].is_null() ? "-" : e["file"].get<std::string>()) << (set.levels[i].reused ? " (reused)" : "") << "\n";
    if (!e["message"].get<std::string>().empty()) std::cout << "    " << e["message"].get<std::string>() << "\n";
  }
  std::cout << "manifest:        " << manifest_path << " (total " << std::fixed << std::setprecision(1)
            << total.seconds() << " s)\n";
  for (const OffsetSetLevel& level : set.levels)
    if (level.status == OffsetStatus::Failed) {
      std::cerr << "cdbench: error: some levels could not be certified (see the messages above)\n";
      return kExitInvalidMesh;
    }
  return kExitOk;
}

}  // namespace

void register_offset(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<OffsetCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "offset",
      "Certified offset surfaces of a closed mesh at signed distances (negative inside): each level set of the "
      "signed distance is meshed with CGAL's surface mesher and certified: closed, manifold, outward, "
      "self-intersection free; every point of every face within EPS of the level (EPS <= tolerance); no component "
      "of the level set missed. Writes one OFF per level and manifest.json to DIR; a re-run reuses levels already "
      "there. Exits 1 if a level cannot be certified.");
  cmd->add_option("mesh", opt->mesh, "closed input mesh")->required();
  cmd->add_option("--levels", opt->levels,
                  "comma-separated levels: absolute distances (-0.5), percentages of the certified maximum "
                  "penetration (-80%), ranges FROM:TO:STEP (-25%:25%:5%)")
      ->required();
  cmd->add_option("-o,--output", opt->out, "output directory")->required();
  cmd->add_option("--tolerance", opt->tolerance, "band tolerance relative to the bbox diagonal")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 0.5));
  cmd->add_option("--mesher-radius", opt->offset.radius_relative,
                  "largest facet size (surface Delaunay ball radius) relative to the diagonal; smaller gives "
                  "finer meshes everywhere, the tolerance alone refines only where needed")
      ->capture_default_str()
      ->check(CLI::Range(1e-4, 0.5));
  cmd->add_option("--mesher-distance", opt->offset.distance_over_tolerance,
                  "the mesher's first distance bound as a fraction of the tolerance (re-meshes use 0.7x the "
                  "last one); larger gives coarser candidates, whose few faces outside the band are split locally")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 4.0));
  cmd->add_option("--max-penetration-tolerance", opt->max_penetration_tolerance,
                  "width of the max-penetration interval relative to the diagonal")
      ->capture_default_str()
      ->check(CLI::Range(1e-12, 1e-2));
  cmd->add_flag("--parallel-mesher", opt->offset.parallel_mesher,
                "mesh each candidate with CGAL's Mesh_3 on all threads instead of Surface_mesher on one; the offsets "
                "are certified all the same but not reproducible bit for bit");
  cmd->add_flag("--verbose", opt->verbose, "report every attempt and phase of every level on stderr");
  cmd->add_option("--threads", opt->threads, "worker threads (0: all cores)")->capture_default_str()->check(CLI::Range(0, 1024));
  cmd->callback([opt, &exit_code]() { exit_code = run_offset(*opt); });
}

}  // namespace cdbench::cli
