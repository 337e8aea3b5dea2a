/* visfield's C API (C99): scenes, structures by name, batch ray queries, ObjectFields and
 * BeamField updates, behind opaque handles, for engines and other languages. Link libvisfield
 * (find_package(visfield) target visfield::visfield, or pkg-config visfield).
 *
 * Conventions
 * - Every call that can fail returns vf_error: VF_OK (0) or a code; vf_last_error() and
 *   vf_last_error_message() then describe the failure on the calling thread, and the error
 *   callback (vf_set_error_callback) is called with the same code and message. No C++ exception
 *   crosses this boundary. Output parameters are written only on success.
 * - Handles are opaque values, created by vf_*_create / _load / _build and freed by vf_*_release
 *   (NULL is accepted and ignored). They are numbers, never addresses: a released handle, a handle
 *   never made (forged) or a handle of another kind (a scene passed as a structure) returns
 *   VF_ERROR_INVALID_ARGUMENT from every call, releasing twice included, and the process goes on.
 *   A structure or field keeps what it was built from alive: the scene handle may be released
 *   first; a handle released on one thread while another thread's call uses it lives until that
 *   call returns.
 * - Counts: a count whose arrays would not fit in memory (count times the element size beyond
 *   PTRDIFF_MAX) returns VF_ERROR_INVALID_ARGUMENT before any array is read.
 * - Thread safety: every call may be made from any thread, on any handle, at any time. Queries
 *   (vf_intersect*, vf_occluded*, vf_structure_get_stats) on one structure run at once; its edits
 *   and commit (vf_structure_remove, _insert, _move, _commit) are exclusive: a query that overlaps
 *   a commit waits for it (it is blocked) and answers for the structure before or after the commit,
 *   never for a state between. Edits of a scene (vf_scene_add_*, _set_transform, _remove_instance)
 *   likewise exclude the calls that read it (builds, counts, bounds, vf_structure_insert, fields).
 *   Queries run in parallel themselves (vf_set_threads).
 * - Rays: origin, direction (any non-zero length; t is in its units) and the range (tmin, tmax],
 *   which may start behind the origin (tmin < 0); an invalid ray (NaN, zero direction,
 *   tmin >= tmax) hits nothing. A hit's t is finite: where the computed t overflows (directions
 *   near 1e-38 long), there is no hit, for vf_occluded as for vf_intersect. Hits: t, barycentrics u, v of
 *   the triangle's vertices 1 and 2, the triangle index in its mesh (prim), the object id
 *   (instance), and the unnormalised geometric normal. A miss has t = +inf and prim = instance =
 *   VF_INVALID_ID; a hit of an approximate structure (ObjectField) has prim = VF_INVALID_ID.
 */
#ifndef VISFIELD_VISFIELD_H
#define VISFIELD_VISFIELD_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define VF_API __attribute__((visibility("default")))
#else
#define VF_API
#endif

/** The id a miss reports for prim and instance. */
#define VF_INVALID_ID 0xffffffffu

/** What a call returns. */
typedef enum vf_error {
  VF_OK = 0,                     /**< Success. */
  VF_ERROR_INVALID_ARGUMENT = 1, /**< A NULL handle or pointer, a count or id out of range, a bad spec or parameter. */
  VF_ERROR_BAD_INPUT = 2,        /**< A file or array that cannot be read or is malformed. */
  VF_ERROR_OUT_OF_MEMORY = 3,    /**< Over the memory limit (refused before allocating) or an allocation failed. */
  VF_ERROR_UNSUPPORTED = 4,      /**< The structure cannot do this (edit a structure that is not updatable). */
  VF_ERROR_INTERRUPTED = 5,      /**< Stopped by SIGINT or SIGTERM. */
  VF_ERROR_INTERNAL = 6          /**< A bug: please report the message. */
} vf_error;

typedef struct vf_scene_s* vf_scene;         /**< Meshes and objects (instances). */
typedef struct vf_structure_s* vf_structure; /**< A built structure (exact or fields) over a scene. */
typedef struct vf_field_s* vf_field;         /**< One mesh's ObjectField (object space). */

/** A ray, 32 bytes, laid out as visfield's own (so arrays of them are passed without a copy). */
typedef struct vf_ray {
  float org_x, org_y, org_z;
  float dir_x, dir_y, dir_z;
  float tmin, tmax;
} vf_ray;

