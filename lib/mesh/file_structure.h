#pragma once
// Structural pre-check of PLY files before CGAL parses them (OFF, OBJ and STL are read by our own
// readers, text_readers.h, which check as they go): every count a file announces is
// compared with what the file can hold, so that no reader sizes a buffer from an unchecked number.
#include <string>

namespace cdbench {

enum class MeshFormat;

// Throws InputError ("<name>: <what is wrong>") when the bytes cannot be a well-formed file of the
// format. Passing does not mean the mesh is valid, only that parsing it is safe and bounded.
void check_mesh_file_structure(const std::string& bytes, MeshFormat format, const std::string& name);

}  // namespace cdbench
