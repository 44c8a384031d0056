#include "mesh/text_readers.h"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <string_view>
#include <vector>

#include <tbb/parallel_for.h>

#include "mesh/text_numbers.h"
#include "util/error.h"

namespace cdbench {
namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what) { throw InputError(name + ": " + what); }

std::string at_line(std::size_t line) { return "line " + std::to_string(line) + ": "; }

// A token as it appears, shortened for messages, with non-printable bytes in hex.
std::string quoted(std::string_view t) {
  std::string out = "'";
  for (std::size_t i = 0; i < t.size() && i < 40; ++i) {
    const unsigned char c = static_cast<unsigned char>(t[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      static const char* hex = "0123456789ABCDEF";
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  if (t.size() > 40) out += "...";
  return out + "'";
}

bool has_non_ascii(std::string_view s) {
  for (char c : s)
    if (static_cast<unsigned char>(c) >= 0x80) return true;
  return false;
}

std::string encoding_hint(std::string_view line) {
  return has_non_ascii(line) ? " (the line holds non-ASCII bytes: is the file in another encoding than ASCII/UTF-8?)"
                             : "";
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

void split(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
}

// A finite decimal number (from_chars does not take a leading '+').
bool parse_double(std::string_view t, double& v) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  return r.ec == std::errc() && r.ptr == t.data() + t.size() && std::isfinite(v);
}

bool parse_int(std::string_view t, long long& v) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

// Lines of a text from byte `start` to byte `stop` (the end), with their numbers (the line before
// `start` is number `number`); '\r' is whitespace for the tokenizer.
class Lines {
 public:
  Lines(std::string_view bytes, std::size_t start, std::size_t stop = std::string::npos, std::size_t number = 0)
      : s_(bytes), pos_(start), stop_(std::min(stop, bytes.size())), number_(number) {}
  bool next(std::string_view& line) {
    if (pos_ >= stop_) return false;
    std::size_t end = s_.find('\n', pos_);
    if (end == std::string::npos || end > stop_) end = stop_;
    line = std::string_view(s_).substr(pos_, end - pos_);
    pos_ = end + 1;
    ++number_;
    return true;
  }
  std::size_t number() const { return number_; }
  std::size_t position() const { return std::min(pos_, stop_); }  // the start of the next line

 private:
  std::string_view s_;
  std::size_t pos_;
  std::size_t stop_;
  std::size_t number_ = 0;
};

}  // namespace

namespace {

// The first NUL byte at or after `from` (npos: none); large inputs are searched in chunks on all
// threads (a 42 MB file took 60 ms on one), the first found in the earliest chunk.
std::size_t find_first_nul(std::string_view bytes, std::size_t from) {
  constexpr std::size_t kChunk = std::size_t(1) << 22;
  if (bytes.size() - std::min(from, bytes.size()) < 2 * kChunk) return bytes.find('\0', from);
  const std::size_t chunks = (bytes.size() - from + kChunk - 1) / kChunk;
  std::atomic<std::size_t> first{std::string_view::npos};
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    const std::size_t begin = from + c * kChunk;
    if (begin >= first.load(std::memory_order_relaxed)) return;
    const std::size_t end = std::min(bytes.size(), begin + kChunk);
    const std::size_t at = bytes.substr(0, end).find('\0', begin);
    if (at == std::string_view::npos) return;
    std::size_t seen = first.load(std::memory_order_relaxed);
    while (at < seen && !first.compare_exchange_weak(seen, at, std::memory_order_relaxed)) {
    }
  });
  return first.load();
}

}  // namespace

std::size_t check_text_encoding(std::string_view bytes, const std::string& name) {
  const auto starts = [&](std::initializer_list<unsigned char> prefix) {
    if (bytes.size() < prefix.size()) return false;
    std::size_t i = 0;
    for (unsigned char c : prefix)
      if (static_cast<unsigned char>(bytes[i++]) != c) return false;
    return true;
  };
  if (starts({0xFF, 0xFE, 0x00, 0x00}) || starts({0x00, 0x00, 0xFE, 0xFF}))
    fail(name, "the file is encoded as UTF-32 (byte-order mark); save it as ASCII or UTF-8");
  if (starts({0xFF, 0xFE})) fail(name, "the file is encoded as UTF-16 little-endian (byte-order mark FF FE); save it as ASCII or UTF-8");
  if (starts({0xFE, 0xFF})) fail(name, "the file is encoded as UTF-16 big-endian (byte-order mark FE FF); save it as ASCII or UTF-8");
  const std::size_t skip = starts({0xEF, 0xBB, 0xBF}) ? 3 : 0;
  const std::size_t nul = find_first_nul(bytes, skip);
  if (nul != std::string::npos) {
    // UTF-16 without a byte-order mark: ASCII characters alternate with NUL bytes.
    std::size_t zeros_even = 0, zeros_odd = 0, n = std::min<std::size_t>(bytes.size(), 512);
    for (std::size_t i = 0; i < n; ++i)
      if (bytes[i] == '\0') ++(i % 2 ? zeros_odd : zeros_even);
    if (n >= 8 && (zeros_odd >= n / 2 - 1 || zeros_even >= n / 2 - 1) && (zeros_odd == 0 || zeros_even == 0))
      fail(name, std::string("the file looks encoded as UTF-16 ") + (zeros_odd ? "little" : "big") +
                     "-endian (every other byte is NUL); save it as ASCII or UTF-8");
    fail(name, "byte " + std::to_string(nul) + " is a NUL byte: this is not a text file");
  }
  return skip;
}

