#pragma once
// Our own readers for OBJ and STL, and the encoding check shared by the text formats.
//
// CGAL's OBJ and STL readers say only whether a file parsed; users need to know where it did not
// and what was skipped. Both formats are simple enough to read line by line here, with the line
// (or, for binary STL, the byte offset) in every message. OFF and PLY stay with CGAL behind the
// structural pre-check of file_structure.cpp, which names lines and offsets the same way.
#include <string>

#include "mesh/triangle_mesh.h"

namespace cdbench {

// Text formats must be ASCII-compatible (ASCII or UTF-8). Returns the number of bytes of a UTF-8
// byte-order mark to skip (0 or 3); throws InputError naming UTF-16/UTF-32 (byte-order mark or
// the pattern of NUL bytes) or the offset of the first NUL byte of a file that is not text.
std::size_t check_text_encoding(const std::string& bytes, const std::string& name);

// OBJ: 'v' (first three coordinates), 'f'/'fo' (vertex index before any '/', negative = relative),
// line continuation with '\'. Every other line (vt, vn, l, p, g, o, s, materials, free-form
// geometry, unknown keywords such as the counts line of FCL's meshes) is skipped and summarised in
// one notice. Throws InputError naming the line of a malformed 'v' or 'f', or when there is no face.
PolygonSoup read_obj(const std::string& bytes, const std::string& name);

// STL, binary (84 + 50 n bytes exactly) or ASCII ('solid' ... 'endsolid', several solids allowed).
// Every corner becomes its own point; welding (mesh/weld.h) joins them.
PolygonSoup read_stl(const std::string& bytes, const std::string& name);

}  // namespace cdbench
