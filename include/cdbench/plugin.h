/* cdbench plugin interface: time and check any collision library with `cdbench bench`.
 *
 * A plugin is a shared library exporting one C function, cdbench_plugin_entry, that returns a
 * description of the implementation. cdbench builds the implementation once from the two meshes
 * (create), then calls query for every pose of a pose set (warm-up, median of N, pinned thread)
 * and checks each answer against the pose's certified clearance:
 *
 *   cdbench bench POSESET --impl plugin:/path/to/libmyplugin.so -o DIR
 *
 * Conventions: vertices are x, y, z doubles; triangles are three 0-based vertex indices,
 * counter-clockwise seen from outside. A pose places the mover at x_world = R x + t in the fixed
 * mesh's frame, R given row-major (R[3 * i + j] = R_ij). The fixed mesh is at the identity.
 * The mesh arrays stay valid only during create: copy what you keep.
 * See doc/validate-your-library.md; examples/fcl_plugin is a complete plugin.
 */
#ifndef CDBENCH_PLUGIN_H
#define CDBENCH_PLUGIN_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Raised when the structures below change incompatibly; cdbench refuses other versions. */
#define CDBENCH_PLUGIN_ABI_VERSION 1

/* Flags. */
#define CDBENCH_PLUGIN_DETECTS_CONTAINMENT 1u /* "collides" also when the mover lies wholly inside the fixed solid */
#define CDBENCH_PLUGIN_COUNTS_TESTS 2u        /* bv_tests / triangle_tests are filled */
#define CDBENCH_PLUGIN_COMPUTES_DISTANCE 4u   /* distance is filled (separation distance when apart) */

typedef struct cdbench_mesh {
  const double* vertices; /* 3 * vertex_count */
  size_t vertex_count;
  const uint32_t* triangles; /* 3 * triangle_count */
  size_t triangle_count;
} cdbench_mesh;

typedef struct cdbench_answer {
  int collides;            /* nonzero: the two solids (or surfaces) intersect */
  double distance;         /* with CDBENCH_PLUGIN_COMPUTES_DISTANCE; otherwise left as is */
  uint64_t bv_tests;       /* with CDBENCH_PLUGIN_COUNTS_TESTS */
  uint64_t triangle_tests; /* with CDBENCH_PLUGIN_COUNTS_TESTS */
} cdbench_answer;

typedef struct cdbench_plugin {
  uint32_t abi_version; /* CDBENCH_PLUGIN_ABI_VERSION */
  const char* name;     /* shown in the tables, e.g. "fcl-obbrss-plugin" */
  uint32_t flags;       /* CDBENCH_PLUGIN_* */
  /* Builds the implementation's structures. Returns its state, or NULL after writing a
   * NUL-terminated message of at most error_size bytes into error. */
  void* (*create)(const cdbench_mesh* fixed, const cdbench_mesh* mover, char* error, size_t error_size);
  /* One static query; answer is zero-initialised with distance = NaN. Returns 0 on success. */
  int (*query)(void* state, const double R[9], const double t[3], cdbench_answer* answer);
  void (*destroy)(void* state);
} cdbench_plugin;

/* The one symbol a plugin exports. */
const cdbench_plugin* cdbench_plugin_entry(void);
typedef const cdbench_plugin* (*cdbench_plugin_entry_fn)(void);

#ifdef __cplusplus
}
#endif

#endif /* CDBENCH_PLUGIN_H */
