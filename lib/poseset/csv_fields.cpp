#include "poseset/csv_fields.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "util/error.h"

namespace cdbench {

std::vector<std::string> split_csv_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::string cur;
  const auto push = [&] {
    const std::size_t a = cur.find_first_not_of(" \t");
    const std::size_t b = cur.find_last_not_of(" \t");
    fields.push_back(a == std::string::npos ? std::string() : cur.substr(a, b - a + 1));
    cur.clear();
  };
  for (char c : line) {
    if (c == ',') push();
    else if (c != '\r' && c != '\n') cur += c;
  }
  push();
  return fields;
}

bool is_blank_line(const std::string& line) { return line.find_first_not_of(" \t\r") == std::string::npos; }

std::vector<std::string> read_csv_header(std::istream& in, std::size_t* line_no) {
  std::string line;
  while (std::getline(in, line)) {
    ++*line_no;
    if (*line_no == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    if (!is_blank_line(line)) return split_csv_fields(line);
  }
  return {};
}

std::map<std::string, std::size_t> csv_columns(const std::vector<std::string>& header, const std::string& where) {
  std::map<std::string, std::size_t> column;
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (header[i].empty()) throw InputError(where + ": header column " + std::to_string(i + 1) + " has no name");
    if (!column.emplace(header[i], i).second) throw InputError(where + ": header names column '" + header[i] + "' twice");
  }
  return column;
}

double parse_double_field(const std::string& field, const std::string& where, const std::string& column) {
  const char* s = field.c_str();
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(s, &end);
  if (field.empty() || end == s || *end != '\0')
    throw InputError(where + ": column " + column + " is not a number: '" + field + "'");
  return x;
}

double parse_finite_field(const std::string& field, const std::string& where, const std::string& column) {
  const double x = parse_double_field(field, where, column);
  if (!std::isfinite(x)) throw InputError(where + ": column " + column + " is not finite: '" + field + "'");
  return x;
}

std::uint64_t parse_index_field(const std::string& field, const std::string& where, const std::string& column) {
  const char* s = field.c_str();
  char* end = nullptr;
  errno = 0;
  const unsigned long long x = std::strtoull(s, &end, 10);
  if (field.empty() || end == s || *end != '\0' || field[0] == '-' || field[0] == '+' || errno == ERANGE)
    throw InputError(where + ": column " + column + " is not a non-negative integer: '" + field + "'");
  return static_cast<std::uint64_t>(x);
}

}  // namespace cdbench
