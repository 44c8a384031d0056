// Independent check of the distance report of `cdbench wrap` / `cdbench repair`:
//   check_repair INPUT OUTPUT.off OUTPUT.repair.json [error_bound_relative]
// recomputes both one-sided Hausdorff distances with CGAL's bounded_error_Hausdorff_distance
// (another algorithm, in doubles, error bound e) and checks that each lies within e of the
// certified interval in the JSON. Prints a table; exits 1 on any disagreement.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "mesh/read_mesh.h"
#include "guarded_main.h"

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;

// The soup as a CGAL mesh with the same triangles (fanned like cdbench does; non-manifold
// vertices are duplicated by orient_polygon_soup, which moves nothing).
Mesh to_cgal(const cdbench::PolygonSoup& soup) {
  std::vector<Kernel::Point_3> points;
  for (const auto& p : soup.points) points.emplace_back(p.x(), p.y(), p.z());
  std::vector<std::vector<std::size_t>> tris;
  for (const auto& poly : soup.polygons)
    for (std::size_t k = 1; k + 1 < poly.size(); ++k) tris.push_back({poly[0], poly[k], poly[k + 1]});
  PMP::orient_polygon_soup(points, tris);
  Mesh m;
  PMP::polygon_soup_to_polygon_mesh(points, tris, m);
  return m;
}

static int run(int argc, char** argv) {
  if (argc < 4) {
    std::cerr << "usage: check_repair INPUT OUTPUT.off OUTPUT.repair.json [relative error bound, default 1e-4]\n";
    return 2;
  }
  const double rel = argc > 4 ? std::atof(argv[4]) : 1e-4;
  const Mesh in = to_cgal(cdbench::read_polygon_soup(argv[1]));
  const Mesh out = to_cgal(cdbench::read_polygon_soup(argv[2]));
  std::ifstream js(argv[3]);
  const nlohmann::json j = nlohmann::json::parse(js);
  const auto box = CGAL::Polygon_mesh_processing::bbox(in);
  const double diag = std::sqrt(CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                                CGAL::square(box.zmax() - box.zmin()));
  const double e = rel * diag;
  int bad = 0;
  std::printf("%-16s %22s %22s %22s %8s %s\n", "direction", "certified lo", "certified hi", "CGAL (+-e)", "CGAL s", "agree");
  for (const char* key : {"input_to_output", "output_to_input"}) {
    const bool forward = std::string(key) == "input_to_output";
    const auto t0 = std::chrono::steady_clock::now();
    const double h = PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(forward ? in : out,
                                                                                            forward ? out : in, e);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double lo = j[key]["lo"], hi = j[key]["hi"];
    const bool ok = h >= lo - e && h <= hi + e;
    bad += !ok;
    std::printf("%-16s %22.17g %22.17g %22.17g %8.2f %s\n", key, lo, hi, h, s, ok ? "yes" : "NO");
  }
  std::printf("error bound e = %.3g (%.0e x input diagonal)\n", e, rel);
  return bad ? 1 : 0;
}

int main(int argc, char** argv) { return guarded_main("check_repair", run, argc, argv); }
