#pragma once
/// \file Indexed triangle meshes.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "visfield/core/bounds.hpp"
#include "visfield/core/vec.hpp"

namespace vf {

/// Vertex indices of one triangle.
using TriangleIndices = std::array<std::uint32_t, 3>;

/// How an approximate occluder (`--occluder field`) represents a mesh's objects.
enum class MeshOccluder : std::uint8_t {
  automatic,  ///< The structure decides (FieldScene: a field).
  exact,      ///< Exact geometry always: receivers such as grounds and walls, whose fields would be coarse.
  field,      ///< A precomputed field (ObjectField).
};

/// A triangle mesh: shared vertex positions plus index triples, in the mesh's own (object) space.
/// Owns its arrays; immutable once handed to a Scene. Not thread-safe to mutate.
struct TriangleMesh {
  std::string name;                          ///< For messages: usually the source file name.
  std::vector<Vec3f> positions;              ///< Vertex positions.
  std::vector<TriangleIndices> triangles;    ///< Index triples into positions.
  std::vector<std::uint32_t> material_ids;   ///< Per triangle index into Scene::materials, or empty (all use material 0).
  MeshOccluder occluder = MeshOccluder::automatic;  ///< Scene JSON "occluder": "exact" | "field".
  std::string field_file;  ///< Scene JSON "field" (or its "path"): the mesh's .vfield file, read when it exists, written when not ("" = none).
  std::string field_params;  ///< Scene JSON "field" object's table parameters as "key=value,..." (field_params.hpp; "" = none).

  /// Bounds of the referenced and unreferenced vertices alike; O(V).
  Bounds3f bounds() const;
  /// Number of triangles with exactly zero area (coincident or collinear corners); O(T).
  std::size_t count_degenerate() const;
  /// Number of triangles with the same three vertex indices (in any order) as an earlier triangle.
  /// They are kept: the surface is the same, and an exact query returns one of the copies. O(T log T)
  /// time (parallel), 24 bytes per triangle of scratch; polls check_interrupt().
  std::size_t count_duplicates() const;
  /// Bytes held by the arrays.
  std::size_t memory_bytes() const;
};

/// True when triangle (a, b, c) has zero area in float arithmetic (degenerate, kept out of accelerators).
bool is_degenerate_triangle(const Vec3f& a, const Vec3f& b, const Vec3f& c);

/// Largest coordinate magnitude visfield accepts, in object and in world space. The watertight
/// triangle test multiplies three coordinate differences; below 1e12 those products stay inside
/// float range (3.4e38) with room to spare, so no hit is lost to overflow.
inline constexpr float kMaxCoordinate = 1e12f;

/// Checks a mesh for NaN/Inf positions or positions beyond ±kMaxCoordinate, out-of-range indices and
/// emptiness; throws vf::Error naming `what` (a file name) and the first problem found. O(V + T).
void validate_mesh(const TriangleMesh& mesh, const std::string& what);

}  // namespace vf
