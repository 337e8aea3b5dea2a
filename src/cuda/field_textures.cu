// The texture variant of the field lookup: each u8 field's cells in a cudaArray 3D texture.

#include "visfield/cuda/field_textures.hpp"

#include <algorithm>
#include <cstring>
#include <string>
#include <utility>

#include "launch.cuh"
#include "texture_lookup.cuh"
#include "visfield/core/error.hpp"
#include "visfield/gpu/ray_generation.hpp"
#include "visfield/gpu/texture_layout.hpp"

namespace vf::cuda {
namespace {

/// Device 0's 3D texture limits.
gpu::Texture3DLimits texture_limits() {
  int width = 0, height = 0, depth = 0;
  check(cudaDeviceGetAttribute(&width, cudaDevAttrMaxTexture3DWidth, 0), "cudaDeviceGetAttribute");
  check(cudaDeviceGetAttribute(&height, cudaDevAttrMaxTexture3DHeight, 0), "cudaDeviceGetAttribute");
  check(cudaDeviceGetAttribute(&depth, cudaDevAttrMaxTexture3DDepth, 0), "cudaDeviceGetAttribute");
  return {static_cast<std::uint32_t>(width), static_cast<std::uint32_t>(height), static_cast<std::uint32_t>(depth)};
}

template <int Capacity, bool kStreams>
__global__ void __launch_bounds__(detail::kBlockThreads, detail::kMinBlocksPerSm)
    ao_texture_kernel(gpu::FieldSceneView view, const unsigned long long* textures, const unsigned int* stacks,
                                  const gpu::SurfaceFrame* points, std::size_t n, AoParams p, std::uint32_t* unoccluded) {
  const std::size_t rays = static_cast<std::size_t>(p.rays_per_point), total = n * rays;
  for (std::size_t idx = detail::first_index(); idx < total; idx += detail::index_step()) {
    std::size_t i, k;
    detail::divide(idx, rays, i, k);
    const Ray ray = detail::ao_ray_of<kStreams>(points, i, k, p);
    detail::add_vote(unoccluded, i, !detail::occluded_texture<Capacity>(view, textures, stacks, ray));
  }
}

}  // namespace

FieldTextures FieldTextures::create(const gpu::PackedFieldScene& packed) {
  require_device();
  const gpu::Texture3DLimits limits = texture_limits();
  FieldTextures out;
  std::vector<std::uint32_t> stacks;
  for (std::size_t f = 0; f < packed.slots().size(); ++f) {
    const gpu::FieldSlot& slot = packed.slots()[f];
    const field::FieldTables& t = slot.tables;
    if (t.storage != field::CellStorage::u8 || t.normals != field::NormalStorage::none ||
        t.direction_lookup != field::DirectionLookup::nearest || t.position_lookup != field::PositionLookup::nearest)
      throw Error("field textures: field " + std::to_string(f) + " is not u8 cells with nearest lookups and no normals");
    const unsigned int n = static_cast<unsigned int>(t.directions);
    if (t.cell_stride != static_cast<unsigned long long>(n) * n) throw Error("field textures: field " + std::to_string(f) + " has padded cell tables");
    const unsigned int positions = 2u * static_cast<unsigned int>(t.upper_count);
    const gpu::FieldTextureShape shape = gpu::field_texture_shape(positions, n, limits);
    const unsigned int stack = shape.stack, depth = shape.depth;
    // The table is sample-major with N*N bytes a sample, which is already slice z = s / stack,
    // row j + N*(s mod stack); the last slice is padded with misses.
    std::vector<unsigned char> cells(static_cast<std::size_t>(depth) * stack * n * n, 255);
    std::memcpy(cells.data(), packed.buffer().data() + slot.cells, static_cast<std::size_t>(positions) * n * n);
    const cudaChannelFormatDesc format = cudaCreateChannelDesc<unsigned char>();
    const cudaExtent extent = make_cudaExtent(n, n * stack, depth);
    cudaArray_t array = nullptr;
    check(cudaMalloc3DArray(&array, &format, extent), "cudaMalloc3DArray");
    out.arrays_.push_back(array);
    out.bytes_ += cells.size();
    cudaMemcpy3DParms copy{};
    copy.srcPtr = make_cudaPitchedPtr(cells.data(), n, n, n * stack);
    copy.dstArray = array;
    copy.extent = extent;
    copy.kind = cudaMemcpyHostToDevice;
    check(cudaMemcpy3D(&copy), "cudaMemcpy3D");
    cudaResourceDesc resource{};
    resource.resType = cudaResourceTypeArray;
    resource.res.array.array = array;
    cudaTextureDesc texture{};
    texture.addressMode[0] = texture.addressMode[1] = texture.addressMode[2] = cudaAddressModeClamp;
    texture.filterMode = cudaFilterModePoint;
    texture.readMode = cudaReadModeElementType;
    texture.normalizedCoords = 0;
    cudaTextureObject_t object = 0;
    check(cudaCreateTextureObject(&object, &resource, &texture, nullptr), "cudaCreateTextureObject");
    out.textures_.push_back(object);
    stacks.push_back(stack);
  }
  out.objects_ = DeviceArray<std::uint64_t>::from(std::span<const std::uint64_t>(out.textures_));
  out.stacks_ = DeviceArray<std::uint32_t>::from(std::span<const std::uint32_t>(stacks));
  return out;
}

FieldTextures::FieldTextures(FieldTextures&& other) noexcept
    : textures_(std::move(other.textures_)), arrays_(std::move(other.arrays_)), objects_(std::move(other.objects_)),
      stacks_(std::move(other.stacks_)), bytes_(std::exchange(other.bytes_, 0)) {
  other.textures_.clear();
  other.arrays_.clear();
}

FieldTextures& FieldTextures::operator=(FieldTextures&& other) noexcept {
  if (this != &other) {
    release();
    textures_ = std::move(other.textures_);
    arrays_ = std::move(other.arrays_);
    objects_ = std::move(other.objects_);
    stacks_ = std::move(other.stacks_);
    bytes_ = std::exchange(other.bytes_, 0);
    other.textures_.clear();
    other.arrays_.clear();
  }
  return *this;
}

FieldTextures::~FieldTextures() { release(); }

void FieldTextures::release() {
  for (const std::uint64_t t : textures_) cudaDestroyTextureObject(static_cast<cudaTextureObject_t>(t));
  for (void* a : arrays_) cudaFreeArray(static_cast<cudaArray_t>(a));
  textures_.clear();
  arrays_.clear();
}

void ambient_occlusion(const DeviceFieldScene& scene, const FieldTextures& textures, const gpu::SurfaceFrame* points, std::size_t n,
                       const AoParams& p, std::uint32_t* unoccluded) {
  if (p.rays_per_point < 1) throw Error("ambient occlusion: rays_per_point must be at least 1");
  if (n == 0) return;  // before the memset: an empty output may be a null pointer
  check(cudaMemset(unoccluded, 0, n * sizeof(std::uint32_t)), "cudaMemset");
  const std::size_t total = n * static_cast<std::size_t>(p.rays_per_point);
  const gpu::FieldSceneView view = scene.view();
  const auto* objects = reinterpret_cast<const unsigned long long*>(textures.device_objects());
  detail::with_stack_capacity(detail::stack_bound(view), [&](auto capacity) {
    detail::with_ao_keying(p, [&](auto streams) {
      detail::launch_and_finish("ambient occlusion kernel (textures)", [&] {
        ao_texture_kernel<capacity.value, streams.value><<<detail::blocks_for(total), detail::kBlockThreads>>>(
            view, objects, textures.device_stacks(), points, n, p, unoccluded);
      });
    });
  });
}

}  // namespace vf::cuda
