#include "mesh/file_structure.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "mesh/read_mesh.h"
#include "mesh/text_numbers.h"
#include "util/error.h"

namespace cdbench {
namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what) { throw InputError(name + ": " + what); }

bool parse_number(const std::string& t) {
  if (t.empty()) return false;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  return end == t.c_str() + t.size() && std::isfinite(v);
}

// Whitespace-separated tokens from `start` on, counting lines as the file does (from 1).
class BodyTokens {
 public:
  BodyTokens(const std::string& bytes, std::size_t start) : s_(bytes), pos_(start) {
    for (std::size_t i = 0; i < start; ++i) line_ += bytes[i] == '\n';
  }
  bool next(std::string& tok) {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) line_ += s_[pos_++] == '\n';
    if (pos_ >= s_.size()) return false;
    const std::size_t start = pos_;
    while (pos_ < s_.size() && !std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
    tok.assign(s_, start, pos_ - start);
    return true;
  }
  std::size_t line() const { return line_; }

 private:
  const std::string& s_;
  std::size_t pos_;
  std::size_t line_ = 1;
};

// --- PLY ---
struct PlyProperty {
  bool list = false;
  int count_size = 0;  // bytes of the list count type
  int size = 0;        // bytes of the scalar (or list item) type
  bool is_float = false;
  std::string count_type, type, name;
};
struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
};

