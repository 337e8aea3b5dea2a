#include "file_checks.hpp"

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "visfield/core/error.hpp"

namespace vf::io_detail {

void require_readable_file(const std::filesystem::path& path) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) throw Error(path.string() + ": no such file");
  if (std::filesystem::is_directory(status)) throw Error(path.string() + ": is a directory, not a file");
  if (!std::filesystem::is_regular_file(status)) throw Error(path.string() + ": not a regular file");
  // No format we read has a valid empty file; saying so beats each parser's own wording.
  if (std::filesystem::file_size(path, ec) == 0 && !ec) throw Error(path.string() + ": the file is empty");
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) throw Error(path.string() + ": cannot open: " + std::strerror(errno));
  std::fclose(file);
}

std::string upper_case(std::string text) {
  for (char& c : text) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return text;
}

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  if (!ext.empty() && ext.front() == '.') ext.erase(0, 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace vf::io_detail