/** A closest hit, 32 bytes. */
typedef struct vf_hit {
  float t, u, v;
  uint32_t prim, instance;
  float ng_x, ng_y, ng_z;
} vf_hit;

/** Rays as separate arrays (structure of arrays), `count` long; tmin and tmax may be NULL (0 and +inf). */
typedef struct vf_rays_soa {
  const float *org_x, *org_y, *org_z;
  const float *dir_x, *dir_y, *dir_z;
  const float *tmin, *tmax;
} vf_rays_soa;

/** Where closest hits go as separate arrays; any may be NULL (not wanted). */
typedef struct vf_hits_soa {
  float *t, *u, *v;
  uint32_t *prim, *instance;
  float *ng_x, *ng_y, *ng_z;
} vf_hits_soa;

/** Called on every failure with its code, message and the user pointer given with it. */
typedef void (*vf_error_callback)(vf_error code, const char* message, void* user);

/** Statistics of a built structure. */
typedef struct vf_structure_stats {
  double build_ms;        /**< Build wall time in milliseconds. */
  uint64_t memory_bytes;  /**< Bytes the structure holds. */
  uint64_t nodes, leaves, references, depth;
  int exact;              /**< 1 for an exact structure, 0 for an approximate one (fields). */
  int updatable;          /**< 1 when objects can be removed, inserted and moved after the build. */
} vf_structure_stats;

/** What an ObjectField holds. */
typedef struct vf_field_info {
  uint32_t positions, directions;
  float sphere_center[3], sphere_radius;  /**< Bounding sphere in the mesh's object space. */
  uint64_t memory_bytes;
  double build_ms;
  int has_normals;                         /**< 1 when the field has a normal field. */
} vf_field_info;

/* ----- Library ----- */

/** The library version, "MAJOR.MINOR.PATCH". Thread-safe. */
VF_API const char* vf_version(void);
/** The code of the calling thread's last failure (VF_OK when none yet). Thread-safe. */
VF_API vf_error vf_last_error(void);
/** One line describing the calling thread's last failure ("" when none); valid until its next call. */
VF_API const char* vf_last_error_message(void);
/** Sets (or, with NULL, removes) the error callback for every thread. Not to overlap with other calls. */
VF_API void vf_set_error_callback(vf_error_callback callback, void* user);
/** Worker threads for builds and queries from now on (0 = all hardware threads). */
VF_API vf_error vf_set_threads(int threads);

/* ----- Scenes ----- */

/** An empty scene (meshes and objects are added to it). */
VF_API vf_error vf_scene_create(vf_scene* out);
/** A scene read from a mesh file (OBJ, PLY, glTF/GLB, STL...), a scene .json or "builtin:NAME". */
VF_API vf_error vf_scene_load(const char* path, vf_scene* out);
/** Adds a mesh: `vertex_count` xyz triples and `triangle_count` vertex-index triples, copied. The
 * mesh index (0, 1, ...) goes to *mesh. Refused: indices out of range, NaN/inf or coordinates beyond 1e12. */
VF_API vf_error vf_scene_add_mesh(vf_scene scene, const float* vertices, size_t vertex_count, const uint32_t* indices,
                                  size_t triangle_count, uint32_t* mesh);
/** Adds an object of mesh `mesh` placed by the row-major 3x4 matrix [s*R | t] (rotation R,
 * uniform scale s > 0, translation t; NULL = identity). Its id goes to *id; ids are never reused. */
VF_API vf_error vf_scene_add_instance(vf_scene scene, uint32_t mesh, const float* transform_3x4, uint32_t* id);
/** Places object `id` by a 3x4 matrix as above. */
VF_API vf_error vf_scene_set_transform(vf_scene scene, uint32_t id, const float* transform_3x4);
/** Removes object `id`. */
VF_API vf_error vf_scene_remove_instance(vf_scene scene, uint32_t id);
/** Counts: meshes, objects, and triangles over all objects (any pointer may be NULL). */
VF_API vf_error vf_scene_counts(vf_scene scene, size_t* meshes, size_t* objects, size_t* triangles);
/** World bounds of the objects: lower[3] and upper[3]. */
VF_API vf_error vf_scene_bounds(vf_scene scene, float lower[3], float upper[3]);
/** Frees a scene (structures built from it stay valid). VF_ERROR_INVALID_ARGUMENT for a handle that is not live. */
VF_API vf_error vf_scene_release(vf_scene scene);