PolygonSoup read_obj(std::string_view bytes, const std::string& name) {
  Lines lines(bytes, check_text_encoding(bytes, name));
  PolygonSoup soup;
  struct Skipped {
    std::size_t count = 0, first_line = 0, order = 0;
  };
  std::map<std::string, Skipped> skipped;
  long long max_index = 0;  // positive indices are checked at the end (OBJ allows referring ahead)
  std::size_t max_index_line = 0;
  std::vector<std::string_view> tok;
  std::string joined;
  std::string_view raw;
  while (lines.next(raw)) {
    const std::size_t line_no = lines.number();
    std::string_view line = raw;
    // A trailing backslash continues the line.
    if (!line.empty() && (line.back() == '\\' || (line.size() > 1 && line.back() == '\r' && line[line.size() - 2] == '\\'))) {
      joined.assign(line.substr(0, line.find_last_of('\\')));
      std::string_view more;
      while (lines.next(more)) {
        const bool again = !more.empty() && (more.back() == '\\' || (more.size() > 1 && more.back() == '\r' &&
                                                                      more[more.size() - 2] == '\\'));
        joined += ' ';
        joined.append(again ? more.substr(0, more.find_last_of('\\')) : more);
        if (!again) break;
      }
      line = joined;
    }
    const std::size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    split(line, tok);
    if (tok.empty()) continue;
    const std::string_view key = tok[0];
    if (key == "v") {
      double x, y, z;
      if (tok.size() < 4 || !parse_double(tok[1], x) || !parse_double(tok[2], y) || !parse_double(tok[3], z))
        fail(name, at_line(line_no) + "a vertex ('v') needs three finite coordinates, found " + quoted(raw) +
                       encoding_hint(raw));
      soup.points.emplace_back(x, y, z);
    } else if (key == "f" || key == "fo") {
      if (tok.size() < 4)
        fail(name, at_line(line_no) + "a face ('f') needs at least 3 corners, found " + std::to_string(tok.size() - 1));
      std::vector<std::size_t> poly;
      poly.reserve(tok.size() - 1);
      for (std::size_t k = 1; k < tok.size(); ++k) {
        const std::string_view corner = tok[k].substr(0, tok[k].find('/'));
        long long id = 0;
        if (!parse_int(corner, id))
          fail(name, at_line(line_no) + "face corner " + quoted(tok[k]) +
                         " is not a vertex index (expected v, v/vt, v/vt/vn or v//vn)" + encoding_hint(raw));
        if (id == 0) fail(name, at_line(line_no) + "face corner " + quoted(tok[k]) + ": OBJ vertex indices count from 1");
        if (id < 0) {
          const long long resolved = static_cast<long long>(soup.points.size()) + id;
          if (resolved < 0)
            fail(name, at_line(line_no) + "face corner " + quoted(tok[k]) + " refers " + std::to_string(-id) +
                           " vertices back, but only " + std::to_string(soup.points.size()) + " are defined so far");
          poly.push_back(static_cast<std::size_t>(resolved));
        } else {
          if (id > max_index) {
            max_index = id;
            max_index_line = line_no;
          }
          poly.push_back(static_cast<std::size_t>(id - 1));
        }
      }
      soup.polygons.push_back(std::move(poly));
    } else {
      Skipped& s = skipped[std::string(key.substr(0, 24))];
      if (s.count++ == 0) {
        s.first_line = line_no;
        s.order = skipped.size();
      }
    }
  }
  if (max_index > static_cast<long long>(soup.points.size()))
    fail(name, at_line(max_index_line) + "a face refers to vertex " + std::to_string(max_index) +
                   " (counting from 1), but the file defines only " + std::to_string(soup.points.size()) + " vertices");
  std::string summary;
  if (!skipped.empty()) {
    std::vector<std::pair<std::size_t, std::string>> order;
    std::size_t total = 0;
    for (const auto& [k, s] : skipped) {
      order.push_back({s.first_line, k});
      total += s.count;
    }
    std::sort(order.begin(), order.end());
    summary = "skipped " + std::to_string(total) + (total == 1 ? " line" : " lines") +
              " that are not triangle-mesh geometry:";
    std::size_t shown = 0;
    for (const auto& [first, k] : order) {
      if (shown++ == 8) {
        summary += " ...";
        break;
      }
      summary += " " + quoted(k) + " x" + std::to_string(skipped[k].count) + " (first at line " +
                 std::to_string(first) + ")";
    }
  }
  if (soup.polygons.empty())
    fail(name, "no faces: the file has " + std::to_string(soup.points.size()) + " vertices ('v') and no 'f' lines" +
                   (summary.empty() ? std::string() : "; " + summary));
  if (!summary.empty()) soup.notices.push_back(summary);
  return soup;
}

