#pragma once
// Private to the C API: what its opaque handles hold and the table that hands them out, the errors
// it tells apart, and the conversions from C arguments.

#include <cmath>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <vector>

#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/scene.hpp"
#include "visfield/core/transform.hpp"
#include "visfield/field/object_field.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/registry/structure_queries.hpp"

namespace vf::capi {

/// What a scene handle holds: the scene, shared so that loading and building never copy it, and the
/// lock that keeps its edits (exclusive) apart from what reads it (shared: builds, counts, bounds).
struct SceneObject {
  std::shared_ptr<Scene> scene;
  mutable std::shared_mutex lock;
};

/// What a structure handle holds: the built structure and its resolved spec (no scene pointer), and
/// the lock that keeps queries (shared) apart from edits and commits (exclusive): a query that
/// overlaps a commit waits for it and sees the structure before or after it, never between.
struct StructureObject {
  StructureObject(AnyStructure built, std::string spec) : structure(std::move(built)), resolved(std::move(spec)) {}
  AnyStructure structure;
  std::string resolved;
  mutable std::shared_mutex lock;
};

/// What a field handle holds: one mesh's ObjectField and the hash of that mesh (what a saved file records).
struct FieldObject {
  field::ObjectField field;
  std::uint64_t mesh_hash = 0;
};

/// A caller's mistake (VF_ERROR_INVALID_ARGUMENT).
class ArgumentError : public Error {
 public:
  explicit ArgumentError(const std::string& message) : Error(message) {}
};

/// The live handles of one kind. A handle is a number, never an address: its kind (8 bits), the
/// generation of its slot (24 bits) and the slot (32 bits). Looking up a released handle (its slot's
/// generation has moved on), a forged one (no such slot, another kind) or NULL throws ArgumentError,
/// so the C caller's mistakes are errors and never touch freed memory. Lookups hand out a shared_ptr:
/// an object released on another thread lives until the calls using it return. Thread-safe.
template <class T>
class HandleTable {
 public:
  /// `kind`: the tag that tells this table's handles from the others'; `what`: "scene", "structure"...
  HandleTable(std::uint8_t kind, const char* what) : kind_(kind), what_(what) {}

  /// A new handle owning `object`.
  std::uintptr_t add(std::shared_ptr<T> object) {
    const std::lock_guard<std::mutex> guard(mutex_);
    std::uint32_t slot = 0;
    if (free_.empty()) {
      slot = static_cast<std::uint32_t>(slots_.size());
      slots_.push_back(Slot{});
    } else {
      slot = free_.front();
      free_.pop_front();  // the oldest free slot: a stale handle waits longest for its slot to return
    }
    slots_[slot].object = std::move(object);
    return encode(slot, slots_[slot].generation);
  }

  /// The object of a live handle.
  std::shared_ptr<T> get(std::uintptr_t handle) const {
    const std::lock_guard<std::mutex> guard(mutex_);
    return slots_[find(handle)].object;
  }

  /// Releases a live handle; the object goes when the last call using it returns.
  void release(std::uintptr_t handle) {
    std::shared_ptr<T> last;  // freed after the table's lock is let go
    const std::lock_guard<std::mutex> guard(mutex_);
    const std::uint32_t slot = find(handle);
    last = std::move(slots_[slot].object);
    slots_[slot].generation = (slots_[slot].generation + 1) & kGenerationMask;
    free_.push_back(slot);
  }

 private:
  static constexpr std::uint32_t kGenerationMask = (1u << 24) - 1;
  struct Slot {
    std::uint32_t generation = 0;
    std::shared_ptr<T> object;
  };

  std::uintptr_t encode(std::uint32_t slot, std::uint32_t generation) const {
    return (static_cast<std::uintptr_t>(kind_) << 56) | (static_cast<std::uintptr_t>(generation) << 32) | slot;
  }

  // The slot of a live handle of this kind; ArgumentError for anything else.
  std::uint32_t find(std::uintptr_t handle) const;

  std::uint8_t kind_;
  const char* what_;
  mutable std::mutex mutex_;
  std::vector<Slot> slots_;
  std::deque<std::uint32_t> free_;
};

static_assert(sizeof(std::uintptr_t) == 8, "handles pack a kind, a generation and a slot into 64 bits");

/// Rays converted per step where a query needs its own buffer (2 MiB of rays).
inline constexpr std::size_t kChunk = std::size_t{1} << 16;

template <class T>
std::uint32_t HandleTable<T>::find(std::uintptr_t handle) const {
  if (handle == 0) throw ArgumentError(std::string(what_) + " is NULL");
  const auto slot = static_cast<std::uint32_t>(handle & 0xffffffffu);
  const auto generation = static_cast<std::uint32_t>((handle >> 32) & kGenerationMask);
  if ((handle >> 56) != kind_ || slot >= slots_.size() || slots_[slot].generation != generation || !slots_[slot].object)
    throw ArgumentError(std::string(what_) + ": not a live " + what_ + " handle (released, never made, or another kind of handle)");
  return slot;
}

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

/// Runs `edit` on the handle's structure under its exclusive lock: UnsupportedError when it cannot
/// be edited, ArgumentError for a refused edit (an unknown id).
template <class Edit>
void edit_object(StructureObject& handle, Edit&& edit) {
  if (!is_updatable(handle.structure))
    throw UnsupportedError("the structure " + handle.resolved + " cannot be edited after its build (BeamField and two-level structures can)");
  const std::unique_lock<std::shared_mutex> exclusive(handle.lock);
  as_argument_error([&] { edit(handle.structure); });
}

}  // namespace vf::capi
