#pragma once
/// \file How an ObjectField's normal field stores the surface normal seen in each cell (the GPU
/// visibility-field paper's normal fields, for shading and reflections off field-represented
/// objects); host and device, no STL. A unit normal is folded onto the octahedron (Cigolle et al.,
/// "A Survey of Efficient Representations for Independent Unit Vectors", JCGT 2014) and its two
/// coordinates in [−1, 1] are quantised:
///  - oct16: 8 bits each (one u16 per cell; measured worst angular error 0.63°, mean 0.31°);
///  - oct32: 16 bits each (one u32 per cell; measured worst 0.0073°, mean 0.0026°, float-limited).
/// The encoder picks, of the four roundings, the code whose decoded normal is nearest (the
/// "precise" variant), so the error is the lattice's, not twice it.

#include "visfield/core/host_device.hpp"

namespace vf::field {

/// Normal-field encodings. The values are stored in field files.
enum class NormalStorage : unsigned char { none = 0, oct16 = 1, oct32 = 2 };

/// Number of encodings (numbered 0 .. kNormalStorageCount − 1).
inline constexpr int kNormalStorageCount = 3;

/// Bits one cell's normal takes (0, 16 or 32).
VF_HOST_DEVICE inline int normal_bits(NormalStorage storage) {
  return storage == NormalStorage::oct16 ? 16 : storage == NormalStorage::oct32 ? 32 : 0;
}

/// The largest code of one octahedral coordinate (255 or 65535).
VF_HOST_DEVICE inline unsigned normal_max_code(NormalStorage storage) { return storage == NormalStorage::oct16 ? 255u : 65535u; }

/// The unit normal of code `code` (first coordinate in the low half, second in the high half).
VF_HOST_DEVICE inline hd::Vec3<float> decode_normal(NormalStorage storage, unsigned code) {
  const unsigned half = storage == NormalStorage::oct16 ? 8u : 16u;
  const float top = static_cast<float>(normal_max_code(storage));
  float u = static_cast<float>(code & normal_max_code(storage)) / top * 2.0f - 1.0f;
  float v = static_cast<float>(code >> half) / top * 2.0f - 1.0f;
  const float z = 1.0f - hd::abs(u) - hd::abs(v);
  if (z < 0.0f) {
    const float fu = hd::copysign(1.0f - hd::abs(v), u), fv = hd::copysign(1.0f - hd::abs(u), v);
    u = fu;
    v = fv;
  }
  const float inv = 1.0f / hd::sqrt(u * u + v * v + z * z);
  return {u * inv, v * inv, z * inv};
}

/// The code of unit normal `n` (any non-zero length is normalised first): of the four roundings of
/// its octahedral coordinates, the one whose decoded normal has the largest cosine to `n`.
VF_HOST_DEVICE inline unsigned encode_normal(NormalStorage storage, const hd::Vec3<float>& n) {
  const float l1 = hd::abs(n.x) + hd::abs(n.y) + hd::abs(n.z);
  if (!(l1 > 0.0f)) return 0;
  float u = n.x / l1, v = n.y / l1;
  if (n.z < 0.0f) {
    const float fu = hd::copysign(1.0f - hd::abs(v), u), fv = hd::copysign(1.0f - hd::abs(u), v);
    u = fu;
    v = fv;
  }
  const unsigned half = storage == NormalStorage::oct16 ? 8u : 16u;
  const float top = static_cast<float>(normal_max_code(storage));
  const float cu = hd::clamp((u + 1.0f) * 0.5f * top, 0.0f, top), cv = hd::clamp((v + 1.0f) * 0.5f * top, 0.0f, top);
  const float inv_length = 1.0f / hd::sqrt(hd::dot(n, n));
  unsigned best = 0;
  float best_cos = -2.0f;
  for (int k = 0; k < 4; ++k) {
    const unsigned a = static_cast<unsigned>(hd::floor(cu)) + ((k & 1) && cu < top ? 1u : 0u);
    const unsigned b = static_cast<unsigned>(hd::floor(cv)) + ((k & 2) && cv < top ? 1u : 0u);
    const unsigned code = a | (b << half);
    const float c = hd::dot(decode_normal(storage, code), n) * inv_length;
    if (c > best_cos) {
      best_cos = c;
      best = code;
    }
  }
  return best;
}

}  // namespace vf::field
