#pragma once
/// \file The .vfield file: one ObjectField on disk, versioned and checksummed, tied to its mesh.
///
/// Layout (little-endian), version 2: "VISFIELD", u32 version, u32 positions, u32 directions,
/// u8 mapping, u8 storage, u8 normals, u8 zero, u64 mesh hash, f32 sphere centre x y z, f32 radius,
/// u64 cell bytes, u64 average count, u64 normal bytes, f64 precompute ms, u64 rays traced (88 bytes
/// of header); the cell table; the averages (f32, 1-bit variant only); the normal table; u64 FNV-1a
/// checksum of everything before it. Version 1 (read, not written) had no normal field: its header
/// lacks the normal byte count (80 bytes) and its normals byte is zero.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "visfield/core/triangle_set.hpp"
#include "visfield/field/object_field.hpp"

namespace vf::field {

/// The version this build writes (it reads this one and version 1).
inline constexpr std::uint32_t kFieldFileVersion = 2;

/// FNV-1a hash of a mesh's object-space triangles (corner bits, in order): what ties a field to the
/// mesh it was precomputed for. O(triangles).
std::uint64_t mesh_hash(const TriangleSet& object_triangles);

/// A field as read from a file, with the hash of the mesh it belongs to.
struct StoredField {
  ObjectField field;
  std::uint64_t mesh_hash = 0;
  std::uint32_t version = kFieldFileVersion;  ///< The file's format version.
};

/// `bytes` (a whole .vfield file, at least 8 bytes) with its last 8 bytes made the checksum of the
/// rest again: for tests and fuzzing, to reach the checks behind the checksum.
std::string with_field_checksum(std::string bytes);

/// The bytes of a .vfield file for `field` of the mesh hashing to `hash`.
std::string encode_field(const ObjectField& field, std::uint64_t hash);

/// Parses .vfield bytes into a field read with the lookup options of `lookups` (they are not
/// stored); `name` (the file) starts every message. Throws vf::Error with one line on a short,
/// corrupted (checksum), wrong-version or inconsistent file, and refuses a table beyond the memory
/// limit before allocating it.
StoredField decode_field(std::string_view bytes, const std::string& name, const ObjectFieldConfig& lookups = {});

/// Writes `field` to `path` atomically (temporary file, then rename): an interrupted or failed write
/// leaves no partial file.
void save_field(const ObjectField& field, std::uint64_t hash, const std::filesystem::path& path);

/// Reads a .vfield file. With `expected_hash`, a file made for another mesh is refused. Lookup
/// options (bilinear, blend, through) are not stored: they come from `lookups`.
StoredField load_field(const std::filesystem::path& path, std::optional<std::uint64_t> expected_hash = std::nullopt,
                       const ObjectFieldConfig& lookups = {});

}  // namespace vf::field
