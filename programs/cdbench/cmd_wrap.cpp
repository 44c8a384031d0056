// cdbench wrap IN OUT (CGAL alpha wrapping) and cdbench repair IN OUT (exact union of closed parts,
// else alpha wrapping). Both report the certified two-sided distance between input and output and
// write it beside the output as <OUT without extension>.repair.json.
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "distance/hausdorff.h"
#include "mesh/read_mesh.h"
#include "mesh/repair.h"
#include "mesh/write_mesh.h"
#include "number_text.h"
#include "util/atomic_file.h"
#include "util/error.h"
#include "util/progress.h"
#include "util/sha256.h"

namespace cdbench::cli {
namespace {

struct RepairCliOptions {
  std::string input, output;
  double alpha = 0.0, offset = 0.0;
  double relative_alpha = 100.0, relative_offset = 3000.0;
  double weld_tolerance = 0.0, distance_tolerance = 1e-2;
  std::size_t max_faces = kMaxWrapFaces;
  bool wrap_only = false, no_wrap = false;
};

nlohmann::json to_json(const HausdorffResult& h) {
  return {{"lo", h.distance.lo},      {"hi", h.distance.hi},   {"witness", {h.witness.x(), h.witness.y(), h.witness.z()}},
          {"converged", h.converged}, {"cells", h.cells},      {"seconds", h.seconds}};
}

std::string json_path_for(const std::string& output) {
  const std::size_t dot = output.find_last_of('.');
  const std::size_t slash = output.find_last_of('/');
  const bool has_ext = dot != std::string::npos && (slash == std::string::npos || dot > slash);
  return (has_ext ? output.substr(0, dot) : output) + ".repair.json";
}

int run_repair(const RepairCliOptions& opt, const char* command) {
  if (mesh_format_from_path(opt.output) != MeshFormat::Off)
    throw InputError(opt.output + ": the output must be an .off file");
  check_output_path(opt.output);
  check_output_path(json_path_for(opt.output));
  const PolygonSoup soup = read_polygon_soup(opt.input);
  RepairOptions ro;
  ro.weld_tolerance = opt.weld_tolerance;
  ro.allow_wrap = !opt.no_wrap;
  ro.wrap = {opt.alpha, opt.offset, opt.relative_alpha, opt.relative_offset, opt.max_faces};
  if (Progress::enabled()) std::cerr << command << " " << opt.input << " (may take a while)...\n";
  RepairResult r;
  if (opt.wrap_only) {
    const AlphaWrapResult w = alpha_wrap(soup, ro.wrap);
    r.method = RepairMethod::AlphaWrap;
    r.alpha = w.alpha;
    r.offset = w.offset;
    r.seconds = w.seconds;
    r.result = validate_mesh(w.mesh);
  } else {
    r = repair_mesh(soup, ro);
  }
  std::cout << "input:    " << opt.input << ": " << soup.points.size() << " vertices, " << soup.polygons.size()
            << " polygons" << (r.input_report.errors.empty() ? "" : " (not a valid solid)") << "\n";
  for (const auto& e : r.input_report.errors) std::cout << "problem:  " << e.message << "\n";
  std::cout << "method:   " << to_string(r.method);
  if (r.method == RepairMethod::ExactUnion) std::cout << " of " << r.parts << " closed parts (CGAL corefinement)";
  if (r.method == RepairMethod::AlphaWrap) std::cout << ", alpha " << number_text(r.alpha) << ", offset " << number_text(r.offset);
  std::cout << std::fixed << std::setprecision(2) << " (" << r.seconds << " s)\n" << std::defaultfloat;
  if (!r.exact_note.empty()) std::cout << "note:     exact union not used: " << r.exact_note << "\n";
  if (!r.result.report.valid()) {
    for (const auto& e : r.result.report.errors) std::cerr << "cdbench: result invalid: " << e.message << "\n";
    if (opt.no_wrap) {
      std::cerr << "cdbench: error: no exact repair found and --no-wrap was given; nothing written\n";
      return kExitInvalidMesh;
    }
    return kExitInternal;  // alpha wrapping guarantees validity: this would be a bug
  }
  const TriangleMesh& out = r.result.mesh;
  std::cout << "output:   " << opt.output << ": " << out.vertices.size() << " vertices, " << out.faces.size()
            << " triangles, genus " << r.result.report.genus << ", " << r.result.report.components << " component(s)\n";

  HausdorffOptions ho;
  ho.relative_tolerance = opt.distance_tolerance;
  if (Progress::enabled()) std::cerr << "certifying the distance between input and output...\n";
  const SurfaceDeviation d = two_sided_hausdorff(fan_triangulation(soup), out, ho);
  std::cout << "distance: input -> output in [" << number_text(d.first_to_second.distance.lo) << ", "
            << number_text(d.first_to_second.distance.hi) << "] (every input point is within the upper end of the output)\n";
  std::cout << "distance: output -> input in [" << number_text(d.second_to_first.distance.lo) << ", "
            << number_text(d.second_to_first.distance.hi) << "] (every output point is within the upper end of the input)\n";
  if (!d.first_to_second.converged || !d.second_to_first.converged)
    std::cout << "note:     the distance search hit its work limit: the intervals are valid but wider\n";

  const std::string json_path = json_path_for(opt.output);
  nlohmann::json j = {{"command", command},
                      {"input", opt.input},
                      {"input_sha256", sha256_file(opt.input)},
                      {"output", opt.output},
                      {"method", to_string(r.method)},
                      {"input_problems", nlohmann::json::array()},
                      {"output_vertices", out.vertices.size()},
                      {"output_triangles", out.faces.size()},
                      {"output_genus", r.result.report.genus},
                      {"weld_tolerance", opt.weld_tolerance},
                      {"distance_relative_tolerance", opt.distance_tolerance},
                      {"input_to_output", to_json(d.first_to_second)},
                      {"output_to_input", to_json(d.second_to_first)},
                      {"hausdorff", {{"lo", std::max(d.first_to_second.distance.lo, d.second_to_first.distance.lo)},
                                     {"hi", std::max(d.first_to_second.distance.hi, d.second_to_first.distance.hi)}}},
                      {"seconds_repair", r.seconds}};
  for (const auto& e : r.input_report.errors) j["input_problems"].push_back(e.message);
  if (r.method == RepairMethod::AlphaWrap) j["alpha_wrap"] = {{"alpha", r.alpha}, {"offset", r.offset}};
  if (r.method == RepairMethod::ExactUnion) j["parts"] = r.parts;
  if (!r.exact_note.empty()) j["exact_union_not_used"] = r.exact_note;
  write_off(out, opt.output);
  write_file_atomically(json_path, [&](std::ostream& os) { os << j.dump(2) << "\n"; });
  std::cout << "written:  " << opt.output << ", " << json_path << "\n";
  return kExitOk;
}

void add_common(CLI::App* cmd, RepairCliOptions& o) {
  cmd->add_option("input", o.input, "input mesh (OFF, OBJ, PLY, STL)")->required();
  cmd->add_option("output", o.output, "output mesh (.off), written atomically; the distance report goes to "
                                       "<output without extension>.repair.json")
      ->required();
  cmd->add_option("--alpha", o.alpha, "absolute alpha (default: bbox diagonal / --relative-alpha)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--offset", o.offset, "absolute offset (default: bbox diagonal / --relative-offset)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--relative-alpha", o.relative_alpha, "diagonal / alpha when --alpha is not given")
      ->capture_default_str()
      ->check(CLI::Range(1.0, kMaxRelativeAlpha));
  cmd->add_option("--relative-offset", o.relative_offset, "diagonal / offset when --offset is not given")
      ->capture_default_str()
      ->check(CLI::Range(1.0, kMaxRelativeOffset));
  cmd->add_option("--max-faces", o.max_faces,
                  "the largest wrap: refused before the work when its size, estimated from the input's area and "
                  "alpha, is larger; stopped when its Steiner points pass it")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--distance-tolerance", o.distance_tolerance,
                  "relative width of the certified distance intervals (hi - lo <= tolerance x lo)")
      ->capture_default_str()
      ->check(CLI::Range(1e-9, 1.0));
}

}  // namespace

