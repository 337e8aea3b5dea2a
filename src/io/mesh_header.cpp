#include "mesh_header.hpp"

#include <cctype>
#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "file_checks.hpp"
#include "visfield/core/error.hpp"
#include "visfield/io/json_reader.hpp"

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

std::uint32_t little_endian_u32(const std::string& bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = v << 8 | static_cast<unsigned char>(bytes[at + static_cast<std::size_t>(i)]);
  return v;
}

// Assimp's glTF reader parses the JSON recursively: deep nesting must be refused before it starts.
// Its answer to JSON that is cut short is "no suitable reader found": say what is wrong instead.
void check_gltf_json(std::string_view text, const std::string& what) {
  json::check_json_nesting(text, what);
  if (!nlohmann::json::accept(text)) throw Error(what + ": the JSON is invalid or cut short");
}

void check_gltf(const std::filesystem::path& path, std::uintmax_t file_size) {
  check_gltf_json(read_head(path, file_size), path.string() + ": malformed GLTF");
}

// A GLB is a 12-byte header ("glTF", version, length) and chunks; version 2 starts with a JSON chunk
// (length, "JSON", text), version 1 with its JSON content's length and format at offset 12.
void check_glb(const std::filesystem::path& path, std::uintmax_t file_size) {
  const std::string what = path.string() + ": malformed GLB: ";
  const std::string head = read_head(path, 20);
  if (head.size() < 20) throw Error(what + "a GLB of " + std::to_string(file_size) + " bytes, shorter than its 20-byte header");
  const std::uint64_t json_bytes = little_endian_u32(head, 12);
  if (20 + json_bytes > file_size)
    throw Error(what + "the header declares " + std::to_string(json_bytes) + " bytes of JSON but only " +
                std::to_string(file_size - 20) + " bytes follow it");
  check_gltf_json(std::string_view(read_head(path, 20 + json_bytes)).substr(20), what.substr(0, what.size() - 2));
}

// Assimp picks a reader by extension and, failing that, by probing every reader; a file whose
// header does not match its extension could then be read as some other format. Check the magic
// bytes of the formats that have them so a mislabelled or corrupt file is reported, not guessed.
void require_format_signature(const std::filesystem::path& path, const std::string& ext) {
  std::string expected;
  if (ext == "ply") expected = "ply";
  else if (ext == "glb") expected = "glTF";
  else return;
  if (read_head(path, expected.size()) != expected)
    throw Error(path.string() + ": malformed " + upper_case(ext) + ": the file does not start with \"" + expected + "\"");
}

}  // namespace

void check_mesh_header(const std::filesystem::path& path, const std::string& lower_extension) {
  require_format_signature(path, lower_extension);
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) return;  // require_readable_file has run; the reader will report what is wrong
  if (lower_extension == "ply") check_ply(path, size);
  if (lower_extension == "stl") check_binary_stl(path, size);
  if (lower_extension == "gltf") check_gltf(path, size);
  if (lower_extension == "glb") check_glb(path, size);
}

}  // namespace vf::io_detail
