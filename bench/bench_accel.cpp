#include "bench_accel.hpp"

#include "bench_options.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/spec.hpp"

namespace vf::bench {
namespace {

// Embree's parameters: its own instancing (levels=2, one Embree scene per mesh under instances) or one
// flattened triangle geometry (levels=1, the default, as most users build); how a batch calls it; its
// build quality. The defaults are what a typical user writes.
constexpr ParamSpec kEmbreeParams[] = {
    {"levels", ParamType::choice, "1", "1 = one flattened triangle geometry, 2 = Embree instancing", 0, 0, "1|2"},
    {"call", ParamType::choice, "1",
     "1 = rtcIntersect1/rtcOccluded1 ray by ray, 16 = rtcIntersect16/rtcOccluded16 packets (coherent), stream = "
     "rtcIntersect1M/rtcOccluded1M, best = each of them at both qualities, the fastest reported",
     0, 0, "1|16|stream|best"},
    {"quality", ParamType::choice, "medium", "build quality: medium (Embree's default) or high (spatial splits)", 0, 0, "medium|high"},
};

ParamValues embree_params(const std::string& spec) {
  return read_params(parse_spec(spec, "--accel "), kEmbreeParams, std::string("--accel ") + kEmbreeName);
}

bool names_embree(const std::string& spec) { return spec.substr(0, spec.find(':')) == kEmbreeName; }

// One of our specs: the registry's part, and whether the benchmark's call=1 asks for one query a ray.
struct OwnSpec {
  std::string structure;
  bool one_ray = false;
};

OwnSpec own_spec(const std::string& spec) {
  const Spec parsed = parse_spec(spec, "--accel ");
  OwnSpec own{parsed.name, false};
  std::string params;
  for (const auto& [key, value] : parsed.params) {
    if (key != "call") {
      params += (params.empty() ? ":" : ",") + key + "=" + value;
    } else if (value == "1" || value == "batch") {
      own.one_ray = value == "1";
    } else {
      throw UsageError("--accel " + parsed.name + ": call must be batch (the batch path) or 1 (one query a ray), got '" + value + "'");
    }
  }
  own.structure += params;
  return own;
}

}  // namespace

std::vector<std::string> bench_accel_names() {
  std::vector<std::string> names = structure_names();
  if (kHaveEmbree) names.emplace_back(kEmbreeName);
  return names;
}

void check_bench_accel(const std::string& spec) {
  try {
    if (!names_embree(spec)) {
      check_structure_spec(own_spec(spec).structure);
    } else if (!kHaveEmbree) {
      throw UsageError("--accel embree: this visfield-bench was built without Embree (configure with -DVISFIELD_EMBREE=ON)");
    } else {
      embree_params(spec);
    }
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
}

std::vector<BuiltBenchAccel> build_bench_rows(const std::string& spec, SceneGeometry& geometry, const BuildContext& context,
                                              [[maybe_unused]] int threads) {
  std::vector<BuiltBenchAccel> built;
#if VISFIELD_HAVE_EMBREE
  if (names_embree(spec)) {
    const ParamValues params = embree_params(spec);
    const bool instanced = params.text("levels") == "2", best = params.text("call") == "best";
    const auto build = [&](const EmbreeSettings& settings) {
      return instanced ? EmbreeScene::build_instanced(geometry.scene(), threads, settings)
                       : EmbreeScene::build(geometry.flattened(), threads, settings);
    };
    if (!best) {
      const EmbreeSettings settings{params.text("call") == "16"       ? EmbreeCall::packet16
                                    : params.text("call") == "stream" ? EmbreeCall::stream
                                                                      : EmbreeCall::one,
                                    params.text("quality") == "high"};
      built.push_back({build(settings), embree_spec(instanced, settings)});
      return built;
    }
    for (const bool high : {false, true}) {
      const EmbreeScene scene = build({EmbreeCall::one, high});
      for (const EmbreeCall call : {EmbreeCall::one, EmbreeCall::packet16, EmbreeCall::stream})
        built.push_back({scene.with_call(call), embree_spec(instanced, {call, high}), true});
    }
    return built;
  }
#endif
  const OwnSpec own = own_spec(spec);
  BuiltStructure result = build_structure(own.structure, geometry, context);
  if (own.one_ray) result.resolved += (result.resolved.find(':') == std::string::npos ? ":" : ",") + std::string("call=1");
  built.push_back({std::move(result.structure), std::move(result.resolved), false, own.one_ray});
  return built;
}

BuiltBenchAccel build_bench_accel(const std::string& spec, SceneGeometry& geometry, const BuildContext& context, int threads) {
  std::vector<BuiltBenchAccel> rows = build_bench_rows(spec, geometry, context, threads);
  if (rows.size() != 1) throw UsageError("--accel " + spec + ": call=best runs in visfield-bench's table only");
  return std::move(rows.front());
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