void register_wrap(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<RepairCliOptions>();
  opt->wrap_only = true;
  CLI::App* cmd = app.add_subcommand(
      "wrap",
      "Repair any input (polygon soup, open or self-intersecting surface) with CGAL's 3D alpha wrapping into a "
      "closed, 2-manifold, self-intersection-free, outward-oriented mesh that passes 'cdbench check'. The output "
      "encloses the input at distance about OFFSET; ALPHA bounds the size of the features that are filled. The "
      "certified distance between input and output (both directions) is printed and written to "
      "<output>.repair.json. See also 'cdbench repair', which keeps the geometry exactly when it can.");
  add_common(cmd, *opt);
  cmd->callback([opt, &exit_code]() { exit_code = run_repair(*opt, "wrap"); });
}

void register_repair(CLI::App& app, int& exit_code) {
  auto opt = std::make_shared<RepairCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "repair",
      "Make a valid closed solid of IN, keeping its geometry when possible: vertices with equal coordinates are "
      "welded; a valid result is written unchanged; an input made of closed parts that overlap or touch is "
      "replaced by their exact union (CGAL corefinement, exact kernel); anything else is alpha-wrapped as by "
      "'cdbench wrap'. The certified distance between input and output (both directions) is printed and written "
      "to <output>.repair.json.");
  add_common(cmd, *opt);
  cmd->add_option("--weld-tolerance", opt->weld_tolerance,
                  "also weld vertices closer than this (moves them; reported). Exactly equal ones are always welded")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--no-wrap", opt->no_wrap, "never alpha-wrap: fail (exit 1) when no exact repair exists");
  cmd->callback([opt, &exit_code]() { exit_code = run_repair(*opt, "repair"); });
}

}  // namespace cdbench::cli
