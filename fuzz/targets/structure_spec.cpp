// Fuzz target: the structure-spec parser of --accel (and of visfield-bench's comma-separated lists),
// then the build of every spec it accepts over a small scene.

#include <cstdint>
#include <string>

#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/spec.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/scenes/builtin.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const vf::Scene scene = vf::make_builtin_scene("boxes", {.seed = 1, .size = 6});
  // A spec may ask for any size the parameter ranges allow (beam:dirs=8193,n=1024 is 34 GB of tile
  // tables): builds estimated past 256 MB are refused with their estimate, as --max-memory would.
  static const bool limited = (vf::set_memory_limit(256.0 * (1 << 20), "the fuzz target's 256 MiB"), true);
  (void)limited;
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
