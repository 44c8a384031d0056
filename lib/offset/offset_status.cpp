#include "offset/offset_status.h"

namespace cdbench {

const char* to_string(OffsetStatus status) {
  switch (status) {
    case OffsetStatus::Certified: return "certified";
    case OffsetStatus::Empty: return "empty";
    case OffsetStatus::Original: return "original";
    case OffsetStatus::Failed: return "failed";
  }
  return "?";
}

bool offset_status_from_string(const std::string& text, OffsetStatus* status) {
  for (OffsetStatus s : {OffsetStatus::Certified, OffsetStatus::Empty, OffsetStatus::Original, OffsetStatus::Failed})
    if (text == to_string(s)) {
      *status = s;
      return true;
    }
  return false;
}

}  // namespace cdbench
