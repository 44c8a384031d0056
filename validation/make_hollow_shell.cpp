// Hollow solids for measuring the maximum penetration's search on thin walls (doc/distance.md,
// "Cubes across a thin wall"; doc/performance.md, "What is still slow"): a solid and a smaller copy
// with its faces reversed, as the cavity.
//   make_hollow_shell OUT.off sphere K RATIO    make_icosphere(1, K) and the same scaled by RATIO:
//       one curved wall 1 - RATIO thick (K in [0, 7], RATIO in (0, 1); e.g. shell.off sphere 3 0.97)
//   make_hollow_shell OUT.off box X Y Z WALL    the box [0, X] x [0, Y] x [0, Z] and the box WALL
//       inside it: a housing with flat walls WALL thick, deepest at the inner corners,
//       WALL sqrt(3) / (1 + sqrt(3)) deep (e.g. housing.off box 200 100 50 1)
//   make_hollow_shell OUT.off tube R_IN R_OUT LENGTH N    make_tube: an open-ended tube of N
//       facets, its wall R_OUT - R_IN thick (e.g. tube.off tube 0.98 1 4 64)
//   make_hollow_shell OUT.off torus R A RATIO NU NV    make_torus(R, A, NU, NV) and the same with
//       minor radius RATIO A: a ring-shaped shell, its wall curved both ways (e.g. ring.off torus 2
//       0.5 0.98 200 24)
//   make_hollow_shell OUT.off knot P Q R S A RATIO NU NV    a tube of radius A about the (P, Q) torus
//       knot ((R + S cos Qt) cos Pt, (R + S cos Qt) sin Pt, S sin Qt), NU rings of NV vertices on
//       parallel-transported frames, and the same with radius RATIO A as its cavity: a knotted
//       shell (e.g. trefoil.off knot 2 3 2 0.8 0.25 0.96 400 12)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include <array>
#include <vector>

#include "guarded_main.h"
#include "mesh/shapes.h"
#include "mesh/write_mesh.h"

