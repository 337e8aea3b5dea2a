#pragma once
// Private to the C API: what its opaque handles hold, the errors it tells apart, and the
// conversions from C arguments.

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>

#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/transform.hpp"
#include "visfield/field/object_field.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/registry/structure_queries.hpp"

/// A scene handle: the scene, shared so that loading and building never copy it.
struct vf_scene_s {
  std::shared_ptr<vf::Scene> scene;
};

/// A structure handle: the built structure and its resolved spec. Self-contained (no scene pointer).
struct vf_structure_s {
  vf::AnyStructure structure;
  std::string resolved;
};

/// A field handle: one mesh's ObjectField and the hash of that mesh (what a saved file records).
struct vf_field_s {
  vf::field::ObjectField field;
  std::uint64_t mesh_hash = 0;
};

namespace vf::capi {

/// The library version the C API reports.
inline constexpr const char* kVersion = VISFIELD_VERSION;

/// Rays converted per step where a query needs its own buffer (2 MiB of rays).
inline constexpr std::size_t kChunk = std::size_t{1} << 16;

/// A caller's mistake (VF_ERROR_INVALID_ARGUMENT).
class ArgumentError : public Error {
 public:
  explicit ArgumentError(const std::string& message) : Error(message) {}
};

/// A request the structure cannot serve (VF_ERROR_UNSUPPORTED).
class UnsupportedError : public Error {
 public:
  explicit UnsupportedError(const std::string& message) : Error(message) {}
};

/// Runs `body`, turning the vf::Error it throws about its arguments (unknown ids, bad specs) into an ArgumentError.
template <class Body>
void as_argument_error(Body&& body) {
  try {
    body();
  } catch (const MemoryRefused&) {
    throw;
  } catch (const Interrupted&) {
    throw;
  } catch (const ArgumentError&) {
    throw;
  } catch (const Error& e) {
    throw ArgumentError(e.what());
  }
}

/// The transform of a row-major 3x4 matrix [s·R | t] (NULL: identity). Throws ArgumentError unless
/// the 3x3 part is a rotation times a uniform scale s > 0 (to Transform::is_valid's tolerance).
inline Transform transform_from_3x4(const float* m) {
  Transform t;
  if (m == nullptr) return t;
  const double det = static_cast<double>(m[0]) * (static_cast<double>(m[5]) * m[10] - static_cast<double>(m[6]) * m[9]) -
                     static_cast<double>(m[1]) * (static_cast<double>(m[4]) * m[10] - static_cast<double>(m[6]) * m[8]) +
                     static_cast<double>(m[2]) * (static_cast<double>(m[4]) * m[9] - static_cast<double>(m[5]) * m[8]);
  if (!(det > 0.0) || !std::isfinite(det))
    throw ArgumentError("transform: the 3x3 part must be a rotation times a uniform scale > 0 (its determinant is " + std::to_string(det) + ")");
  const auto s = static_cast<float>(std::cbrt(det));
  for (int r = 0; r < 3; ++r) t.rotation.rows[static_cast<std::size_t>(r)] = Vec3f{m[4 * r] / s, m[4 * r + 1] / s, m[4 * r + 2] / s};
  t.translation = Vec3f{m[3], m[7], m[11]};
  t.scale = s;
  if (!t.is_valid())
    throw ArgumentError("transform: the 3x3 part is not a rotation times a uniform scale (no shear, no mirroring, the same scale on every axis)");
  return t;
}

/// The field parameters of "key=value,..." (NULL or "": the defaults), as `field:` specs take them.
inline field::ObjectFieldConfig field_config(const char* params) {
  field::ObjectFieldConfig config;
  as_argument_error([&] { config = field_config_from_spec(std::string("field") + (params && *params ? std::string(":") + params : ""), "params "); });
  return config;
}

/// Runs `edit` on the handle's structure: UnsupportedError when it cannot be edited, ArgumentError
/// for a refused edit (an unknown id).
template <class Edit>
void edit_object(vf_structure_s& handle, Edit&& edit) {
  if (!is_updatable(handle.structure))
    throw UnsupportedError("the structure " + handle.resolved + " cannot be edited after its build (BeamField and two-level structures can)");
  as_argument_error([&] { edit(handle.structure); });
}

}  // namespace vf::capi