int ply_type_size(const std::string& t, bool& is_float) {
  is_float = (t == "float" || t == "float32" || t == "double" || t == "float64");
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

std::uint64_t read_uint(const unsigned char* p, int size, bool big_endian, bool is_signed, bool& negative) {
  std::uint64_t v = 0;
  for (int b = 0; b < size; ++b) {
    const int idx = big_endian ? b : size - 1 - b;
    v = (v << 8) | p[idx];
  }
  negative = is_signed && (v >> (8 * size - 1)) != 0;
  return v;
}

// CGAL's PLY reader casts the properties it uses to the type it expects (coordinates float or
// double, colours uchar, half-edge indices uint, uvs float) and dereferences the cast unchecked, so
// another type there crashed it (fuzzing finding 2). Such files are refused here, naming the property.
void check_ply_property_types(const std::vector<PlyElement>& elements, const std::string& name) {
  const auto require = [&](const PlyElement& e, const PlyProperty& p, std::initializer_list<const char*> types,
                           const char* what) {
    if (!p.list)
      for (const char* t : types)
        if (p.type == t) return;
    fail(name, "PLY header: property '" + p.name + "' of element '" + e.name + "' must be " + what + ", not " +
                   (p.list ? "a list" : "'" + p.type + "'"));
  };
  for (const PlyElement& e : elements) {
    const bool vertex = e.name == "vertex" || e.name == "vertices", face = e.name == "face" || e.name == "faces";
    for (const PlyProperty& p : e.properties) {
      const std::string& n = p.name;
      if (vertex && (n == "x" || n == "y" || n == "z"))
        require(e, p, {"float", "float32", "double", "float64"}, "float or double");
      if ((vertex || face) && (n == "red" || n == "green" || n == "blue" || n == "r" || n == "g" || n == "b"))
        require(e, p, {"uchar", "uint8"}, "uchar (a colour)");
      if (e.name == "halfedge" && (n == "source" || n == "target")) require(e, p, {"uint", "uint32"}, "uint");
      if (e.name == "halfedge" && (n == "u" || n == "v")) require(e, p, {"float", "float32"}, "float");
    }
  }
}

void check_ply(const std::string& bytes, const std::string& name) {
  if (bytes.compare(0, 3, "ply") != 0 || (bytes.size() > 3 && bytes[3] != '\n' && bytes[3] != '\r'))
    fail(name, "not a PLY file: it does not start with the line 'ply'");
  // The header ends at the first line whose first word is end_header, as CGAL's reader reads it
  // (not at the first occurrence of the text, which may sit inside another word or a comment).
  std::size_t header_end = std::string::npos, body = bytes.size();
  for (std::size_t at = 0; at < bytes.size();) {
    std::size_t eol = bytes.find('\n', at);
    if (eol == std::string::npos) eol = bytes.size();
    std::istringstream ls(bytes.substr(at, eol - at));
    std::string first;
    if ((ls >> first) && first == "end_header") {
      header_end = at;
      body = std::min(bytes.size(), eol + 1);
      break;
    }
    at = eol + 1;
  }
  if (header_end == std::string::npos) fail(name, "PLY header has no 'end_header' line");
  std::istringstream header(bytes.substr(0, header_end));
  std::string line, format;
  std::vector<PlyElement> elements;
  std::size_t line_no = 0;
  while (std::getline(header, line)) {
    ++line_no;
    std::istringstream ls(line);
    std::string word;
    if (!(ls >> word)) continue;
    // CGAL takes the format from line 2 only: another format line there or later would make this
    // check walk the body in one encoding while CGAL reads it in another (fuzzing finding 3).
    if (line_no == 2 && word != "format") fail(name, "PLY header: line 2 must be the 'format' line");
    if (word == "format") {
      if (line_no != 2) fail(name, "PLY header: line " + std::to_string(line_no) + ": a second 'format' line");
      ls >> format;
    } else if (word == "element") {
      PlyElement e;
      std::string count;
      if (!(ls >> e.name >> count) || !parse_count(count, e.count))
        fail(name, "PLY header: bad element line '" + line.substr(0, 60) + "'");
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) fail(name, "PLY header: a property comes before any element");
      PlyProperty p;
      std::string type;
      ls >> type;
      if (type == "list") {
        p.list = true;
        ls >> p.count_type >> p.type;
        bool f = false;
        p.count_size = ply_type_size(p.count_type, f);
        if (p.count_size == 0 || f) fail(name, "PLY header: bad list count type '" + p.count_type + "'");
      } else {
        p.type = type;
      }
      ls >> p.name;
      p.size = ply_type_size(p.type, p.is_float);
      if (p.size == 0) fail(name, "PLY header: unknown property type '" + p.type.substr(0, 20) + "'");
      elements.back().properties.push_back(p);
    }
  }
  check_ply_property_types(elements, name);
  const bool ascii = format == "ascii";
  const bool big = format == "binary_big_endian";
  if (!ascii && !big && format != "binary_little_endian") fail(name, "PLY header: unknown format '" + format + "'");
  const long long avail = static_cast<long long>(bytes.size() - body);
  for (const PlyElement& e : elements) {
    // Every item takes at least one byte (binary) or two (ASCII token and separator).
    if (e.count > avail) {
      fail(name, "PLY header announces " + std::to_string(e.count) + " " + e.name + " elements, more than the " +
                     std::to_string(avail) + " bytes of data can hold");
    }
  }
  if (ascii) {
    BodyTokens data(bytes, body);
    std::string tok;
    for (const PlyElement& e : elements) {
      for (long long i = 0; i < e.count; ++i) {
        for (const PlyProperty& p : e.properties) {
          if (!data.next(tok))
            fail(name, "truncated after line " + std::to_string(data.line()) + ": element " + e.name + " " +
                           std::to_string(i) + " of " + std::to_string(e.count) + " is incomplete");
          if (p.list) {
            long long k = 0;
            if (!parse_count(tok, k) || k > avail)
              fail(name, "line " + std::to_string(data.line()) + ": " + e.name + " " + std::to_string(i) +
                             ": bad list length '" + tok.substr(0, 20) + "'");
            for (long long j = 0; j < k; ++j)
              if (!data.next(tok) || !parse_number(tok))
                fail(name, "line " + std::to_string(data.line()) + ": " + e.name + " " + std::to_string(i) +
                               ": list shorter than its length " + std::to_string(k));
          } else if (!parse_number(tok)) {
            fail(name, "line " + std::to_string(data.line()) + ": " + e.name + " " + std::to_string(i) + ": '" +
                           tok.substr(0, 20) + "' is not a finite number");
          }
        }
      }
    }
    return;
  }
  std::size_t pos = body;
  const auto* base = reinterpret_cast<const unsigned char*>(bytes.data());
  for (const PlyElement& e : elements) {
    for (long long i = 0; i < e.count; ++i) {
      for (const PlyProperty& p : e.properties) {
        std::uint64_t n = 1;
        if (p.list) {
          if (pos + p.count_size > bytes.size())
            fail(name, "truncated at byte " + std::to_string(pos) + ": " + e.name + " " + std::to_string(i) + " of " +
                           std::to_string(e.count));
          bool negative = false;
          const bool is_signed = p.count_type == "char" || p.count_type == "short" || p.count_type == "int" ||
                                 p.count_type == "int8" || p.count_type == "int16" || p.count_type == "int32";
          n = read_uint(base + pos, p.count_size, big, is_signed, negative);
          pos += p.count_size;
          if (negative || n > (bytes.size() - pos) / static_cast<std::uint64_t>(p.size))
            fail(name, "byte " + std::to_string(pos - p.count_size) + ": " + e.name + " " + std::to_string(i) +
                           ": list length " + (negative ? "negative" : std::to_string(n)) +
                           " runs past the end of the file");
        }
        if (pos + n * p.size > bytes.size())
          fail(name, "truncated at byte " + std::to_string(pos) + ": " + e.name + " " + std::to_string(i) + " of " +
                         std::to_string(e.count));
        if (p.is_float && !p.list) {
          bool finite = true;
          if (p.size == 4) {
            unsigned char b[4];
            for (int k = 0; k < 4; ++k) b[k] = base[pos + (big ? 3 - k : k)];
            float f;
            std::memcpy(&f, b, 4);
            finite = std::isfinite(f);
          } else {
            unsigned char b[8];
            for (int k = 0; k < 8; ++k) b[k] = base[pos + (big ? 7 - k : k)];
            double d;
            std::memcpy(&d, b, 8);
            finite = std::isfinite(d);
          }
          if (!finite)
            fail(name, "byte " + std::to_string(pos) + ": " + e.name + " " + std::to_string(i) +
                           ": a coordinate is NaN or infinite");
        }
        pos += n * p.size;
      }
    }
  }
}

}  // namespace

void check_mesh_file_structure(const std::string& bytes, MeshFormat format, const std::string& name) {
  switch (format) {
    case MeshFormat::Ply: return check_ply(bytes, name);
    case MeshFormat::Off:
    case MeshFormat::Stl:
    case MeshFormat::Obj: return;  // read by our own readers (text_readers.cpp), which check as they go
  }
}

}  // namespace cdbench
