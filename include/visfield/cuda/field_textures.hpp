#pragma once
/// \file The texture variant of the field lookup, as the GPU paper stored its fields: each field's
/// u8 cells in a 3D texture (i, j + N·(sample mod k), sample div k), read with point sampling, to be
/// measured against the plain buffer. For fields of u8 cells, nearest lookups and no normal field
/// (the paper's); the answers equal the buffer's bit for bit (tests/cuda).

#include <cstddef>
#include <cstdint>
#include <vector>

#include "visfield/cuda/device_scene.hpp"
#include "visfield/cuda/kernels.hpp"

namespace vf::cuda {

/// One 3D texture object per field of a packed scene. Move-only; frees its arrays.
class FieldTextures {
 public:
  FieldTextures() = default;
  /// Textures of every field of `packed`. Throws vf::Error when a field is not u8 with nearest
  /// lookups and no normals, or on a CUDA failure.
  static FieldTextures create(const gpu::PackedFieldScene& packed);
  FieldTextures(FieldTextures&& other) noexcept;
  FieldTextures& operator=(FieldTextures&& other) noexcept;
  FieldTextures(const FieldTextures&) = delete;
  FieldTextures& operator=(const FieldTextures&) = delete;
  ~FieldTextures();

  /// The texture objects (cudaTextureObject_t values), one per field, in device memory.
  const std::uint64_t* device_objects() const { return objects_.data(); }
  /// Samples stacked along y per texture slice, per field.
  const std::uint32_t* device_stacks() const { return stacks_.data(); }
  /// Bytes of the texture arrays.
  std::size_t bytes() const { return bytes_; }

 private:
  void release();
  std::vector<std::uint64_t> textures_;  // cudaTextureObject_t
  std::vector<void*> arrays_;            // cudaArray_t
  DeviceArray<std::uint64_t> objects_;
  DeviceArray<std::uint32_t> stacks_;
  std::size_t bytes_ = 0;
};

/// ambient_occlusion() with every field cell read through `textures` instead of the packed buffer:
/// the same rays, the same answers.
void ambient_occlusion(const DeviceFieldScene& scene, const FieldTextures& textures, const gpu::SurfaceFrame* points, std::size_t n,
                       const AoParams& params, std::uint32_t* unoccluded);

}  // namespace vf::cuda
