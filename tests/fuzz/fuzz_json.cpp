// The JSON readers: poseset.json (and the poses.csv beside it), an offsets folder's manifest.json
// (read back for reuse) and a bench summary.json (read by plot). First byte: which file.
#include <filesystem>

#include "fuzz_support.h"
#include "offset/offset_manifest.h"
#include "poseset/poseset_manifest.h"
#include "score/scoring.h"
#include "util/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string bytes = cdbench::fuzz::payload(data, size);
  try {
    switch (data[0] % 3) {
      case 0: {
        const std::string dir = cdbench::fuzz::scratch_dir();
        cdbench::fuzz::write_scratch("poseset.json", bytes);
        cdbench::fuzz::write_scratch("poses.csv", std::string(cdbench::kPoseCsvHeader) + "\n");
        const cdbench::PoseSetManifest m = cdbench::read_poseset_manifest(dir);
        cdbench::read_poseset_rows(m);
        break;
      }
      case 1: {
        const cdbench::PreviousOffsets p = cdbench::read_offset_manifest(cdbench::fuzz::write_scratch("manifest.json", bytes));
        for (const auto& [key, e] : p.by_key)
          if (e.key != key || e.file.has_value() != e.sha256.has_value()) std::abort();
        break;
      }
      default:
        cdbench::read_bench_summary(cdbench::fuzz::write_scratch("summary.json", bytes));
        break;
    }
  } catch (const cdbench::InputError&) {
  }
  return 0;
}
