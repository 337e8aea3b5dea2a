#pragma once
// Private to the io module: refuses mesh files whose headers declare more data than the file holds,
// before a reader allocates for the declared counts (a 200-byte PLY may declare 4 billion vertices),
// and glTF whose JSON nests deeper than a recursive reader's stack allows.

#include <filesystem>
#include <string>

namespace vf::io_detail {

/// Checks a mesh file before Assimp reads it. PLY and GLB must start with their magic bytes. For
/// PLY (ASCII and binary), binary STL and GLB: throws vf::Error "<path>: malformed PLY: the header
/// declares ... but the file holds ..." when the counts of the header need more bytes than
/// follow it, or when the header itself is malformed; for glTF and GLB, when the JSON nests more than
/// json::kMaxJsonDepth deep. Other formats pass. Reads 64 KiB at most, or a glTF's JSON.
void check_mesh_header(const std::filesystem::path& path, const std::string& lower_extension);

}  // namespace vf::io_detail
