#include "mesh_loading.h"

#include "mesh/read_mesh.h"
#include "util/error.h"
#include "util/timer.h"

namespace cdbench::cli {

LoadedMesh load_mesh(const std::string& path, const ValidateOptions& options) {
  LoadedMesh loaded;
  loaded.path = path;
  Timer t_read;
  const PolygonSoup soup = read_polygon_soup(path);
  loaded.seconds_read = t_read.seconds();
  Timer t_validate;
  loaded.validated = validate_mesh(soup, options);
  loaded.seconds_validate = t_validate.seconds();
  return loaded;
}

}  // namespace cdbench::cli
