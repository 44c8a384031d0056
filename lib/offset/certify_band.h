#pragma once
// Certificate (b) of an offset mesh S_d: a rigorous band eps such that every point of every face of
// S_d has signed distance to the original surface F within [d - eps, d + eps].
#include <cstddef>
#include <vector>

#include "distance/signed_distance.h"

namespace cdbench {

struct BandOptions {
  double target = 0.0;     // stop splitting a face once its half-width is at most this
  int max_split_depth = 4; // a face is split into at most 4^depth pieces for its upper bound
  // Faces whose half-width exceeds this get a second, deeper pass (max_split_depth + 2, target/2)
  // when they are few (at most 200 or 1 %): a loose bound on a few faces should not force a whole
  // re-mesh. 0: no second pass.
  double second_pass_above = 0.0;
};

struct BandResult {
  double epsilon = 0.0;              // max over faces of the certified half-width
  std::vector<double> face_epsilon;  // per face
  std::size_t worst_face = 0;
  std::size_t faces_touching = 0;    // faces not proved disjoint from F (certificate impossible)
  std::size_t pieces = 0;            // sub-triangles evaluated in all
  double seconds = 0.0;
};

// Sets epsilon and worst_face from face_epsilon (the first face of the largest value; 0 and 0 for
// no faces): for bands assembled from several certificates' faces.
void set_band_maximum(BandResult& band);

// d: the level (signed, nonzero). Uses TBB over faces; deterministic.
BandResult certify_band(const SignedDistance& sdf, const TriangleMesh& offset, double d, const BandOptions& options);

}  // namespace cdbench
