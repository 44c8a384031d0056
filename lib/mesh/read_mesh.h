#pragma once
// Reading meshes: OFF, OBJ, PLY (ASCII and binary) and STL (ASCII and binary) through CGAL's I/O.
//
// CGAL's readers trust what a file announces (vertex counts, per-face list lengths) and size their
// buffers from it, so a hostile header could make them allocate terabytes. Every file is therefore
// first walked structurally by our own pre-check (counts against the file size, list lengths
// against the bytes or tokens that follow, binary floats finite) and only then parsed by CGAL.
#include <string>
#include <string_view>

#include "core/triangle_mesh.h"

namespace cdbench {

enum class MeshFormat { Off, Obj, Ply, Stl };

// Format from the file name's extension (case-insensitive); throws InputError for anything else.
MeshFormat mesh_format_from_path(const std::string& path);

// Reads the file as a polygon soup. Throws InputError naming the file and what is wrong (unreadable,
// empty, unknown format, malformed structure, non-finite coordinates, indices out of range,
// polygons with fewer than 3 corners, no faces).
PolygonSoup read_polygon_soup(const std::string& path);

// A file of triangles read as they are (no validation, no welding): the meshes cdbench writes
// itself (offsets). InputError naming the file for a polygon that is not a triangle.
TriangleMesh read_triangle_mesh(const std::string& path);

// Same as read_polygon_soup, from the file's bytes (the name is used for the format and in messages).
PolygonSoup read_polygon_soup_from_bytes(std::string_view bytes, const std::string& name);

}  // namespace cdbench
