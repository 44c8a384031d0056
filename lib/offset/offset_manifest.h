#pragma once
// manifest.json of an offsets folder, as read back by a later run that may reuse its levels
// (written by offset_set.cpp). A level is reused only when its key (input SHA-256, distance,
// options, version) matches and its file is intact; a manifest that cannot be read is ignored
// with the reason, never trusted in part.
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "offset/offset_status.h"

namespace cdbench {

struct OffsetManifestEntry {
  std::string key;
  OffsetStatus status = OffsetStatus::Failed;
  std::optional<std::string> file, sha256;  // none: the level was not certified (no mesh written)
  double epsilon = 0.0;                     // NaN when the manifest has none (null)
  std::size_t faces = 0;
  nlohmann::json json;                      // the entry as written (copied into the new manifest)
};

struct PreviousOffsets {
  std::map<std::string, OffsetManifestEntry> by_key;
  std::string ignored_because;  // non-empty: a manifest exists but was ignored (the reason)
};

// A missing file gives no entries and no reason.
PreviousOffsets read_offset_manifest(const std::string& path);

}  // namespace cdbench
