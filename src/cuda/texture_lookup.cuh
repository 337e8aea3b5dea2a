#pragma once
// The field query with its cells read from a 3D texture (private to the cuda module; the texture
// variant that field_textures.hpp measures): field/field_query.hpp's steps for u8 cells and nearest
// lookups, the byte read replaced by a point-sampled tex3D. tests/cuda checks it against the buffer
// bit for bit.

#include <cuda_runtime.h>

#include "visfield/field/field_query.hpp"
#include "visfield/gpu/field_scene_view.hpp"

namespace vf::cuda::detail {

/// Cell (i, j) of `sample` from the texture: x = i, y = j + N·(sample mod stack), z = sample div stack.
__device__ inline field::FieldAnswer texture_cell(cudaTextureObject_t tex, unsigned int stack, int sample, int i, int j, int n) {
  const unsigned int s = static_cast<unsigned int>(sample);
  const unsigned int code = tex3D<unsigned char>(tex, static_cast<float>(i) + 0.5f,
                                                 static_cast<float>(j + n * static_cast<int>(s % stack)) + 0.5f,
                                                 static_cast<float>(s / stack) + 0.5f);
  field::FieldAnswer a;
  a.hit = field::quantized_is_hit(field::CellStorage::u8, code);
  if (!a.hit) return {};
  a.t = field::decode_quantized(field::CellStorage::u8, code);
  return a;
}

/// field::trace_field for u8 cells and nearest lookups, its cell read through `tex`: the same steps
/// (sphere_visit, the nearest sample, sample_read, square_of, place_answer), only the byte read differs.
__device__ inline field::FieldAnswer trace_field_texture(const field::FieldTables& f, cudaTextureObject_t tex, unsigned int stack,
                                                         const hd::Vec3<float>& org, const hd::Vec3<float>& dir, float tmin, float tmax) {
  field::SphereVisit v;
  if (!field::sphere_visit(f, org, dir, tmin, tmax, v)) return {};
  const int sample = field::heaviest_corner_position(v.point, f.lattice_n);
  const field::SampleRead r = field::sample_read(f, v, sample);
  float s, t;
  field::square_of(f, r.frame, r.q, s, t);
  const field::FieldAnswer a =
      texture_cell(tex, stack, sample, field::cell_of(s, f.directions), field::cell_of(t, f.directions), f.directions);
  return field::place_answer(f, v, field::shifted_answer(r, a));
}

/// gpu::occluded (fields, then the exact part) with the fields' cells read through textures.
template <int Capacity>
__device__ inline bool occluded_texture(const gpu::FieldSceneView& scene, const unsigned long long* textures, const unsigned int* stacks,
                                        const Ray& ray) {
  const auto hit = [&](const gpu::FieldObject& o) {
    const Ray local = gpu::to_object(o.to_object, ray);
    return trace_field_texture(scene.fields[o.field], textures[o.field], stacks[o.field], {local.org.x, local.org.y, local.org.z},
                               {local.dir.x, local.dir.y, local.dir.z}, ray.tmin, ray.tmax)
        .hit;
  };
  if (gpu::some_object(scene, ray, hit)) return true;
  return gpu::occluded<Capacity>(scene.exact, ray);
}

}  // namespace vf::cuda::detail
