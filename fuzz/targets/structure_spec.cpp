// Fuzz target: the structure-spec parser of --accel (and of visfield-bench's comma-separated lists),
// then the build of every spec it accepts over a small scene.

#include <cstdint>
#include <string>

#include "visfield/core/error.hpp"
#include "visfield/core/spec.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/scenes/builtin.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const vf::Scene scene = vf::make_builtin_scene("boxes", {.seed = 1, .size = 6});
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (const std::string& spec : vf::split_spec_list(text)) {
    try {
      vf::SceneGeometry geometry(scene);
      vf::build_structure(spec, geometry, vf::BuildContext{1000});
    } catch (const vf::Error&) {
    }
  }
  return 0;
}
