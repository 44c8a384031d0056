#pragma once
// Repair of real-world input by CGAL's 3D alpha wrapping: any soup (open, self-intersecting,
// non-manifold) becomes a closed, 2-manifold, self-intersection-free, outward mesh that encloses it
// at distance about `offset`.
#include "core/triangle_mesh.h"

namespace cdbench {

// The finest wrap asked for, as the diagonal over alpha or over the offset (the CLI's ranges of
// --relative-alpha and --relative-offset; an absolute --alpha or --offset finer than these is an
// InputError of alpha_wrap, naming its relative value: --alpha 1e-6 on the unit sphere had not
// finished after a minute when it was stopped).
constexpr double kMaxRelativeAlpha = 1e5;
constexpr double kMaxRelativeOffset = 1e6;

struct AlphaWrapOptions {
  double alpha = 0.0;   // <= 0: bbox diagonal / relative_alpha
  double offset = 0.0;  // <= 0: bbox diagonal / relative_offset
  double relative_alpha = 100.0;
  double relative_offset = 3000.0;
};

struct AlphaWrapResult {
  TriangleMesh mesh;
  double alpha = 0.0, offset = 0.0, seconds = 0.0;
};

AlphaWrapResult alpha_wrap(const PolygonSoup& soup, const AlphaWrapOptions& options = {});

}  // namespace cdbench
