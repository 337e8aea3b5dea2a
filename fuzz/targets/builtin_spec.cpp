// Fuzz target: the builtin: scene-spec parser, then the scene itself when it is small (a size the
// parser accepts may ask for up to 50M triangles, which is not a parsing question).

#include <cstdint>
#include <string>

#include "visfield/core/error.hpp"
#include "visfield/scenes/builtin.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string spec = "builtin:" + std::string(reinterpret_cast<const char*>(data), size);
  try {
    const vf::BuiltinSpec parsed = vf::parse_builtin_spec(spec);
    if (parsed.params.size <= 2000) vf::make_builtin_scene(parsed.name, parsed.params);
  } catch (const vf::Error&) {
  }
  return 0;
}
