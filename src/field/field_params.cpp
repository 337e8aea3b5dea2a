#include "visfield/field/field_params.hpp"

#include <string>

namespace vf::field {

ObjectFieldConfig with_table_params(ObjectFieldConfig c, const ParamValues& p, bool given_only) {
  const auto use = [&](std::string_view key) { return given_only ? p.given(key) : p.has(key); };
  if (use("positions")) c.positions = static_cast<int>(std::stoul(p.text("positions")));
  if (use("directions")) c.directions = static_cast<int>(p.whole("directions"));
  for (int m = 0; m < kMappingCount; ++m)
    if (use("mapping") && mapping_name(static_cast<HemisphereMapping>(m)) == p.text("mapping")) c.mapping = static_cast<HemisphereMapping>(m);
  for (int s = 0; s < kStorageCount; ++s)
    if (use("storage") && storage_name(static_cast<CellStorage>(s)) == p.text("storage")) c.storage = static_cast<CellStorage>(s);
  for (int s = 0; s < kNormalStorageCount; ++s)
    if (use("normals") && normals_name(static_cast<NormalStorage>(s)) == p.text("normals")) c.normals = static_cast<NormalStorage>(s);
  return c;
}

ObjectFieldConfig with_table_params(const ObjectFieldConfig& base, std::string_view params, const std::string& where) {
  if (params.empty()) return base;
  const Spec spec = parse_spec("field:" + std::string(params), where);
  return with_table_params(base, read_params(spec, kTableParams, where + "field"), /*given_only=*/true);
}

}  // namespace vf::field
