// A hollow sphere for measuring the maximum penetration's search on thin shells
// (doc/performance.md, "What is still slow"): make_icosphere(1, K) and the same sphere scaled by
// RATIO with its faces reversed, as the cavity. A closed solid with one curved wall 1 - RATIO thick,
// whose deepest points form a 2-D plateau along the wall's mid-surface.
//   make_hollow_sphere OUT.off K RATIO   (K in [0, 7], RATIO in (0, 1); e.g. shell.off 3 0.97)
#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "guarded_main.h"
#include "mesh/shapes.h"
#include "mesh/write_mesh.h"

int main(int argc, char** argv) {
  return guarded_main("make_hollow_sphere", [](int argc, char** argv) {
    if (argc != 4) {
      std::fprintf(stderr, "usage: make_hollow_sphere OUT.off K RATIO\n");
      return 2;
    }
    const int k = std::stoi(argv[2]);
    const double ratio = std::stod(argv[3]);
    if (!(ratio > 0.0 && ratio < 1.0) || k < 0 || k > 7)
      throw std::invalid_argument("RATIO must lie in (0, 1) and K in [0, 7]");
    cdbench::TriangleMesh cavity = cdbench::make_icosphere(ratio, k);
    for (auto& f : cavity.faces) std::swap(f[1], f[2]);  // facing into the cavity
    cdbench::write_off(cdbench::merge_meshes(cdbench::make_icosphere(1.0, k), cavity), argv[1]);
    return 0;
  }, argc, argv);
}
