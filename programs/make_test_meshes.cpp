// Writes the small generated test meshes of data/meshes/ (run: make_test_meshes DIR).
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>

#include "mesh/shapes.h"
#include "mesh/write_mesh.h"

int main(int argc, char** argv) {
  using namespace cdbench;
  const char* usage = "usage: make_test_meshes DIR\n  writes sphere.off, torus.off, box.off and two_spheres.off into DIR (made if missing)\n";
  if (argc == 2 && (std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0)) {
    std::cout << usage;
    return 0;
  }
  if (argc != 2) {
    std::cerr << usage;
    return 2;
  }
  const std::string dir = argv[1];
  try {
    std::filesystem::create_directories(dir);  // as `cdbench ... -o DIR` does
    write_off(make_icosphere(1.0, 3), dir + "/sphere.off");
    write_off(make_torus(2.0, 0.5, 64, 32), dir + "/torus.off");
    write_off(make_box(Vec3(0, 0, 0), Vec3(2, 1, 4)), dir + "/box.off");
    write_off(merge_meshes(make_icosphere(1.0, 2), make_icosphere(0.5, 2, Vec3(3, 0, 0))), dir + "/two_spheres.off");
  } catch (const std::exception& e) {
    std::cerr << "make_test_meshes: " << e.what() << "\n";
    return 1;
  }
  std::cout << "wrote sphere.off torus.off box.off two_spheres.off to " << dir << "\n";
  return 0;
}
