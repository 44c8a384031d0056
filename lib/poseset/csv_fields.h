#pragma once
// Fields of one line of the bundle's simple CSV files (no quoting: every field is a number or a
// word), with errors that name the file, the line and the column.
#include <cstddef>
#include <cstdint>
#include <istream>
#include <map>
#include <string>
#include <vector>

namespace cdbench {

// Splits at commas; drops a trailing CR/LF; surrounding blanks of each field are trimmed.
std::vector<std::string> split_csv_fields(const std::string& line);

// True for a line of blanks only (skipped by the readers).
bool is_blank_line(const std::string& line);
// The header: the first non-blank line (a UTF-8 byte-order mark skipped), split; empty at the end
// of the stream. `line_no` counts the lines read.
std::vector<std::string> read_csv_header(std::istream& in, std::size_t* line_no);
// Column index by name; InputError naming `where` for an empty or repeated name.
std::map<std::string, std::size_t> csv_columns(const std::vector<std::string>& header, const std::string& where);

// `where` is "file:line"; `column` the column's name (or number) for the message.
double parse_double_field(const std::string& field, const std::string& where, const std::string& column);
// A finite double.
double parse_finite_field(const std::string& field, const std::string& where, const std::string& column);
std::uint64_t parse_index_field(const std::string& field, const std::string& where, const std::string& column);

}  // namespace cdbench
