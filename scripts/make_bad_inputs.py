#!/usr/bin/env python3
"""Writes the malformed and invalid meshes of data/bad/ and their expected outcomes (expected.tsv).

Each row of expected.tsv: file, exit code of `cdbench check` (2 unreadable, 1 invalid solid,
0 usable), and a substring the message must contain. Deterministic: re-running gives the same bytes.
"""
import os
import random
import struct

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "bad")
rows = []


def write(name, data, code, expect):
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(os.path.join(OUT, name), mode) as f:
        f.write(data)
    rows.append((name, code, expect))


def off(vertices, faces, header=None):
    s = header if header is not None else "OFF\n%d %d 0\n" % (len(vertices), len(faces))
    s += "".join("%r %r %r\n" % tuple(v) for v in vertices)
    s += "".join(("%d " % len(f)) + " ".join(str(i) for i in f) + "\n" for f in faces)
    return s


CUBE_V = [(x, y, z) for z in (0.0, 1.0) for y in (0.0, 1.0) for x in (0.0, 1.0)]
CUBE_F = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4),
          (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
TET_V = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)]
TET_F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def shifted(faces, k):
    return [tuple(i + k for i in f) for f in faces]


# Files as exporters write them (issue 14): seams split vertices, OBJ carries non-geometry lines,
# encodings other than ASCII. Each closed solid after exact welding must be accepted.
CUBE_QUADS = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]


def textured_cube_ply():
    """Each quad has its own 4 corners with texture coordinates, as a textured export writes them."""
    verts, faces = [], []
    for q in CUBE_QUADS:
        ids = []
        for k, i in enumerate(q):
            ids.append(len(verts))
            verts.append(CUBE_V[i] + ((k & 1) * 1.0, (k >> 1) * 1.0))
        faces.append(ids)
    s = ("ply\nformat ascii 1.0\ncomment exported with texture coordinates\nelement vertex %d\n"
         "property float x\nproperty float y\nproperty float z\nproperty float s\nproperty float t\n"
         "element face %d\nproperty list uchar int vertex_indices\nend_header\n" % (len(verts), len(faces)))
    s += "".join("%r %r %r %r %r\n" % v for v in verts)
    s += "".join("4 " + " ".join(str(i) for i in f) + "\n" for f in faces)
    return s


def textured_cube_obj(counts_line=False):
    s = "%d %d\n" % (8, 12) if counts_line else ""
    s += "# exported cube\nmtllib cube.mtl\no Cube\n"
    s += "".join("v %r %r %r\n" % v for v in CUBE_V)
    s += "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0 0\n"
    s += "g side\nusemtl paint\ns off\n"
    for n, q in enumerate(CUBE_QUADS):
        s += "f " + " ".join("%d/%d/%d" % (i + 1, k + 1, n + 1) for k, i in enumerate(q)) + "\n"
    s += "l 1 2\np 3\n"
    return s


def stl_ascii(triangles, name="cube"):
    s = "solid %s\n" % name
    for t in triangles:
        s += "  facet normal 0 0 0\n    outer loop\n"
        s += "".join("      vertex %r %r %r\n" % v for v in t)
        s += "    endloop\n  endfacet\n"
    return s + "endsolid %s\n" % name


def real_world_files(write):
    tris = [tuple(CUBE_V[i] for i in f) for f in CUBE_F]
    write("textured_cube.ply", textured_cube_ply(), 0, "welded 16 vertices with exactly equal coordinates")
    write("textured_cube.obj", textured_cube_obj(), 0, "'vt' x4")
    write("fcl_counts_line.obj", textured_cube_obj(counts_line=True), 0, "'8' x1 (first at line 1)")
    soup = [v for t in tris for v in t]
    write("soup_cube.off", off(soup, [(3 * k, 3 * k + 1, 3 * k + 2) for k in range(12)]), 0,
          "welded 28 vertices with exactly equal coordinates")
    write("cube_ascii.stl", stl_ascii(tris), 0, "welded 28 vertices")
    body = b"".join(struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *v) for v in t) + b"\0\0"
                    for t in tris)
    write("cube_solid_header.stl", b"solid exported by a CAD program".ljust(80, b" ") + struct.pack("<I", 12) + body,
          0, "welded 28 vertices")
    crlf = "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nv 0 0 1\r\nf -4 -2 -3\r\nf -4 -3 -1\r\nf -4 -1 -2\r\nf -3 -2 \\\r\n -1\r\n"
    write("crlf_relative.obj", crlf, 0, "valid closed solid")
    write("utf8_bom.off", "\ufeff" + off(TET_V, TET_F), 0, "valid closed solid")
    write("utf16.obj", textured_cube_obj().encode("utf-16"), 2, "UTF-16 little-endian (byte-order mark FF FE)")
    write("utf16_no_bom.obj", textured_cube_obj().encode("utf-16-be"), 2, "looks encoded as UTF-16 big-endian")
    write("latin1.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1,5\xb0\nf 1 3 2\n".encode("latin-1"), 2,
          "line 4: a vertex ('v') needs three finite coordinates")
    write("short_vertex.obj", "# a cube\nv 0 0 0\nv 1 0\nf 1 2 1\n", 2, "line 3: a vertex ('v') needs three")
    write("bad_corner.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 x/2 3\n", 2, "line 4: face corner 'x/2'")
    write("far_relative.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\n", 2, "refers 3 vertices back")
    write("lines_only.obj", "v 0 0 0\nv 1 0 0\nl 1 2\n", 2, "no 'f' lines; skipped 1 line")
    bad_stl = stl_ascii(tris[:2]).replace("vertex", "vertx", 4)
    write("bad_keyword.stl", bad_stl, 2, "line 4: expected 'vertex' or 'endloop', found 'vertx'")
    write("truncated_ascii.stl", stl_ascii(tris)[:300], 2, "truncated after line")
    write("bad_number.ply", textured_cube_ply().replace("1.0 1.0 0.0", "1.0 abc 0.0", 1), 2,
          "line 15: vertex 2: 'abc' is not a finite number")


