#include "mesh/write_mesh.h"

#include "util/atomic_file.h"

namespace cdbench {

void write_off(const TriangleMesh& mesh, std::ostream& out) {
  out.precision(17);
  out << "OFF\n" << mesh.vertices.size() << ' ' << mesh.faces.size() << " 0\n";
  for (const Vec3& v : mesh.vertices) out << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  for (const Face& f : mesh.faces) out << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
}

void write_off(const TriangleMesh& mesh, const std::string& path) {
  write_file_atomically(path, [&](std::ostream& out) { write_off(mesh, out); });
}

}  // namespace cdbench
