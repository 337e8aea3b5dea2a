#pragma once
// The field query with its cells read from a 3D texture (private to the cuda module; the texture
// variant that field_textures.hpp measures): trace_field() and read_direction() of
// field/field_query.hpp for u8 cells and nearest lookups, every operation and order kept, only the
// byte read replaced by a point-sampled tex3D. tests/cuda checks it against the buffer bit for bit.

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

/// field::trace_field for u8 cells and nearest lookups, reading cells through `tex`.
__device__ inline field::FieldAnswer trace_field_texture(const field::FieldTables& f, cudaTextureObject_t tex, unsigned int stack,
                                                         const hd::Vec3<float>& org, const hd::Vec3<float>& dir, float tmin, float tmax) {
  const float len = hd::sqrt(hd::dot(dir, dir));
  const float inv = 1.0f / len;
  const hd::Vec3<float> d{dir.x * inv, dir.y * inv, dir.z * inv};
  const float s_min = tmin * len, s_max = tmax * len;
  const float diameter = 2.0f * f.radius;
  const hd::Vec3<float> oc{org.x - f.centre.x, org.y - f.centre.y, org.z - f.centre.z};
  const float b = hd::dot(oc, d), c = hd::dot(oc, oc) - f.radius * f.radius;
  const float disc = b * b - c;
  if (!(disc >= 0.0f)) return {};
  const float root = hd::sqrt(disc);
  const float s_enter = -b - root, s_exit = -b + root;
  const bool inside = !(c > 0.0f);
  if (!inside && s_enter < 0.0f) return {};
  const float s_at = inside ? s_exit : s_enter;
  hd::Vec3<float> e{oc.x + d.x * s_at, oc.y + d.y * s_at, oc.z + d.z * s_at};
  const float e_inv = inside ? 1.0f / f.radius : 1.0f / hd::sqrt(hd::dot(e, e));
  e = {e.x * e_inv, e.y * e_inv, e.z * e_inv};
  const hd::Vec3<float> dd = inside ? hd::Vec3<float>{-d.x, -d.y, -d.z} : d;
  // read_at (nearest) and read_direction (nearest), the cell from the texture.
  const int sample = field::nearest_position(e, f.lattice_n, f.upper);
  const hd::Vec3<float> w = field::sample_inward(f, sample);
  const OrthonormalBasis<float> basis = orthonormal_basis(w);
  hd::Vec3<float> local{hd::dot(basis.u, dd), hd::dot(basis.v, dd), hd::dot(w, dd)};
  if (local.z < 0.0f) {
    const float planar = hd::sqrt(local.x * local.x + local.y * local.y);
    local = planar > 0.0f ? hd::Vec3<float>{local.x / planar, local.y / planar, 0.0f} : hd::Vec3<float>{0.0f, 0.0f, 1.0f};
  }
  float s, t;
  field::direction_to_square(f.mapping, local, s, t);
  field::FieldAnswer a = texture_cell(tex, stack, sample, field::cell_of(s, f.directions), field::cell_of(t, f.directions), f.directions);
  if (!a.hit) return {};
  const float s_hit = inside ? s_exit - a.t * diameter : s_enter + a.t * diameter;
  if (inside && !(s_hit > f.self_offset * diameter)) return {};
  if (!(s_hit >= s_min && s_hit <= s_max)) return {};
  a.t = s_hit * inv;
  return a;
}

/// gpu::occluded (fields, then the exact part) with the fields' cells read through textures.
__device__ inline bool occluded_texture(const gpu::FieldSceneView& scene, const unsigned long long* textures, const unsigned int* stacks,
                                        const Ray& ray) {
  for (unsigned int k = 0; k < scene.object_count; ++k) {
    const gpu::FieldObject& o = scene.objects[k];
    if (scene.object_count > 1 && !gpu::may_meet(o, ray)) continue;
    const Ray local = gpu::to_object(o.to_object, ray);
    if (trace_field_texture(scene.fields[o.field], textures[o.field], stacks[o.field], {local.org.x, local.org.y, local.org.z},
                            {local.dir.x, local.dir.y, local.dir.z}, ray.tmin, ray.tmax)
            .hit)
      return true;
  }
  return gpu::occluded(scene.exact, ray);
}

}  // namespace vf::cuda::detail
