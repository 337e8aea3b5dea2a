#pragma once
// Private helpers of the io module: checks on input paths and one-line error text.

#include <filesystem>
#include <string>
#include <string_view>

namespace vf::io_detail {

/// Throws vf::Error ("<path>: no such file", "<path>: is a directory, not a file", "<path>: the file
/// is empty", "<path>: cannot open: <reason>") unless `path` names a non-empty regular file this
/// process can open for reading.
void require_readable_file(const std::filesystem::path& path);

/// `text` upper-cased (ASCII): a format's name in messages ("PLY").
std::string upper_case(std::string text);

/// The extension of `path` without the dot, lower-cased ("" when there is none).
std::string lower_extension(const std::filesystem::path& path);

}  // namespace vf::io_detail
