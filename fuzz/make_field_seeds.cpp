// Writes the seed corpus of the field_file fuzz target: small .vfield files of a tetrahedron
// (290 positions x 8^2 cells), one per storage and mapping, two with normal fields, and one in the
// version-1 layout.
// Usage: build/bin/make_field_seeds fuzz/corpus/field_file

#include <array>
#include <fstream>
#include <string>

#include "visfield/field/field_file.hpp"

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  using namespace vf;
  TriangleSet set;
  const Vec3f a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0}, d{0, 0, 1};
  for (const std::array<Vec3f, 3>& t : {std::array<Vec3f, 3>{a, b, c}, {a, b, d}, {a, c, d}, {b, c, d}}) {
    set.triangles.push_back(t);
    set.prim.push_back(static_cast<std::uint32_t>(set.prim.size()));
    set.instance.push_back(kInvalidId);
    for (const Vec3f& p : t) set.bounds.extend(p);
  }
  struct Seed {
    const char* name;
    field::ObjectFieldConfig config;
  };
  using field::CellStorage;
  using field::HemisphereMapping;
  for (const Seed& s : {Seed{"u8-concentric", {.positions = 290, .directions = 8}},
                        Seed{"u16-polar", {.positions = 290, .directions = 8, .mapping = HemisphereMapping::polar, .storage = CellStorage::u16}},
                        Seed{"f32-rejection",
                             {.positions = 290, .directions = 8, .mapping = HemisphereMapping::rejection_malley, .storage = CellStorage::f32}},
                        Seed{"bit-equal-area",
                             {.positions = 290, .directions = 8, .mapping = HemisphereMapping::concentric_equal_area, .storage = CellStorage::bit}},
                        Seed{"u8-oct16-normals", {.positions = 290, .directions = 8, .normals = field::NormalStorage::oct16}},
                        Seed{"u16-oct32-normals",
                             {.positions = 290, .directions = 8, .storage = CellStorage::u16, .normals = field::NormalStorage::oct32}}}) {
    const field::ObjectField f = field::ObjectField::build(set, s.config);
    std::ofstream(std::string(argv[1]) + "/" + s.name, std::ios::binary) << field::encode_field(f, field::mesh_hash(set));
  }
  // A version-1 file (no normal field): the version-2 layout without the normal byte count.
  std::string old = field::encode_field(field::ObjectField::build(set, {.positions = 290, .directions = 8}), field::mesh_hash(set));
  old.erase(64, 8);
  old[8] = 1;
  std::ofstream(std::string(argv[1]) + "/u8-version1", std::ios::binary) << field::with_field_checksum(old);
  return 0;
}
