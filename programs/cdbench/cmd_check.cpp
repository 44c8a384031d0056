// cdbench check MESH: validation verdict, statistics and the certified maximum penetration.
#include <tbb/global_control.h>

#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>

#include "commands.h"
#include "distance/max_penetration.h"
#include "mesh_loading.h"
#include "number_text.h"
#include "util/timer.h"

namespace cdbench::cli {
namespace {

struct CheckOptions {
  std::string mesh;
  bool json = false;
  bool skip_max_penetration = false;
  double tolerance = 1e-6;
  double weld_tolerance = 0.0;
  int threads = 0;
};

std::string vec(const Vec3& v, int digits = 17) {
  return "(" + number_text(v.x(), digits) + ", " + number_text(v.y(), digits) + ", " + number_text(v.z(), digits) + ")";
}

// What one check found, for the two printers below.
struct CheckFindings {
  const LoadedMesh& loaded;
  bool run_mp = false;
  MaxPenetrationResult mp;
  double seconds_tree = 0.0;
  const MeshReport& report() const { return loaded.validated.report; }
  const TriangleMesh& mesh() const { return loaded.validated.mesh; }
};

void print_json(const CheckOptions& opt, const CheckFindings& f) {
  const MeshReport& r = f.report();
  const Aabb box = f.mesh().bbox();
  const double diag = box.diagonal();
  nlohmann::json j;
  j["mesh"] = opt.mesh;
  j["input"] = {{"vertices", r.input_vertices}, {"polygons", r.input_polygons}};
  j["vertices"] = f.mesh().vertices.size();
  j["faces"] = f.mesh().faces.size();
  j["bbox"] = {{"min", {box.lo.x(), box.lo.y(), box.lo.z()}}, {"max", {box.hi.x(), box.hi.y(), box.hi.z()}}};
  j["diagonal"] = diag;
  j["closed"] = r.closed;
  j["components"] = r.components;
  j["genus"] = r.genus >= 0 ? nlohmann::json(r.genus) : nlohmann::json(nullptr);
  j["volume"] = r.valid() ? nlohmann::json({r.volume_lo, r.volume_hi}) : nlohmann::json(nullptr);
  j["self_intersections_checked"] = r.self_intersections_checked;
  j["valid"] = r.valid();
  j["errors"] = nlohmann::json::array();
  for (const auto& e : r.errors) j["errors"].push_back({{"kind", e.kind}, {"count", e.count}, {"message", e.message}});
  j["notices"] = r.notices;
  if (f.run_mp) {
    j["max_penetration"] = {{"interval", {f.mp.depth.lo, f.mp.depth.hi}},
                            {"fraction_of_diagonal", {f.mp.depth.lo / diag, f.mp.depth.hi / diag}},
                            {"point", {f.mp.point.x(), f.mp.point.y(), f.mp.point.z()}},
                            {"relative_tolerance", opt.tolerance},
                            {"tolerance_reached", f.mp.tolerance_reached},
                            {"cells", f.mp.cells},
                            {"full_distance_queries", f.mp.full_queries},
                            {"side_queries", f.mp.side_queries},
                            {"levels", f.mp.levels}};
  }
  j["timings_s"] = {{"read", f.loaded.seconds_read},
                    {"validate", f.loaded.seconds_validate},
                    {"self_intersections", r.seconds_self_intersections},
                    {"distance_tree", f.seconds_tree},
                    {"max_penetration", f.mp.seconds}};
  std::cout << std::setw(2) << j << "\n";
}

void print_text(const CheckOptions& opt, const CheckFindings& f) {
  const MeshReport& r = f.report();
  const TriangleMesh& mesh = f.mesh();
  const Aabb box = mesh.bbox();
  const double diag = box.diagonal();
  const MaxPenetrationResult& mp = f.mp;
  std::cout << "mesh:               " << opt.mesh << "\n";
  std::cout << "input:              " << r.input_vertices << " vertices, " << r.input_polygons << " polygons\n";
  std::cout << "mesh:               " << mesh.vertices.size() << " vertices, " << mesh.faces.size() << " triangles\n";
  std::cout << "bbox:               " << vec(box.lo, 9) << " - " << vec(box.hi, 9) << ", diagonal " << number_text(diag, 9)
            << "\n";
  std::cout << "topology:           " << (r.closed ? "closed" : "open") << ", " << r.components
            << (r.components == 1 ? " component" : " components");
  if (r.genus >= 0) std::cout << ", genus " << r.genus;
  std::cout << "\n";
  if (r.valid())
    std::cout << "volume:             " << number_text(0.5 * (r.volume_lo + r.volume_hi), 12) << " (certified in ["
              << number_text(r.volume_lo) << ", " << number_text(r.volume_hi) << "])\n";
  std::cout << "self-intersections: "
            << (r.self_intersections_checked ? (r.has("self-intersection") ? "found (exact test)" : "none (exact test)")
                                             : "not checked")
            << "\n";
  for (const auto& n : r.notices) std::cout << "notice:             " << n << "\n";
  for (const auto& e : r.errors) std::cout << "error:              " << e.message << "\n";
  std::cout << "verdict:            " << (r.valid() ? "valid closed solid" : "INVALID") << "\n";
  if (f.run_mp) {
    std::cout << "max penetration:    [" << number_text(mp.depth.lo) << ", " << number_text(mp.depth.hi) << "] = ["
              << number_text(100 * mp.depth.lo / diag, 9) << "%, " << number_text(100 * mp.depth.hi / diag, 9)
              << "%] of the diagonal, width " << number_text(mp.depth.width() / diag, 3) << " x diagonal"
              << (mp.tolerance_reached ? "" : " (TOLERANCE NOT REACHED)") << "\n";
    std::cout << "deepest point:      " << vec(mp.point) << "\n";
    std::cout << "branch and bound:   " << mp.cells << " cells, " << mp.full_queries << " full distance queries, "
              << mp.side_queries << " exact side tests, " << mp.levels << " levels\n";
    if (!mp.tolerance_reached)
      std::cout << "note:               the interval is certified, but wider than --tolerance "
                << number_text(opt.tolerance, 3) << ": the search stopped at its memory bound (a plateau\n"
                << "                    of deepest points can need many cells); --tolerance "
                << number_text(2 * mp.depth.width() / diag, 1) << " needs far fewer\n";
  }
  std::cout << std::fixed << std::setprecision(3) << "timings (s):        read " << f.loaded.seconds_read
            << ", validate " << f.loaded.seconds_validate << " (self-intersections " << r.seconds_self_intersections
            << "), distance tree " << f.seconds_tree << ", max penetration " << mp.seconds << "\n";
}

int run_check(const CheckOptions& opt) {
  std::unique_ptr<tbb::global_control> threads;
  if (opt.threads > 0)
    threads = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, opt.threads);
  ValidateOptions vo;
  vo.weld_tolerance = opt.weld_tolerance;
  const LoadedMesh loaded = load_mesh(opt.mesh, vo);
  CheckFindings f{loaded, false, {}, 0.0};
  f.run_mp = !opt.skip_max_penetration && loaded.validated.report.valid();
  if (f.run_mp) {
    Timer t_tree;
    const SignedDistance sdf(loaded.validated.mesh);
    f.seconds_tree = t_tree.seconds();
    MaxPenetrationOptions mo;
    mo.relative_tolerance = opt.tolerance;
    f.mp = certified_max_penetration(sdf, mo);
  }
  if (opt.json)
    print_json(opt, f);
  else
    print_text(opt, f);
  return loaded.validated.report.valid() ? kExitOk : kExitInvalidMesh;
}

}  // namespace

