#pragma once
/// \file Where a u8 field's cells go in a 3D texture (the texture variant of the GPU lookup): each
/// sample's N×N table is one N-texel-wide block of rows; `stack` samples are stacked along y in one
/// slice, the slices along z. The device's 3D texture limits decide how many samples a slice stacks.

#include <cstdint>
#include <string>

#include "visfield/core/error.hpp"

namespace vf::gpu {

/// A device's largest 3D texture, in texels per side (cudaDevAttrMaxTexture3D{Width,Height,Depth}).
struct Texture3DLimits {
  std::uint32_t width = 0, height = 0, depth = 0;
};

/// A field's texture: N × N·stack × depth texels; sample s at rows N·(s mod stack), slice s / stack.
struct FieldTextureShape {
  std::uint32_t stack = 1;  ///< Samples a slice stacks along y.
  std::uint32_t depth = 0;  ///< Slices: ⌈samples / stack⌉.
};

/// The fewest samples a slice must stack so that `samples` tables of `n`×`n` cells fit `limits`.
/// Throws vf::Error when no stacking fits (n over the width, or the stacked height over the limit). O(1).
inline FieldTextureShape field_texture_shape(std::uint32_t samples, std::uint32_t n, const Texture3DLimits& limits) {
  if (n == 0 || samples == 0) throw Error("field textures: a field with no cells");
  if (n > limits.width || limits.depth == 0)
    throw Error("field textures: " + std::to_string(n) + "-cell tables exceed the device's 3D texture width of " +
                std::to_string(limits.width));
  FieldTextureShape shape;
  shape.stack = (samples + limits.depth - 1) / limits.depth;
  shape.depth = (samples + shape.stack - 1) / shape.stack;
  if (static_cast<std::uint64_t>(n) * shape.stack > limits.height)
    throw Error("field textures: " + std::to_string(samples) + " samples of " + std::to_string(n) + "x" + std::to_string(n) +
                " cells exceed the device's 3D texture limits (" + std::to_string(limits.width) + " x " + std::to_string(limits.height) +
                " x " + std::to_string(limits.depth) + ")");
  return shape;
}

}  // namespace vf::gpu
