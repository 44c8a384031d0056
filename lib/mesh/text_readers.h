#pragma once
// Our own readers for OFF, OBJ and STL, and the encoding check shared by the text formats.
//
// CGAL's readers say only whether a file parsed; users need to know where it did not and what was
// skipped. These formats are simple enough to read line by line here, with the line (or, for
// binary STL, the byte offset) in every message. PLY stays with CGAL behind the structural
// pre-check of file_structure.cpp, which names lines and offsets the same way. (OFF went through
// that pre-check and then CGAL's reader, two passes over the text: 3.9 s of `cdbench check` on an
// 832,000-face mesh; doc/mesh-intake.md.)
#include <string>
#include <string_view>

#include "core/triangle_mesh.h"

namespace cdbench {

// Text formats must be ASCII-compatible (ASCII or UTF-8). Returns the number of bytes of a UTF-8
// byte-order mark to skip (0 or 3); throws InputError naming UTF-16/UTF-32 (byte-order mark or
// the pattern of NUL bytes) or the offset of the first NUL byte of a file that is not text.
std::size_t check_text_encoding(std::string_view bytes, const std::string& name);

// ASCII OFF ('OFF', 'COFF', 'NOFF', 'STOFF'...: the first three numbers of a vertex line, the k
// indices after a face's count k; colours, normals and '#' comments are ignored). The counts are
// checked against the file's size before anything is sized from them. Throws InputError naming the
// line of a malformed vertex or face, a truncated body, binary or non-3D OFF.
PolygonSoup read_off(std::string_view bytes, const std::string& name);

// OBJ: 'v' (first three coordinates), 'f'/'fo' (vertex index before any '/', negative = relative),
// line continuation with '\'. Every other line (vt, vn, l, p, g, o, s, materials, free-form
// geometry, unknown keywords such as the counts line of FCL's meshes) is skipped and summarised in
// one notice. Throws InputError naming the line of a malformed 'v' or 'f', or when there is no face.
PolygonSoup read_obj(std::string_view bytes, const std::string& name);

// STL, binary (84 + 50 n bytes exactly) or ASCII ('solid' ... 'endsolid', several solids allowed).
// Every corner becomes its own point; welding (mesh/weld.h) joins them.
PolygonSoup read_stl(std::string_view bytes, const std::string& name);

}  // namespace cdbench