namespace {

// The tube of radius a about the (p, q) torus knot, outward (see the header).
cdbench::TriangleMesh knot_tube(int p, int q, double R, double S, double a, int nu, int nv) {
  using cdbench::Vec3;
  const double pi = std::acos(-1.0);
  std::vector<Vec3> centre(nu), tangent(nu), normal(nu);
  for (int i = 0; i < nu; ++i) {
    const double t = 2 * pi * i / nu;
    centre[i] = Vec3((R + S * std::cos(q * t)) * std::cos(p * t), (R + S * std::cos(q * t)) * std::sin(p * t),
                     S * std::sin(q * t));
  }
  for (int i = 0; i < nu; ++i) tangent[i] = (centre[(i + 1) % nu] - centre[(i + nu - 1) % nu]).normalized();
  normal[0] = tangent[0].cross(Vec3(0.3, 0.5, 0.8)).normalized();
  for (int i = 1; i < nu; ++i)  // parallel transport: the previous normal made normal to the tangent
    normal[i] = (normal[i - 1] - normal[i - 1].dot(tangent[i]) * tangent[i]).normalized();
  // The frame's twist after one turn, spread along the knot so that it closes.
  const Vec3 last = (normal[nu - 1] - normal[nu - 1].dot(tangent[0]) * tangent[0]).normalized();
  const double twist = std::atan2(last.dot(tangent[0].cross(normal[0])), last.dot(normal[0]));
  cdbench::TriangleMesh m;
  for (int i = 0; i < nu; ++i) {
    const Vec3 b = tangent[i].cross(normal[i]);
    for (int j = 0; j < nv; ++j) {
      const double th = 2 * pi * j / nv - twist * i / nu;
      m.vertices.push_back(centre[i] + a * (std::cos(th) * normal[i] + std::sin(th) * b));
    }
  }
  const auto id = [&](int i, int j) { return static_cast<std::uint32_t>((i % nu) * nv + j % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      m.faces.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
      m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
    }
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  return guarded_main("make_hollow_shell", [](int argc, char** argv) {
    const std::string kind = argc > 2 ? argv[2] : "";
    if (!((kind == "sphere" && argc == 5) || (kind == "box" && argc == 7) || (kind == "tube" && argc == 7) ||
          (kind == "torus" && argc == 8) || (kind == "knot" && argc == 11))) {
      std::fprintf(stderr, "usage: make_hollow_shell OUT.off sphere K RATIO\n"
                           "       make_hollow_shell OUT.off box X Y Z WALL\n"
                           "       make_hollow_shell OUT.off tube R_IN R_OUT LENGTH N\n"
                           "       make_hollow_shell OUT.off torus R A RATIO NU NV\n"
                           "       make_hollow_shell OUT.off knot P Q R S A RATIO NU NV\n");
      return 2;
    }
    if (kind == "tube") {
      const double r_in = std::stod(argv[3]), r_out = std::stod(argv[4]), length = std::stod(argv[5]);
      const int n = std::stoi(argv[6]);
      if (!(r_in > 0.0 && r_in < r_out && length > 0.0 && std::isfinite(r_out) && std::isfinite(length)) ||
          n < 3 || n > 1000000)
        throw std::invalid_argument("need 0 < R_IN < R_OUT, LENGTH > 0 and N in [3, 1000000]");
      cdbench::write_off(cdbench::make_tube(r_in, r_out, length, n), argv[1]);
      return 0;
    }
    cdbench::TriangleMesh solid, cavity;
    if (kind == "knot") {
      const int p = std::stoi(argv[3]), q = std::stoi(argv[4]);
      const double major = std::stod(argv[5]), s = std::stod(argv[6]), a = std::stod(argv[7]),
                   ratio = std::stod(argv[8]);
      const int nu = std::stoi(argv[9]), nv = std::stoi(argv[10]);
      if (p < 1 || q < 0 || p > 100 || q > 100 || !(s >= 0.0 && s < major && std::isfinite(major)) || !(a > 0.0) ||
          !(ratio > 0.0 && ratio < 1.0) || nu < 3 || nv < 3 || nu > 1000000 || nv > 1000)
        throw std::invalid_argument("need P >= 1, Q >= 0, 0 <= S < R, A > 0, RATIO in (0, 1), NU, NV >= 3");
      solid = knot_tube(p, q, major, s, a, nu, nv);
      cavity = knot_tube(p, q, major, s, ratio * a, nu, nv);
    } else if (kind == "torus") {
      const double major = std::stod(argv[3]), minor = std::stod(argv[4]), ratio = std::stod(argv[5]);
      const int nu = std::stoi(argv[6]), nv = std::stoi(argv[7]);
      if (!(minor > 0.0 && minor < major && std::isfinite(major)) || !(ratio > 0.0 && ratio < 1.0) || nu < 3 ||
          nv < 3 || nu > 100000 || nv > 100000)
        throw std::invalid_argument("need 0 < A < R, RATIO in (0, 1) and NU, NV in [3, 100000]");
      solid = cdbench::make_torus(major, minor, nu, nv);
      cavity = cdbench::make_torus(major, ratio * minor, nu, nv);
    } else if (kind == "sphere") {
      const int k = std::stoi(argv[3]);
      const double ratio = std::stod(argv[4]);
      if (!(ratio > 0.0 && ratio < 1.0) || k < 0 || k > 7)
        throw std::invalid_argument("RATIO must lie in (0, 1) and K in [0, 7]");
      solid = cdbench::make_icosphere(1.0, k);
      cavity = cdbench::make_icosphere(ratio, k);
    } else {
      const cdbench::Vec3 hi(std::stod(argv[3]), std::stod(argv[4]), std::stod(argv[5]));
      const double wall = std::stod(argv[6]);
      if (!(wall > 0.0) || !(2.0 * wall < hi.minCoeff()) || !std::isfinite(hi.maxCoeff()))
        throw std::invalid_argument("WALL must be positive and less than half of X, Y and Z");
      solid = cdbench::make_box(cdbench::Vec3::Zero(), hi);
      cavity = cdbench::make_box(cdbench::Vec3::Constant(wall), hi - cdbench::Vec3::Constant(wall));
    }
    for (auto& f : cavity.faces) std::swap(f[1], f[2]);  // facing into the cavity
    cdbench::write_off(cdbench::merge_meshes(solid, cavity), argv[1]);
    return 0;
  }, argc, argv);
}