namespace {

// Whether a line holds a token once its '#' comment is cut (the lines next_tokens returns): its
// first non-blank character is not '#'.
bool holds_token(std::string_view line) {
  std::size_t k = 0;
  while (k < line.size() && is_space(line[k])) ++k;
  return k < line.size() && line[k] != '#';
}

// The next line holding a token once its '#' comment is cut; false at the end.
bool next_tokens(Lines& lines, std::vector<std::string_view>& tok) {
  std::string_view line;
  while (lines.next(line)) {
    const std::size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    split(line, tok);
    if (!tok.empty()) return true;
  }
  return false;
}

}  // namespace

PolygonSoup read_off(std::string_view bytes, const std::string& name) {
  Lines lines(bytes, check_text_encoding(bytes, name));
  std::vector<std::string_view> t;
  if (!next_tokens(lines, t)) fail(name, "no OFF header (the file holds only blanks or comments)");
  const std::string key(t[0]);
  if (key.size() < 3 || key.compare(key.size() - 3, 3, "OFF") != 0)
    fail(name, "not an OFF file: the first word is '" + key.substr(0, 40) + "', expected 'OFF'");
  if (key.find('n') != std::string::npos || key.find('4') != std::string::npos)
    fail(name, "'" + key + "' (non-3D OFF) is not supported");
  std::size_t i = 1;
  if (i < t.size() && t[i] == "BINARY") fail(name, "binary OFF is not supported; use ASCII OFF, PLY or STL");
  if (i >= t.size()) {
    if (!next_tokens(lines, t)) fail(name, "truncated OFF header: the vertex and face counts are missing");
    i = 0;
  }
  if (t.size() - i < 2)
    fail(name, "OFF header: expected 'vertices faces edges' counts, got '" + std::string(t[i]) + "'");
  long long nv = 0, nf = 0;
  if (!parse_count(t[i], nv) || !parse_count(t[i + 1], nf))
    fail(name, "OFF header: counts must be non-negative integers, got '" + std::string(t[i]) + " " +
                   std::string(t[i + 1]) + "'");
  // The shortest vertex line is "0 0 0\n" (6 bytes), the shortest face line "3 0 1 2\n" (8 bytes):
  // a count the file cannot hold is refused before anything is sized from it.
  const long long size = static_cast<long long>(bytes.size());
  if (nv > size / 6 || nf > size / 8 || nv * 6 + nf * 8 > size)
    fail(name, "OFF header announces " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                   " faces, more than a file of " + std::to_string(size) + " bytes can hold");
  // The records (vertex and face lines) are parsed in chunks of lines on all threads; each record's
  // index, and so its kind, comes from the counts of the chunks before it, and the error reported
  // is that of the first bad record, as a serial reading would report it.
  const std::size_t body = lines.position(), first_line = lines.number();
  std::vector<std::size_t> cuts{body};  // chunk starts, each at the start of a line
  const std::size_t chunk = std::max<std::size_t>(std::size_t{1} << 18, (bytes.size() - body) / 256 + 1);
  while (cuts.back() < bytes.size()) {
    const std::size_t nl = bytes.find('\n', std::min(bytes.size(), cuts.back() + chunk));
    cuts.push_back(nl == std::string::npos ? bytes.size() : nl + 1);
  }
  const std::size_t chunks = cuts.size() - 1;
  std::vector<std::size_t> records(chunks + 1, 0), line_count(chunks + 1, 0);
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    // Each chunk but the last ends with a newline, so its lines are what a later chunk's numbers
    // start after.
    Lines in(bytes, cuts[c], cuts[c + 1]);
    std::string_view line;
    while (in.next(line)) records[c + 1] += holds_token(line);
    line_count[c + 1] = in.number();
  });
  for (std::size_t c = 0; c < chunks; ++c) {
    records[c + 1] += records[c];
    line_count[c + 1] += line_count[c];
  }
  const long long total = static_cast<long long>(records[chunks]);
  if (total < nv)
    fail(name, "truncated: the header announces " + std::to_string(nv) + " vertices, the file ends after " +
                   std::to_string(total));
  if (total < nv + nf)
    fail(name, "truncated: the header announces " + std::to_string(nf) + " faces, the file ends after " +
                   std::to_string(total - nv));
  PolygonSoup soup;
  soup.points.resize(static_cast<std::size_t>(nv));
  soup.polygons.resize(static_cast<std::size_t>(nf));
  std::vector<std::string> error(chunks);  // each chunk's first error: the first non-empty one is the file's
  tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
    Lines lines(bytes, cuts[c], cuts[c + 1], first_line + line_count[c]);
    std::vector<std::string_view> t;
    for (long long r = static_cast<long long>(records[c]); r < nv + nf && next_tokens(lines, t); ++r) {
      if (r < nv) {
        double x, y, z;
        if (t.size() < 3 || !parse_double(t[0], x) || !parse_double(t[1], y) || !parse_double(t[2], z)) {
          error[c] = at_line(lines.number()) + "vertex " + std::to_string(r) + " needs three finite coordinates";
          return;
        }
        soup.points[static_cast<std::size_t>(r)] = Vec3(x, y, z);  // colours or normals after them are ignored
        continue;
      }
      const long long f = r - nv;
      long long k = 0;
      if (!parse_count(t[0], k) || k + 1 > static_cast<long long>(t.size())) {
        error[c] = at_line(lines.number()) + "face " + std::to_string(f) + " announces '" +
                   std::string(t[0].substr(0, 20)) + "' corners but the line holds " + std::to_string(t.size() - 1) +
                   " indices";
        return;
      }
      if (k < 3) {
        error[c] = at_line(lines.number()) + "face " + std::to_string(f) + " has " + std::to_string(k) +
                   " corners; a face needs at least 3";
        return;
      }
      std::vector<std::size_t> poly(static_cast<std::size_t>(k));
      for (long long j = 1; j <= k; ++j) {
        long long id = 0;
        if (!parse_count(t[j], id) || id >= nv) {
          error[c] = at_line(lines.number()) + "face " + std::to_string(f) + " refers to vertex '" +
                     std::string(t[j].substr(0, 20)) + "', but vertex indices run from 0 to " + std::to_string(nv - 1);
          return;
        }
        poly[static_cast<std::size_t>(j - 1)] = static_cast<std::size_t>(id);
      }
      soup.polygons[static_cast<std::size_t>(f)] = std::move(poly);  // colours after the indices are ignored
    }
  });
  for (const std::string& e : error)
    if (!e.empty()) fail(name, e);
  return soup;
}

