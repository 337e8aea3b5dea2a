#include "visfield/field/field_file.hpp"

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <span>
#include <vector>

#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/io/atomic_file.hpp"

namespace vf::field {
namespace {

static_assert(std::endian::native == std::endian::little, "the .vfield writer assumes a little-endian machine");

constexpr char kMagic[8] = {'V', 'I', 'S', 'F', 'I', 'E', 'L', 'D'};
/// Header bytes of version 1 (no normal field) and of version 2.
constexpr std::size_t header_bytes(std::uint32_t version) { return version == 1 ? 80 : 88; }

/// The characters of `s` as the bytes of a table.
std::span<const std::uint8_t> bytes_of(std::string_view s) { return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()}; }

std::uint64_t fnv1a(std::string_view bytes, std::uint64_t h = 0xcbf29ce484222325ull) {
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ull;
  }
  return h;
}

template <class T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

/// Reads values from the front of a byte range, refusing to run past its end.
class Reader {
 public:
  Reader(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name) {}
  template <class T>
  T get() {
    T value;
    std::memcpy(&value, take(sizeof(T)).data(), sizeof(T));
    return value;
  }
  std::string_view take(std::size_t n) {
    if (n > bytes_.size() - at_) throw Error(name_ + ": the file is cut short (not a complete .vfield file)");
    const std::string_view part = bytes_.substr(at_, n);
    at_ += n;
    return part;
  }

 private:
  std::string_view bytes_;
  const std::string& name_;
  std::size_t at_ = 0;
};

}  // namespace

std::string with_field_checksum(std::string bytes) {
  if (bytes.size() < 8) return bytes;
  const std::uint64_t sum = fnv1a(std::string_view(bytes).substr(0, bytes.size() - 8));
  std::memcpy(bytes.data() + bytes.size() - 8, &sum, 8);
  return bytes;
}

std::uint64_t mesh_hash(const TriangleSet& object_triangles) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const auto& triangle : object_triangles.triangles)
    h = fnv1a(std::string_view(reinterpret_cast<const char*>(triangle.data()), sizeof(triangle)), h);
  return h;
}

std::string encode_field(const ObjectField& field, std::uint64_t hash) {
  const ObjectFieldConfig& c = field.config();
  std::string out;
  out.reserve(header_bytes(kFieldFileVersion) + field.cell_table().size() + 4 * field.averages().size() + field.normal_table().size() + 8);
  out.append(kMagic, sizeof(kMagic));
  put(out, kFieldFileVersion);
  put(out, static_cast<std::uint32_t>(c.positions));
  put(out, static_cast<std::uint32_t>(c.directions));
  put(out, static_cast<std::uint8_t>(c.mapping));
  put(out, static_cast<std::uint8_t>(c.storage));
  put(out, static_cast<std::uint8_t>(c.normals));
  put(out, std::uint8_t{0});
  put(out, hash);
  put(out, field.sphere().centre.x);
  put(out, field.sphere().centre.y);
  put(out, field.sphere().centre.z);
  put(out, field.sphere().radius);
  put(out, static_cast<std::uint64_t>(field.cell_table().size()));
  put(out, static_cast<std::uint64_t>(field.averages().size()));
  put(out, static_cast<std::uint64_t>(field.normal_table().size()));
  put(out, field.build_ms());
  put(out, static_cast<std::uint64_t>(field.rays_traced()));
  out.append(reinterpret_cast<const char*>(field.cell_table().data()), field.cell_table().size());
  out.append(reinterpret_cast<const char*>(field.averages().data()), 4 * field.averages().size());
  out.append(reinterpret_cast<const char*>(field.normal_table().data()), field.normal_table().size());
  put(out, fnv1a(out));
  return out;
}

