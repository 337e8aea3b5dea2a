#pragma once
/// \file A FieldScene packed for a GPU, in host memory: every field's tables in ONE contiguous byte
/// buffer (so a device copy is one memcpy, and FieldSlot::rebase turns offsets into pointers
/// there), the field objects with their inverse transforms, and the exact meshes as a GpuBvh. The
/// host queries run the device's code (field_scene_view.hpp) over this copy and equal FieldScene's
/// answers bit for bit (tests/unit/gpu).

#include <cstddef>
#include <cstdint>
#include <vector>

#include "visfield/core/scene.hpp"
#include "visfield/field/field_scene.hpp"
#include "visfield/gpu/field_scene_view.hpp"
#include "visfield/gpu/gpu_bvh.hpp"

namespace vf::gpu {

/// Where each table begins in the packed buffer: every table starts on this many bytes.
inline constexpr std::size_t kTableAlignment = 256;

/// Immutable; queries are const and thread-safe. Movable.
class PackedFieldScene {
 public:
  /// Packs `fields`, built over `scene` (the same scene, unchanged): each mesh's field once, the
  /// objects of field meshes in id order (FieldScene's order), and a GpuBvh over the objects of the
  /// meshes FieldScene keeps exact. O(table bytes + exact triangles log).
  static PackedFieldScene pack(const Scene& scene, const field::FieldScene& fields);
  PackedFieldScene(PackedFieldScene&&) noexcept = default;
  PackedFieldScene& operator=(PackedFieldScene&&) noexcept = default;
  PackedFieldScene(const PackedFieldScene&) = delete;  // the host view points into this copy's buffer
  PackedFieldScene& operator=(const PackedFieldScene&) = delete;

  /// The packed tables; FieldSlot offsets point into it.
  const std::vector<unsigned char>& buffer() const { return buffer_; }
  /// One slot per field (each mesh with a field once).
  const std::vector<FieldSlot>& slots() const { return slots_; }
  /// The field objects in FieldScene's order.
  const std::vector<FieldObject>& objects() const { return objects_; }
  /// The exact meshes' BVH (empty when every object has a field).
  const GpuBvh& exact() const { return exact_; }
  /// The slots rebased to `base` (where a copy of buffer() lives), one FieldTables per slot.
  std::vector<field::FieldTables> tables_at(const unsigned char* base) const;

  /// The form every field has (FieldForm::defaults when each one has ObjectFieldConfig's default
  /// choices, else FieldForm::any): the form the queries are compiled for, here and on a device.
  FieldForm form() const { return form_; }
  /// The tree over the objects, where the FieldScene culls through one (FieldScene::uses_tree()), else
  /// empty: its nodes, root first.
  const std::vector<ObjectNode>& tree_nodes() const { return tree_nodes_; }
  /// The objects' indices, leaf after leaf.
  const std::vector<unsigned int>& tree_items() const { return tree_items_; }
  /// The tree of this host copy.
  ObjectTreeView tree_view() const {
    return {tree_nodes_.data(), tree_items_.data(), static_cast<unsigned int>(tree_nodes_.size())};
  }
  /// The view of this host copy; `tables` must be tables_at(buffer().data()) and outlive the view.
  FieldSceneView view(const std::vector<field::FieldTables>& tables) const;
  /// FieldScene::intersect on the packed copy (by field_scene_view.hpp's code).
  Hit intersect(const Ray& ray) const;
  /// FieldScene::occluded on the packed copy (by field_scene_view.hpp's code).
  bool occluded(const Ray& ray) const;

  /// Bytes of the packed buffer, the slots, the objects and the exact BVH: what a device copy takes.
  std::size_t device_bytes() const;

 private:
  PackedFieldScene() = default;
  std::vector<unsigned char> buffer_;
  std::vector<FieldSlot> slots_;
  std::vector<FieldObject> objects_;
  GpuBvh exact_;
  std::vector<field::FieldTables> host_tables_;  // slots rebased to buffer_.data()
  FieldForm form_ = FieldForm::any;
  std::vector<ObjectNode> tree_nodes_;
  std::vector<unsigned int> tree_items_;
};

}  // namespace vf::gpu