void register_check(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<CheckOptions>();
  CLI::App* cmd = app.add_subcommand(
      "check",
      "Read a mesh (OFF, OBJ, PLY, STL), validate it as a closed solid and report its statistics and certified "
      "maximum penetration (the radius of the largest inscribed ball). Exits 1 when the mesh is not a valid closed "
      "solid, 2 when the file cannot be read.");
  cmd->add_option("mesh", opt->mesh, "mesh file")->required();
  cmd->add_flag("--json", opt->json, "print a JSON report instead of text");
  cmd->add_option("--tolerance", opt->tolerance,
                  "width of the max-penetration interval relative to the bbox diagonal")
      ->capture_default_str()
      ->check(CLI::Range(1e-12, 1.0));
  cmd->add_option("--weld-tolerance", opt->weld_tolerance,
                  "also merge vertices closer than this (moves them; reported). Vertices with exactly equal "
                  "coordinates are always merged. 'cdbench repair --weld-tolerance' writes the welded mesh")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--no-max-penetration", opt->skip_max_penetration, "skip the max-penetration computation");
  cmd->add_option("--threads", opt->threads, "worker threads (0: all cores)")->capture_default_str()->check(CLI::Range(0, 1024));
  cmd->callback([opt, &exit_code]() { exit_code = run_check(*opt); });
}

}  // namespace cdbench::cli
