#include "mesh_loading.h"

#include <iostream>

#include "mesh/read_mesh.h"
#include "util/error.h"
#include "util/timer.h"

namespace cdbench::cli {

LoadedMesh load_mesh(const std::string& path, const ValidateOptions& options) {
  LoadedMesh loaded;
  loaded.path = path;
  Timer t_read;
  PolygonSoup soup = read_polygon_soup(path);
  loaded.seconds_read = t_read.seconds();
  Timer t_validate;
  loaded.validated = validate_mesh(std::move(soup), options);
  loaded.seconds_validate = t_validate.seconds();
  return loaded;
}

bool report_if_not_solid(const LoadedMesh& l) {
  if (l.validated.report.valid()) return true;
  for (const auto& e : l.validated.report.errors) std::cerr << "cdbench: " << l.path << ": " << e.message << "\n";
  std::cerr << "cdbench: error: " << l.path << " is not a valid closed solid (see 'cdbench check'; 'cdbench repair "
            << l.path << " OUT.off' makes one, keeping its geometry when it can)\n";
  return false;
}

bool load_solids(const std::string& fixed_path, const std::string& mover_path, LoadedMesh* fixed, LoadedMesh* mover) {
  *fixed = load_mesh(fixed_path);
  if (!report_if_not_solid(*fixed)) return false;
  if (mover_path.empty()) return true;
  *mover = load_mesh(mover_path);
  return report_if_not_solid(*mover);
}

}  // namespace cdbench::cli