def main():
    os.makedirs(OUT, exist_ok=True)
    rnd = random.Random(20261121)
    write("empty.off", "", 2, "the file is empty")
    write("truncated.off", off(CUBE_V, CUBE_F)[:60], 2, "truncated")
    write("nan.off", off(TET_V[:2] + [(float("nan"), 1.0, 0.0)] + TET_V[3:], TET_F), 2,
          "vertex 2 needs three finite coordinates")
    write("huge_header.off", "OFF\n1000000000000 1 0\n0 0 0\n3 0 0 0\n", 2, "more than a file of")
    write("negative_count.off", "OFF\n-4 4 0\n" + off(TET_V, TET_F).split("\n", 2)[2], 2,
          "counts must be non-negative integers")
    write("index_out_of_range.off", off(TET_V, TET_F[:3] + [(1, 2, 9)]), 2, "refers to vertex '9'")
    write("face_two_corners.off", off(TET_V, TET_F[:3] + [(1, 2)]), 2, "has 2 corners")
    write("huge_face.off", off(TET_V, TET_F[:3]) .replace("OFF\n4 3 0", "OFF\n4 4 0") +
          "4000000000 0 1 2\n", 2, "announces '4000000000' corners")
    write("points_only.off", off(TET_V, []), 2, "no faces")
    write("garbage.off", bytes(rnd.getrandbits(8) for _ in range(4096)), 2, "this is not a text file")
    write("garbage.ply", bytes(rnd.getrandbits(8) for _ in range(4096)), 2, "not a PLY file")
    write("garbage.stl", bytes(rnd.getrandbits(8) for _ in range(4096)), 2, "binary STL announces")
    write("unknown_format.xyz", "0 0 0\n1 0 0\n", 2, "unknown mesh format '.xyz'")
    write("no_extension", "OFF\n", 2, "unknown mesh format '(no extension)'")
    # Binary STL: the count says 100 triangles, the data holds 2.
    tri = struct.pack("<3f", 0, 0, 1) + struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + b"\0\0"
    write("truncated_binary.stl", b"\0" * 80 + struct.pack("<I", 100) + tri * 2, 2,
          "binary STL announces 100 triangles")
    bad = struct.pack("<3f", 0, 0, 1) + struct.pack("<9f", 0, 0, 0, float("nan"), 0, 0, 0, 1, 0) + b"\0\0"
    write("nan_binary.stl", b"\0" * 80 + struct.pack("<I", 2) + tri + bad, 2, "NaN or infinite")
    ply_header = ("ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\n"
                  "property float y\nproperty float z\nelement face 12\nproperty list uchar int vertex_indices\n"
                  "end_header\n")
    body = b"".join(struct.pack("<3f", *v) for v in CUBE_V)
    write("truncated_binary.ply", ply_header.encode() + body[:50], 2, "truncated")
    write("huge_list.ply", ("ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                            "property float y\nproperty float z\nelement face 1\n"
                            "property list int int vertex_indices\nend_header\n").encode()
          + b"".join(struct.pack("<3f", *v) for v in TET_V[:3]) + struct.pack("<i", 2000000000) +
          struct.pack("<3i", 0, 1, 2), 2, "runs past the end of the file")
    write("huge_header.ply", "ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\n"
          "property float y\nproperty float z\nelement face 0\nproperty list uchar int vertex_indices\n"
          "end_header\n0 0 0\n", 2, "more than the")
    write("bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", 2, "line 4: a face refers to vertex 9")
    write("zero_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 2, "OBJ vertex indices count from 1")
    # Closed and manifold, but one face has zero area (vertex 4 lies on edge 0-1).
    zv = TET_V + [(0.5, 0.0, 0.0)]
    zf = [(0, 2, 4), (4, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3), (0, 4, 1)]
    write("zero_area.off", off(zv, zf), 1, "degenerate (zero-area) faces")
    write("open_surface.off", off(CUBE_V, CUBE_F[:10]), 1, "boundary edges")
    # Two cubes sharing the edge x = 1, y = 1 (same vertex indices): four faces on that edge.
    cube2 = [(x + 1.0, y + 1.0, z) for (x, y, z) in CUBE_V]
    verts2 = CUBE_V + cube2
    remap = {8 + 0: 3, 8 + 4: 7}  # the second cube's (0,0,z) corners are the first cube's (1,1,z)
    faces2 = CUBE_F + [tuple(remap.get(i + 8, i + 8) for i in f) for f in CUBE_F]
    write("two_cubes_edge.off", off(verts2, faces2), 1, "non-manifold edges")
    # A closed tetrahedron with a fin: a third face on edge 1-2.
    write("non_manifold_edge.off", off(TET_V + [(1.0, 1.0, -1.0)], TET_F + [(1, 2, 4)]), 1, "non-manifold edges")
    # Two tetrahedra sharing vertex 0 only.
    tet2 = [(0.0, 0.0, 0.0), (-1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0)]
    f2 = [tuple(0 if i == 0 else i + 3 for i in (f[0], f[2], f[1])) for f in TET_F]
    write("non_manifold_vertex.off", off(TET_V + tet2[1:], TET_F + f2), 1, "non-manifold vertices")
    # Two interpenetrating tetrahedra.
    tet3 = [(x + 0.2, y + 0.2, z + 0.2) for (x, y, z) in TET_V]
    write("self_intersecting.off", off(TET_V + tet3, TET_F + shifted(TET_F, 4)), 1, "pairs of faces intersect")
    # Consistent but inward orientation: usable, fixed with a notice.
    write("inward_cube.off", off(CUBE_V, [(f[0], f[2], f[1]) for f in CUBE_F]), 0, "inward-oriented")
    # Inconsistent orientation (one face flipped): fixed with a notice.
    write("one_face_flipped.off", off(CUBE_V, [(0, 1, 2)] + CUBE_F[1:]), 0, "flipped to make the orientation consistent")
    # Extreme scale and size (issue 13): refused with the supported range named; a single face.
    write("box_1e150.off", off([tuple(1e150 * c for c in v) for v in CUBE_V], CUBE_F), 1,
          "outside the supported range |x| <= 1e+40")
    write("box_1e-150.off", off([tuple(1e-150 * c for c in v) for v in CUBE_V], CUBE_F), 1, "below the supported 1e-40")
    write("one_face.off", off(TET_V[:3], [(0, 1, 2)]), 1, "3 boundary edges (the surface is not closed)")
    # Fuzzing finding 1: 'end_header' inside another word; CGAL's reader crashed on the property
    # line that follows (before any element) when the pre-check stopped the header there.
    write("end_header_inside_word.ply", "ply\nformat ascii 1.0\nelemend_header 4\nproperty float x\nend_header\n0\n", 2,
          "a property comes before any element")
    # Fuzzing finding 2: a coordinate property of a type CGAL's reader does not cast (it crashed).
    write("uchar_coordinate.ply", textured_cube_ply().replace("property float y", "property uchar y", 1), 2,
          "property 'y' of element 'vertex' must be float or double, not 'uchar'")
    # Fuzzing finding 3: a second format line; the pre-check took the last, CGAL the first, and CGAL
    # then sized a list from ASCII bytes read as binary (gigabytes, seconds per file).
    second = textured_cube_ply().replace("element vertex", "format ascii 1.0\nelement vertex", 1)
    write("second_format_line.ply", second.replace("format ascii 1.0", "format binary_little_endian 1.0", 1), 2,
          "line 4: a second 'format' line")
    real_world_files(write)
    os.makedirs(os.path.join(OUT, "directory.off"), exist_ok=True)
    with open(os.path.join(OUT, "directory.off", ".keep"), "w") as f:
        f.write("a directory named like a mesh\n")
    rows.append(("directory.off", 2, "not a regular file"))
    with open(os.path.join(OUT, "expected.tsv"), "w") as f:
        f.write("# file\texit\tmessage contains\n")
        for r in rows:
            f.write("%s\t%d\t%s\n" % r)


if __name__ == "__main__":
    main()
