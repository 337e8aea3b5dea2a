#pragma once
/// \file Device copies of the GPU layouts (include/visfield/gpu): the exact BVH, and a scene's packed
/// fields (one copy of the packed buffer, the tables rebased to it, the objects, the exact part).
/// Immutable after upload; the views hold device addresses for the kernels. Move-only.

#include <cstddef>
#include <cstdint>

#include "visfield/cuda/device_buffer.hpp"
#include "visfield/gpu/field_scene_view.hpp"
#include "visfield/gpu/gpu_bvh.hpp"
#include "visfield/gpu/packed_scene.hpp"

namespace vf::cuda {

/// A GpuBvh in device memory.
class DeviceBvh {
 public:
  DeviceBvh() = default;
  /// Copies the four arrays of `bvh` to the device. Throws vf::Error (no device, no memory).
  static DeviceBvh upload(const gpu::GpuBvh& bvh);
  /// Device addresses for the kernels.
  gpu::BvhView view() const;
  /// Device bytes held.
  std::size_t bytes() const { return nodes_.bytes() + triangles_.bytes() + prim_.bytes() + instance_.bytes(); }

 private:
  DeviceArray<gpu::WideNode> nodes_;
  DeviceArray<gpu::WideTriangle> triangles_;
  DeviceArray<std::uint32_t> prim_, instance_;
  unsigned int stack_bound_ = 0;
};

/// Which kernels the queries of a DeviceFieldScene run.
enum class FieldKernels : unsigned char {
  fitted,   ///< Those compiled for the form every field has (gpu::FieldForm), where they share one; else generic.
  generic,  ///< Those that read every choice of the tables at run time (what fitting gains is measured against them).
};

/// A PackedFieldScene in device memory: the packed tables in one cudaMemcpy, their FieldTables
/// rebased to that copy, the objects and the exact meshes' BVH.
class DeviceFieldScene {
 public:
  DeviceFieldScene() = default;
  /// Copies `packed` to the device, its queries to run `kernels`. Throws vf::Error (no device, no memory).
  static DeviceFieldScene upload(const gpu::PackedFieldScene& packed, FieldKernels kernels = FieldKernels::fitted);
  /// Device addresses for the kernels.
  gpu::FieldSceneView view() const;
  /// Device bytes held.
  std::size_t bytes() const {
    return buffer_.bytes() + tables_.bytes() + objects_.bytes() + exact_.bytes() + tree_nodes_.bytes() + tree_items_.bytes();
  }

 private:
  DeviceBuffer buffer_;
  DeviceArray<field::FieldTables> tables_;
  DeviceArray<gpu::FieldObject> objects_;
  DeviceBvh exact_;
  gpu::FieldForm form_ = gpu::FieldForm::any;
  DeviceArray<gpu::ObjectNode> tree_nodes_;
  DeviceArray<unsigned int> tree_items_;
};

}  // namespace vf::cuda