namespace {

std::string triangle_at(std::size_t i) {
  return "triangle " + std::to_string(i) + " (byte " + std::to_string(84 + 50 * i) + ")";
}

PolygonSoup read_binary_stl(std::string_view bytes, const std::string& name, std::uint32_t n) {
  PolygonSoup soup;
  soup.points.reserve(3ull * n);
  soup.polygons.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const char* rec = bytes.data() + 84 + 50ull * i;
    std::vector<std::size_t> poly;
    for (int c = 0; c < 3; ++c) {
      float f[3];
      std::memcpy(f, rec + 12 + 12 * c, 12);  // little-endian, as our targets
      if (!std::isfinite(f[0]) || !std::isfinite(f[1]) || !std::isfinite(f[2]))
        fail(name, triangle_at(i) + ": corner " + std::to_string(c) + " has a NaN or infinite coordinate");
      poly.push_back(soup.points.size());
      soup.points.emplace_back(f[0], f[1], f[2]);
    }
    soup.polygons.push_back(std::move(poly));
  }
  if (n == 0) fail(name, "binary STL with 0 triangles");
  return soup;
}

// ASCII STL as a stream of tokens that knows their lines.
class Tokens {
 public:
  Tokens(std::string_view bytes, std::size_t start) : lines_(bytes, start) {}
  bool next(std::string_view& t) {
    while (k_ >= tok_.size()) {
      if (!lines_.next(line_)) return false;
      split(line_, tok_);
      k_ = 0;
    }
    t = tok_[k_++];
    return true;
  }
  void skip_rest_of_line() { k_ = tok_.size(); }
  std::size_t line() const { return lines_.number(); }
  std::string_view current_line() const { return line_; }

