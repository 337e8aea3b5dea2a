#include "declared_sizes.hpp"

#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "file_checks.hpp"
#include "visfield/core/error.hpp"

namespace vf::io_detail {
namespace {

constexpr std::size_t kMaxPlyHeaderBytes = 64 * 1024;

std::string read_head(const std::filesystem::path& path, std::size_t max_bytes) {
  std::string head(max_bytes, '\0');
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) return {};
  head.resize(std::fread(head.data(), 1, head.size(), file));
  std::fclose(file);
  return head;
}

// Bytes of one value of a PLY scalar type; 0 for a name that is not one.
std::uint64_t ply_type_size(std::string_view type) {
  for (std::string_view t : {"char", "uchar", "int8", "uint8"})
    if (type == t) return 1;
  for (std::string_view t : {"short", "ushort", "int16", "uint16"})
    if (type == t) return 2;
  for (std::string_view t : {"int", "uint", "int32", "uint32", "float", "float32"})
    if (type == t) return 4;
  for (std::string_view t : {"double", "float64"})
    if (type == t) return 8;
  return 0;
}

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::uint64_t min_binary_bytes = 0;  // one element: its scalars, and the count of each list
  std::uint64_t values = 0;            // one element: its scalar and list-count values
};

// a + b and a * b capped at UINT64_MAX: counts of billions times sizes must not wrap around.
std::uint64_t add_capped(std::uint64_t a, std::uint64_t b) { return a > UINT64_MAX - b ? UINT64_MAX : a + b; }
std::uint64_t mul_capped(std::uint64_t a, std::uint64_t b) { return b != 0 && a > UINT64_MAX / b ? UINT64_MAX : a * b; }

std::string describe(const std::vector<PlyElement>& elements) {
  std::string text;
  for (const PlyElement& e : elements) text += (text.empty() ? "" : " and ") + std::to_string(e.count) + " " + e.name;
  return text + " elements";
}

void check_ply(const std::filesystem::path& path, std::uintmax_t file_size) {
  const std::string what = path.string() + ": malformed PLY: ";
  const std::string head = read_head(path, kMaxPlyHeaderBytes);
  const std::size_t end = head.find("end_header");
  if (end == std::string::npos)
    throw Error(what + "no end_header line in the first " + std::to_string(kMaxPlyHeaderBytes / 1024) + " KiB");
  const std::size_t header_bytes = head.find('\n', end) == std::string::npos ? head.size() : head.find('\n', end) + 1;

  std::istringstream lines(head.substr(0, end));
  std::string line, format;
  std::vector<PlyElement> elements;
  while (std::getline(lines, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "format") {
      words >> format;
    } else if (keyword == "element") {
      PlyElement e;
      std::string count;
      words >> e.name >> count;
      if (count.empty() || count.size() > 19 || count.find_first_not_of("0123456789") != std::string::npos)
        throw Error(what + "element " + e.name + " has no valid count ('" + one_line(count) + "')");
      e.count = std::stoull(count);
      elements.push_back(e);
    } else if (keyword == "property") {
      if (elements.empty()) throw Error(what + "a property before any element");
      // "property TYPE NAME" or "property list COUNT_TYPE ITEM_TYPE NAME"; a list's least bytes are its count's.
      std::string type, item_type;
      words >> type;
      if (type == "list") words >> type >> item_type;
      const std::uint64_t size = ply_type_size(type);
      if (size == 0 || (!item_type.empty() && ply_type_size(item_type) == 0))
        throw Error(what + "unknown property type in '" + one_line(line) + "'");
      elements.back().min_binary_bytes += size;
      elements.back().values += 1;
    }
  }
  if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
    throw Error(what + "unknown format '" + one_line(format) + "' (expected ascii, binary_little_endian or binary_big_endian)");

  // Binary: each element takes its scalars and list counts, lists empty at the least. ASCII: each
  // value takes one character and one separator (space or line break) at the least.
  const bool ascii = format == "ascii";
  std::uint64_t needed = 0;
  for (const PlyElement& e : elements)
    needed = add_capped(needed, mul_capped(e.count, ascii ? 2 * e.values : e.min_binary_bytes));
  if (ascii && needed > 0) needed -= 1;  // the last value needs no separator
  const std::uint64_t held = file_size - header_bytes;
  if (needed > held)
    throw Error(what + "the header declares " + describe(elements) + " (at least " + std::to_string(needed) + " bytes of " +
                format + " data) but only " + std::to_string(held) + " bytes follow it");
}

void check_binary_stl(const std::filesystem::path& path, std::uintmax_t file_size) {
  const std::string head = read_head(path, 84);
  // An ASCII STL starts with "solid"; so do some binary ones, which Assimp tells apart by their size.
  const auto binary_size = [&](std::uint64_t n) { return 84 + 50 * n; };
  std::uint32_t count = 0;
  if (head.size() == 84)
    count = static_cast<std::uint32_t>(static_cast<unsigned char>(head[80])) |
            static_cast<std::uint32_t>(static_cast<unsigned char>(head[81])) << 8 |
            static_cast<std::uint32_t>(static_cast<unsigned char>(head[82])) << 16 |
            static_cast<std::uint32_t>(static_cast<unsigned char>(head[83])) << 24;
  if (head.rfind("solid", 0) == 0 && !(head.size() == 84 && binary_size(count) == file_size)) return;
  const std::string what = path.string() + ": malformed STL: ";
  if (head.size() < 84) throw Error(what + "a binary STL of " + std::to_string(file_size) + " bytes, shorter than its 84-byte header");
  if (binary_size(count) > file_size)
    throw Error(what + "the header declares " + std::to_string(count) + " triangles (" + std::to_string(binary_size(count)) +
                " bytes) but the file holds " + std::to_string(file_size) + " bytes");
}

}  // namespace

void check_declared_sizes(const std::filesystem::path& path, const std::string& lower_extension) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) return;  // require_readable_file has run; the reader will report what is wrong
  if (lower_extension == "ply") check_ply(path, size);
  if (lower_extension == "stl") check_binary_stl(path, size);
}

}  // namespace vf::io_detail
