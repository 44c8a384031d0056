#include "offset/offset_manifest.h"

#include <filesystem>

#include "util/error.h"
#include "util/json_keys.h"

namespace cdbench {

PreviousOffsets read_offset_manifest(const std::string& path) {
  PreviousOffsets out;
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return out;
  try {
    const nlohmann::json doc = parse_json_file(path, "");
    const JsonKeys k(path);
    const nlohmann::json& levels = k.array(doc, "levels", "");
    for (std::size_t i = 0; i < levels.size(); ++i) {
      const std::string where = "levels[" + std::to_string(i) + "].";
      OffsetManifestEntry e;
      e.key = k.text(levels[i], "key", where);
      // What a reusing run reads or prints of the entry must have its type.
      k.number(levels[i], "d", where);
      k.text(levels[i], "message", where);
      e.epsilon = k.number(levels[i], "epsilon", where, true);
      k.number(levels[i], "epsilon_over_diagonal", where, true);
      e.faces = k.count(levels[i], "faces", where);
      if (!offset_status_from_string(k.text(levels[i], "status", where), &e.status))
        k.fail(where + "status", "is not certified, empty, original or failed");
      const nlohmann::json& file = k.at(levels[i], "file", where);
      if ((e.status == OffsetStatus::Certified) != !file.is_null()) k.fail(where + "file", "does not match the status");
      if (!file.is_null()) {
        e.file = k.text(levels[i], "file", where);
        e.sha256 = k.text(levels[i], "sha256", where);
        // The file must be a plain name inside the folder, as we write it.
        if (e.file->empty() || e.file->find('/') != std::string::npos || *e.file == "." || *e.file == "..")
          k.fail(where + "file", "is not a file name inside the offsets folder");
      }
      e.json = levels[i];
      out.by_key[e.key] = std::move(e);
    }
  } catch (const InputError& e) {
    out.by_key.clear();
    out.ignored_because = e.what();
  }
  return out;
}

}  // namespace cdbench
