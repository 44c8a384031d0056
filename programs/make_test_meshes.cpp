// Writes the small generated test meshes of data/meshes/ (run: make_test_meshes DIR).
#include <iostream>

#include "mesh/shapes.h"
#include "mesh/write_mesh.h"

int main(int argc, char** argv) {
  using namespace cdbench;
  if (argc != 2) {
    std::cerr << "usage: make_test_meshes DIR\n";
    return 2;
  }
  const std::string dir = argv[1];
  write_off(make_icosphere(1.0, 3), dir + "/sphere.off");
  write_off(make_torus(2.0, 0.5, 64, 32), dir + "/torus.off");
  write_off(make_box(Vec3(0, 0, 0), Vec3(2, 1, 4)), dir + "/box.off");
  write_off(merge_meshes(make_icosphere(1.0, 2), make_icosphere(0.5, 2, Vec3(3, 0, 0))), dir + "/two_spheres.off");
  std::cout << "wrote sphere.off torus.off box.off two_spheres.off to " << dir << "\n";
  return 0;
}
