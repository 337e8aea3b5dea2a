#include "bench_accel.hpp"

#include "bench_options.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/spec.hpp"

namespace vf::bench {
namespace {

// Embree's one parameter: its own instancing (levels=2, one Embree scene per mesh under instances)
// or one flattened triangle geometry (levels=1, the default, as most users build).
constexpr ParamSpec kEmbreeParams[] = {
    {"levels", ParamType::choice, "1", "1 = one flattened triangle geometry, 2 = Embree instancing", 0, 0, "1|2"},
    {"packets", ParamType::choice, "1", "occlusion batches: 1 = rtcOccluded1 ray by ray, 16 = rtcOccluded16 packets (coherent)", 0, 0,
     "1|16"},
};

ParamValues embree_params(const std::string& spec) {
  return read_params(parse_spec(spec, "--accel "), kEmbreeParams, std::string("--accel ") + kEmbreeName);
}

bool names_embree(const std::string& spec) { return spec.substr(0, spec.find(':')) == kEmbreeName; }

}  // namespace

std::vector<std::string> bench_accel_names() {
  std::vector<std::string> names = structure_names();
  if (kHaveEmbree) names.emplace_back(kEmbreeName);
  return names;
}

void check_bench_accel(const std::string& spec) {
  try {
    if (!names_embree(spec)) {
      check_structure_spec(spec);
    } else if (!kHaveEmbree) {
      throw UsageError("--accel embree: this visfield-bench was built without Embree (configure with -DVISFIELD_EMBREE=ON)");
    } else {
      embree_params(spec);
    }
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
}

BuiltBenchAccel build_bench_accel(const std::string& spec, SceneGeometry& geometry, const BuildContext& context,
                                  [[maybe_unused]] int threads) {
#if VISFIELD_HAVE_EMBREE
  if (names_embree(spec)) {
    const ParamValues params = embree_params(spec);
    const bool instanced = params.text("levels") == "2";
    EmbreeScene embree = instanced ? EmbreeScene::build_instanced(geometry.scene(), threads) : EmbreeScene::build(geometry.flattened(), threads);
    embree.set_packet_size(std::stoi(params.text("packets")));
    std::string resolved = std::string(kEmbreeName) + ":levels=" + (instanced ? "2" : "1");
    if (embree.packet_size() != 1) resolved += ",packets=" + std::to_string(embree.packet_size());
    return {std::move(embree), resolved};
  }
#endif
  BuiltStructure built = build_structure(spec, geometry, context);
  return {std::move(built.structure), std::move(built.resolved)};
}

AccelStats bench_accel_stats(const BenchAccel& accel) {
  return visit_accel(accel, [](const auto& structure) -> AccelStats { return structure.stats(); });
}

bool bench_accel_is_exact(const BenchAccel& accel) {
  return visit_accel(accel, [](const auto& structure) {
    return std::decay_t<decltype(structure)>::exactness == Exactness::exact;
  });
}

}  // namespace vf::bench
