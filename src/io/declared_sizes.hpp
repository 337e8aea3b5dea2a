#pragma once
// Private to the io module: refuses mesh files whose headers declare more data than the file holds,
// before a reader allocates for the declared counts (a 200-byte PLY may declare 4 billion vertices).

#include <filesystem>
#include <string>

namespace vf::io_detail {

/// For PLY (ASCII and binary) and binary STL: throws vf::Error "<path>: malformed PLY: the header
/// declares ... but the file holds ..." when the element counts of the header need more bytes than
/// follow it, or when the header itself is malformed. Other formats pass. Reads at most 64 KiB.
void check_declared_sizes(const std::filesystem::path& path, const std::string& lower_extension);

}  // namespace vf::io_detail