 private:
  Lines lines_;
  std::string_view line_;
  std::vector<std::string_view> tok_;
  std::size_t k_ = 0;
};

PolygonSoup read_ascii_stl(std::string_view bytes, const std::string& name, std::size_t start) {
  Tokens in(bytes, start);
  PolygonSoup soup;
  std::string_view t;
  const auto expect = [&](const char* word, const char* context) {
    if (!in.next(t)) fail(name, "truncated after line " + std::to_string(in.line()) + ": expected '" + word + "' " + context);
    if (t != word)
      fail(name, at_line(in.line()) + "expected '" + word + "' " + context + ", found " + quoted(t) +
                     encoding_hint(in.current_line()));
  };
  std::size_t solids = 0;
  while (in.next(t)) {
    if (t != "solid")
      fail(name, at_line(in.line()) + "expected 'solid', found " + quoted(t) + encoding_hint(in.current_line()));
    ++solids;
    in.skip_rest_of_line();  // the solid's name
    while (true) {
      if (!in.next(t)) fail(name, "truncated after line " + std::to_string(in.line()) + ": 'endsolid' is missing");
      if (t == "endsolid") {
        in.skip_rest_of_line();
        break;
      }
      if (t != "facet")
        fail(name, at_line(in.line()) + "expected 'facet' or 'endsolid', found " + quoted(t) +
                       encoding_hint(in.current_line()));
      expect("normal", "after 'facet'");
      for (int k = 0; k < 3; ++k)  // normals are ignored (some exporters write nan); only their presence counts
        if (!in.next(t)) fail(name, "truncated after line " + std::to_string(in.line()) + ": facet normal incomplete");
      expect("outer", "(of 'outer loop')");
      expect("loop", "(of 'outer loop')");
      std::vector<std::size_t> poly;
      while (true) {
        if (!in.next(t)) fail(name, "truncated after line " + std::to_string(in.line()) + ": facet not finished");
        if (t == "endloop") break;
        if (t != "vertex")
          fail(name, at_line(in.line()) + "expected 'vertex' or 'endloop', found " + quoted(t) +
                         encoding_hint(in.current_line()));
        double c[3];
        for (double& x : c) {
          if (!in.next(t) || !parse_double(t, x))
            fail(name, at_line(in.line()) + "a vertex needs three finite coordinates, found " +
                           quoted(in.current_line()) + encoding_hint(in.current_line()));
        }
        poly.push_back(soup.points.size());
        soup.points.emplace_back(c[0], c[1], c[2]);
      }
      if (poly.size() < 3)
        fail(name, at_line(in.line()) + "a facet has " + std::to_string(poly.size()) + " vertices; it needs at least 3");
      expect("endfacet", "after 'endloop'");
      soup.polygons.push_back(std::move(poly));
    }
  }
  if (soup.polygons.empty())
    fail(name, "no facets: the ASCII STL has " + std::to_string(solids) + " solid(s) and no 'facet' blocks");
  return soup;
}

}  // namespace

PolygonSoup read_stl(std::string_view bytes, const std::string& name) {
  const std::size_t size = bytes.size();
  std::uint32_t n = 0;
  if (size >= 84) std::memcpy(&n, bytes.data() + 80, 4);  // STL is little-endian; so are our targets
  // Binary files may begin with "solid" too (many exporters); the exact size decides.
  if (size >= 84 && size == 84 + 50ull * n) return read_binary_stl(bytes, name, n);
  const std::size_t skip = (size >= 3 && bytes.compare(0, 3, "\xEF\xBB\xBF") == 0) ? 3 : 0;
  std::size_t first = skip;
  while (first < size && (is_space(bytes[first]) || bytes[first] == '\n')) ++first;
  if (bytes.compare(first, 5, "solid") == 0) {
    check_text_encoding(bytes, name);
    return read_ascii_stl(bytes, name, skip);
  }
  if (size >= 2 && ((bytes[0] == '\xFF' && bytes[1] == '\xFE') || (bytes[0] == '\xFE' && bytes[1] == '\xFF')))
    check_text_encoding(bytes, name);  // names UTF-16 or UTF-32
  if (size < 84)
    fail(name, "not an STL file: too short for a binary STL (" + std::to_string(size) +
                   " bytes) and it does not start with 'solid'");
  fail(name, "binary STL announces " + std::to_string(n) + " triangles (" + std::to_string(84 + 50ull * n) +
                 " bytes) but the file has " + std::to_string(size) + " bytes");
}

}  // namespace cdbench