StoredField decode_field(std::string_view bytes, const std::string& name, const ObjectFieldConfig& lookups) {
  Reader in(bytes, name);
  if (in.take(sizeof(kMagic)) != std::string_view(kMagic, sizeof(kMagic))) throw Error(name + ": not a .vfield file (no VISFIELD signature)");
  const auto version = in.get<std::uint32_t>();
  if (version != 1 && version != kFieldFileVersion)
    throw Error(name + ": .vfield version " + std::to_string(version) + ", this visfield reads versions 1 and " +
                std::to_string(kFieldFileVersion) + " (rebuild it with visfield field build)");
  const std::size_t header = header_bytes(version);
  if (bytes.size() < header + 8) throw Error(name + ": the file is cut short (not a complete .vfield file)");
  const std::uint64_t stored_sum = [&] {
    std::uint64_t sum;
    std::memcpy(&sum, bytes.data() + bytes.size() - 8, 8);
    return sum;
  }();
  if (fnv1a(bytes.substr(0, bytes.size() - 8)) != stored_sum)
    throw Error(name + ": checksum mismatch (the file is corrupted or cut short)");

  ObjectFieldConfig config;
  config.positions = static_cast<int>(std::min<std::uint32_t>(in.get<std::uint32_t>(), 1u << 30));
  config.directions = static_cast<int>(std::min<std::uint32_t>(in.get<std::uint32_t>(), 1u << 30));
  const auto mapping = in.get<std::uint8_t>(), storage = in.get<std::uint8_t>();
  const auto normals = in.get<std::uint8_t>(), reserved = in.get<std::uint8_t>();
  if (mapping >= kMappingCount) throw Error(name + ": unknown direction mapping " + std::to_string(mapping));
  if (storage >= kStorageCount) throw Error(name + ": unknown cell storage " + std::to_string(storage));
  if (normals >= kNormalStorageCount || (version == 1 && normals != 0)) throw Error(name + ": unknown normal storage " + std::to_string(normals));
  if (reserved != 0) throw Error(name + ": reserved header bytes are not zero");
  config.mapping = static_cast<HemisphereMapping>(mapping);
  config.storage = static_cast<CellStorage>(storage);
  config.normals = static_cast<NormalStorage>(normals);
  config.direction_lookup = lookups.direction_lookup;
  config.position_lookup = lookups.position_lookup;
  config.sample_line = lookups.sample_line;
  try {
    config.validate();
  } catch (const Error& e) {
    throw Error(name + ": " + e.what());
  }
  const auto hash = in.get<std::uint64_t>();
  BoundingSphere sphere;
  sphere.centre.x = in.get<float>();
  sphere.centre.y = in.get<float>();
  sphere.centre.z = in.get<float>();
  sphere.radius = in.get<float>();
  const auto cell_bytes = in.get<std::uint64_t>();
  const auto average_count = in.get<std::uint64_t>();
  const auto normal_bytes = version == 1 ? std::uint64_t{0} : in.get<std::uint64_t>();
  const auto build_ms = in.get<double>();
  const auto rays = in.get<std::uint64_t>();

  const std::uint64_t cells_per_sample = static_cast<std::uint64_t>(config.directions) * static_cast<std::uint64_t>(config.directions);
  const std::uint64_t positions = static_cast<std::uint64_t>(config.positions);
  const std::uint64_t expected_cells = positions * ((cells_per_sample * static_cast<std::uint64_t>(cell_bits(config.storage)) + 7) / 8);
  const std::uint64_t expected_normals = positions * cells_per_sample * static_cast<std::uint64_t>(normal_bits(config.normals)) / 8;
  const std::uint64_t expected_averages = config.storage == CellStorage::bit ? positions : 0;
  if (cell_bytes != expected_cells || average_count != expected_averages || normal_bytes != expected_normals)
    throw Error(name + ": the header's table sizes do not match its parameters (corrupted file)");
  const std::uint64_t total = header + cell_bytes + 4 * average_count + normal_bytes + 8;
  if (bytes.size() != total)
    throw Error(name + ": " + std::to_string(bytes.size()) + " bytes, its header describes " + std::to_string(total));
  require_memory(static_cast<double>(cell_bytes) + 4.0 * static_cast<double>(average_count) + static_cast<double>(normal_bytes),
                 name + "'s field");
  // The tables are read in place: from_tables() copies them once, into the field's own.
  const std::string_view cell_data = in.take(cell_bytes);
  const std::span<const std::uint8_t> cells = bytes_of(cell_data);
  std::vector<float> averages(average_count);
  if (average_count > 0) std::memcpy(averages.data(), in.take(4 * average_count).data(), 4 * average_count);
  const std::string_view normal_data = in.take(normal_bytes);
  for (const float a : averages)
    if (!(a >= 0.0f && a <= 1.0f)) throw Error(name + ": an average distance outside [0, 1] (corrupted file)");
  if (config.storage == CellStorage::f32) {
    for (std::size_t i = 0; i < cells.size(); i += 4) {
      float x;
      std::memcpy(&x, cells.data() + i, 4);
      if (!(x >= 0.0f && x <= 1.0f) && !std::isinf(x)) throw Error(name + ": a distance outside [0, 1] (corrupted file)");
    }
  }
  if (!std::isfinite(build_ms) || build_ms < 0.0) throw Error(name + ": a precompute time that is not a finite duration");
  try {
    return {ObjectField::from_tables(config, sphere, cells, std::move(averages), bytes_of(normal_data), build_ms, rays), hash,
            version};
  } catch (const Error& e) {
    throw Error(name + ": " + e.what());
  }
}

void save_field(const ObjectField& field, std::uint64_t hash, const std::filesystem::path& path) {
  const std::string bytes = encode_field(field, hash);
  write_atomically(path, [&](const std::filesystem::path& tmp) { write_file_bytes(tmp, bytes); });
}

StoredField load_field(const std::filesystem::path& path, std::optional<std::uint64_t> expected_hash, const ObjectFieldConfig& lookups) {
  const std::string name = path.string();
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw Error(name + ": " + (std::filesystem::exists(path) ? ec.message() : std::string("no such file")));
  require_memory(2.0 * static_cast<double>(size), name);
  std::ifstream file(path, std::ios::binary);
  if (!file) throw Error(name + ": cannot open for reading");
  std::string bytes(size, '\0');
  if (!file.read(bytes.data(), static_cast<std::streamsize>(size))) throw Error(name + ": cannot read the whole file");
  StoredField stored = decode_field(bytes, name, lookups);
  if (expected_hash && *expected_hash != stored.mesh_hash)
    throw Error(name + ": made for another mesh (its mesh hash differs; rebuild it with visfield field build)");
  return stored;
}

}  // namespace vf::field
