#include "poseset/pose_csv.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "util/error.h"

namespace cdbench {

const char* const kPoseCsvHeader =
    "pose,level,target,r00,r01,r02,r10,r11,r12,r20,r21,r22,tx,ty,tz,dir_x,dir_y,dir_z,clearance_lo,clearance_hi,"
    "status,orientation,direction,raw_clearance_lo,raw_clearance_hi,polish_steps,lambda";

namespace {

void put(std::string& s, double x) {
  char buf[40];
  if (std::isnan(x)) std::snprintf(buf, sizeof buf, "nan");
  else std::snprintf(buf, sizeof buf, "%.17g", x);
  s += buf;
  s += ',';
}

}  // namespace

namespace {
constexpr PoseStatus kStatuses[] = {PoseStatus::Certified,     PoseStatus::NoContact,
                                    PoseStatus::OffsetEmpty,   PoseStatus::OffsetFailed,
                                    PoseStatus::ToleranceNotReached, PoseStatus::PolishStalled,
                                    PoseStatus::Float};
}  // namespace

const char* to_string(PoseStatus s) {
  switch (s) {
    case PoseStatus::Certified: return "certified";
    case PoseStatus::NoContact: return "uncertified:no-contact";
    case PoseStatus::OffsetEmpty: return "uncertified:offset-empty";
    case PoseStatus::OffsetFailed: return "uncertified:offset-failed";
    case PoseStatus::ToleranceNotReached: return "uncertified:tolerance-not-reached";
    case PoseStatus::PolishStalled: return "uncertified:polish-stalled";
    case PoseStatus::Float: return "uncertified:float";
  }
  return "?";
}

PoseStatus parse_pose_status(const std::string& text, const std::string& where) {
  std::string known;
  for (PoseStatus s : kStatuses) {
    if (text == to_string(s)) return s;
    known += (known.empty() ? "" : ", ") + std::string(to_string(s));
  }
  throw InputError(where + ": unknown status '" + text + "' (expected one of: " + known + ")");
}

std::string format_pose_row(const PoseRow& r) {
  std::string s = std::to_string(r.pose) + "," + std::to_string(r.level) + ",";
  put(s, r.target);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) put(s, r.R(i, j));
  for (int i = 0; i < 3; ++i) put(s, r.t[i]);
  for (int i = 0; i < 3; ++i) put(s, r.dir[i]);
  put(s, r.clearance_lo);
  put(s, r.clearance_hi);
  s += std::string(to_string(r.status)) + "," + std::to_string(r.orientation) + "," + std::to_string(r.direction) + ",";
  put(s, r.raw_clearance_lo);
  put(s, r.raw_clearance_hi);
  s += std::to_string(r.polish_steps) + ",";
  put(s, r.lambda);
  s.back() = '\n';
  return s;
}

PoseRow parse_pose_row(const std::string& line, const std::string& where) {
  std::vector<std::string> f;
  std::string cur;
  for (char c : line) {
    if (c == ',') {
      f.push_back(cur);
      cur.clear();
    } else if (c != '\r' && c != '\n') {
      cur += c;
    }
  }
  f.push_back(cur);
  if (f.size() != static_cast<std::size_t>(kPoseCsvColumns))
    throw InputError(where + ": expected " + std::to_string(kPoseCsvColumns) + " columns, found " + std::to_string(f.size()));
  const auto num = [&](int k) {
    const char* s = f[k].c_str();
    char* end = nullptr;
    errno = 0;
    const double x = std::strtod(s, &end);
    if (end == s || *end != '\0') throw InputError(where + ": column " + std::to_string(k + 1) + " is not a number: '" + f[k] + "'");
    return x;
  };
  const auto integer = [&](int k) {
    const char* s = f[k].c_str();
    char* end = nullptr;
    const unsigned long long x = std::strtoull(s, &end, 10);
    if (end == s || *end != '\0' || f[k][0] == '-')
      throw InputError(where + ": column " + std::to_string(k + 1) + " is not a non-negative integer: '" + f[k] + "'");
    return static_cast<std::uint64_t>(x);
  };
  PoseRow r;
  r.pose = integer(0);
  r.level = static_cast<int>(integer(1));
  r.target = num(2);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.R(i, j) = num(3 + 3 * i + j);
  for (int i = 0; i < 3; ++i) r.t[i] = num(12 + i);
  for (int i = 0; i < 3; ++i) r.dir[i] = num(15 + i);
  r.clearance_lo = num(18);
  r.clearance_hi = num(19);
  r.status = parse_pose_status(f[20], where);
  r.orientation = integer(21);
  r.direction = integer(22);
  r.raw_clearance_lo = num(23);
  r.raw_clearance_hi = num(24);
  r.polish_steps = static_cast<int>(integer(25));
  r.lambda = num(26);
  return r;
}

std::vector<PoseRow> read_pose_csv(std::istream& in, const std::string& name) {
  std::string line;
  if (!std::getline(in, line)) throw InputError(name + ": empty file (no header)");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line.rfind("pose,level,target,r00,r01,r02,r10,r11,r12,r20,r21,r22,tx,ty,tz,dir_x,dir_y,dir_z,clearance_lo,clearance_hi,status", 0) != 0)
    throw InputError(name + ": line 1 is not a poses.csv header");
  std::vector<PoseRow> rows;
  std::size_t n = 1;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty()) continue;
    rows.push_back(parse_pose_row(line, name + ":" + std::to_string(n)));
  }
  return rows;
}

}  // namespace cdbench
