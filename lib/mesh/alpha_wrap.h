#pragma once
// Repair of real-world input by CGAL's 3D alpha wrapping: any soup (open, self-intersecting,
// non-manifold) becomes a closed, 2-manifold, self-intersection-free, outward mesh that encloses it
// at distance about `offset`.
#include <cstddef>

#include "core/triangle_mesh.h"

namespace cdbench {

// The finest wrap asked for, as the diagonal over alpha or over the offset (the CLI's ranges of
// --relative-alpha and --relative-offset; an absolute --alpha or --offset finer than these is an
// InputError of alpha_wrap, naming its relative value: --alpha 1e-6 on the unit sphere had not
// finished after a minute when it was stopped).
constexpr double kMaxRelativeAlpha = 1e5;
constexpr double kMaxRelativeOffset = 1e6;

// The largest wrap made unless asked for more: about the largest offset level (offset/level_list.h)
// and the mesh sizes the pipeline is measured on. A wrap's size grows like the input's area over
// alpha squared, so a fine alpha on a large input is refused before the work (estimate) or stopped
// during it (the wrap's own count), instead of running for hours without output.
constexpr std::size_t kMaxWrapFaces = 5'000'000;

// About how many faces a wrap of a surface of this area has, from below: closed inputs' wraps
// measured 1.3-2.7 area / alpha^2 (the lower end at the finest alpha; doc/mesh-intake.md), this is
// 1.2 area / alpha^2. An estimate, not a bound: an open sheet's wrap covers both sides (about
// twice), internal faces of a soup are not wrapped (less).
double estimated_wrap_faces(double area, double alpha);

struct AlphaWrapOptions {
  double alpha = 0.0;   // <= 0: bbox diagonal / relative_alpha
  double offset = 0.0;  // <= 0: bbox diagonal / relative_offset
  double relative_alpha = 100.0;
  double relative_offset = 3000.0;
  // Refused when the estimate is above it, stopped when the wrap passes it (an InputError naming
  // both figures and a coarser --relative-alpha).
  std::size_t max_faces = kMaxWrapFaces;
};

struct AlphaWrapResult {
  TriangleMesh mesh;
  double alpha = 0.0, offset = 0.0, seconds = 0.0;
};

AlphaWrapResult alpha_wrap(const PolygonSoup& soup, const AlphaWrapOptions& options = {});

}  // namespace cdbench