/* ----- Structures ----- */

/** Builds the structure `spec` names over the scene as it is now: "bvh", "kdtree:kt=10", "beam:dirs=513",
 * "field:positions=4226,directions=32", ... (NULL = "bvh"; `visfield structures` lists them all).
 * The build's memory estimate is checked first (VF_ERROR_OUT_OF_MEMORY with the estimate). */
VF_API vf_error vf_structure_build(vf_scene scene, const char* spec, vf_structure* out);
/** The spec as resolved ("bvh:levels=1"); valid until the structure is released ("" for a handle that is not live). */
VF_API const char* vf_structure_spec(vf_structure structure);
/** Build statistics. */
VF_API vf_error vf_structure_get_stats(vf_structure structure, vf_structure_stats* out);
/** Frees a structure. VF_ERROR_INVALID_ARGUMENT for a handle that is not live (released twice, forged). */
VF_API vf_error vf_structure_release(vf_structure structure);

/** Closest hits of `count` rays (arrays of structures). Thread-safe; parallel. */
VF_API vf_error vf_intersect(vf_structure structure, const vf_ray* rays, size_t count, vf_hit* hits);
/** occluded[i] = 1 when rays[i] hits anything in (tmin, tmax], else 0. Thread-safe; parallel. */
VF_API vf_error vf_occluded(vf_structure structure, const vf_ray* rays, size_t count, uint8_t* occluded);
/** vf_intersect for structure-of-arrays rays and hits. */
VF_API vf_error vf_intersect_soa(vf_structure structure, const vf_rays_soa* rays, size_t count, const vf_hits_soa* hits);
/** vf_occluded for structure-of-arrays rays. */
VF_API vf_error vf_occluded_soa(vf_structure structure, const vf_rays_soa* rays, size_t count, uint8_t* occluded);

/* Updates of an updatable structure (BeamField; also two-level structures): stage edits, then
 * commit. Until the commit, queries answer for the last committed state; after it, exactly as a
 * fresh build of the edited scene. Others return VF_ERROR_UNSUPPORTED. */

/** Stages removing object `id`. */
VF_API vf_error vf_structure_remove(vf_structure structure, uint32_t id);
/** Stages inserting object `id` of `scene` (mesh and transform as they are now in the scene). */
VF_API vf_error vf_structure_insert(vf_structure structure, vf_scene scene, uint32_t id);
/** Stages moving object `id` to the 3x4 matrix `transform_3x4`. */
VF_API vf_error vf_structure_move(vf_structure structure, uint32_t id, const float* transform_3x4);
/** Applies the staged edits. */
VF_API vf_error vf_structure_commit(vf_structure structure);

/* ----- ObjectFields (approximate, per mesh, object space) ----- */

/** Precomputes the field of mesh `mesh` of `scene`. `params`: "positions=4226,directions=32,mapping=concentric,
 * storage=u8,normals=none,bilinear=0,blend=0,through=1" or any subset (NULL = defaults). */
VF_API vf_error vf_field_build(vf_scene scene, uint32_t mesh, const char* params, vf_field* out);
/** Reads a .vfield file made for mesh `mesh` of `scene` (refused when made for another mesh). */
VF_API vf_error vf_field_load(const char* path, vf_scene scene, uint32_t mesh, vf_field* out);
/** Writes the field to `path` atomically (no partial file on failure). */
VF_API vf_error vf_field_save(vf_field field, const char* path);
/** What the field holds. */
VF_API vf_error vf_field_get_info(vf_field field, vf_field_info* out);
/** Approximate closest hits of object-space rays: t, a normal where the field has a normal field, prim = VF_INVALID_ID, instance = 0. */
VF_API vf_error vf_field_intersect(vf_field field, const vf_ray* rays, size_t count, vf_hit* hits);
/** Approximate occlusion of object-space rays. */
VF_API vf_error vf_field_occluded(vf_field field, const vf_ray* rays, size_t count, uint8_t* occluded);
/** Frees a field. VF_ERROR_INVALID_ARGUMENT for a handle that is not live. */
VF_API vf_error vf_field_release(vf_field field);

#ifdef __cplusplus
}
#endif

#endif /* VISFIELD_VISFIELD_H */
