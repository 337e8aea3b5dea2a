// Fuzz target: the .vfield reader. Any input must give a field or a vf::Error. Inputs whose first
// byte is odd get their checksum recomputed first, so that mutations reach the checks behind it;
// a field that parses answers a few rays, singly and as a batch (its tables may hold any codes).

#include <cstdint>
#include <string>
#include <utility>

#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/field/field_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bool limited = (vf::set_memory_limit(256.0 * (1 << 20), "the fuzz target's 256 MiB"), true);
  (void)limited;
  std::string bytes(reinterpret_cast<const char*>(data), size);
  if (size > 8 && (data[0] & 1u)) {
    bytes[0] = 'V';  // keep the signature the seeds start with
    bytes = vf::field::with_field_checksum(std::move(bytes));
  }
  try {
    const vf::field::StoredField stored = vf::field::decode_field(bytes, "fuzz.vfield");
    const vf::field::BoundingSphere& s = stored.field.sphere();
    // Rays from outside and from inside, one at a time and as a batch (the SIMD kernel's reads).
    float rows[8][18];
    for (int k = 0; k < 18; ++k) {
      const vf::Vec3f dir = vf::normalize(vf::Vec3f{k & 1 ? 1.0f : -1.0f, k & 2 ? 0.5f : -0.5f, k & 4 ? 0.25f : -0.25f});
      const vf::Vec3f org = k % 2 ? s.centre : s.centre - dir * (2.0f * s.radius);
      stored.field.trace(org, dir, 0.0f, 1e30f);
      const float values[8] = {org.x, org.y, org.z, dir.x, dir.y, dir.z, 0.0f, 1e30f};
      for (int c = 0; c < 8; ++c) rows[c][k] = values[c];
    }
    vf::field::FieldAnswer answers[18];
    stored.field.trace_batch({rows[0], rows[1], rows[2], rows[3], rows[4], rows[5], rows[6], rows[7], 18}, answers);
  } catch (const vf::Error&) {
  }
  return 0;
}
