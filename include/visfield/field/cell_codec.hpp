#pragma once
/// \file How an ObjectField cell stores the distance from the bounding sphere to the first hit along
/// its direction (displacement-field paper, "Storage"); host and device, no STL. A distance is
/// first normalised by the sphere's diameter 2R to x in [0, 1]; a miss has its own code.
///  - u8:  round(254·x) in 0..254, 255 = miss (error at most 2R/508, the paper's 1 byte per ray);
///  - u16: round(65534·x) in 0..65534, 65535 = miss;
///  - f32: x itself, a miss is +infinity;
///  - bit: 1 = hit, 0 = miss; the distance of a hit is the average of the hit distances of its
///    positional sample (the paper's 1-bit variant, Figure 7), kept beside the table.

#include "visfield/core/host_device.hpp"

namespace vf::field {

/// Cell encodings. The values are stored in field files.
enum class CellStorage : unsigned char { u8 = 0, u16 = 1, f32 = 2, bit = 3 };

/// Number of encodings (numbered 0 .. kStorageCount − 1).
inline constexpr int kStorageCount = 4;

/// Bits one cell takes in a table of `storage` (8, 16, 32 or 1).
VF_HOST_DEVICE inline int cell_bits(CellStorage storage) {
  switch (storage) {
    case CellStorage::u8: return 8;
    case CellStorage::u16: return 16;
    case CellStorage::f32: return 32;
    case CellStorage::bit:
    default: return 1;
  }
}

/// The largest code of a hit for the integer encodings (254, 65534); the next code is the miss.
VF_HOST_DEVICE inline unsigned max_hit_code(CellStorage storage) { return storage == CellStorage::u8 ? 254u : 65534u; }

/// The integer code of normalised distance `x` (clamped to [0, 1]), or of a miss when `hit` is
/// false, for u8 and u16.
VF_HOST_DEVICE inline unsigned encode_quantized(CellStorage storage, bool hit, float x) {
  const unsigned top = max_hit_code(storage);
  if (!hit) return top + 1;
  const float clamped = hd::clamp(x, 0.0f, 1.0f);
  return static_cast<unsigned>(clamped * static_cast<float>(top) + 0.5f);
}

/// Whether integer `code` of a u8 or u16 table is a hit.
VF_HOST_DEVICE inline bool quantized_is_hit(CellStorage storage, unsigned code) { return code <= max_hit_code(storage); }

/// The normalised distance of hit code `code` of a u8 or u16 table: the code times the float
/// reciprocal of the top code (within 6e-8 of the quotient, exact at 0 and at the top; a product
/// is what the SIMD and CUDA lookups can afford).
VF_HOST_DEVICE inline float decode_quantized(CellStorage storage, unsigned code) {
  return static_cast<float>(code) * (storage == CellStorage::u8 ? 1.0f / 254.0f : 1.0f / 65534.0f);
}

}  // namespace vf::field
