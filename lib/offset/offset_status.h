#pragma once
// The outcome of an offset level, as the offset driver returns it, manifest.json records it and
// the pose-set builder decides a level's start from it (no geometry: part of cdbench_offset_io).
#include <string>

namespace cdbench {

// Certified: a mesh with its three certificates; Empty: no point of that signed distance exists;
// Original: the input itself, for d = 0 (band 0) or 0 < |d| <= tolerance (band |d|); Failed: no
// candidate could be certified.
enum class OffsetStatus { Certified, Empty, Original, Failed };

const char* to_string(OffsetStatus status);
// The inverse of to_string (manifests read back); false for any other text.
bool offset_status_from_string(const std::string& text, OffsetStatus* status);

}  // namespace cdbench
