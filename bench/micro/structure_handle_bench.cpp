// What vf::Structure's one handle costs beside the concrete type it holds: the same 1M random rays
// through the BVH's batch path, called on the Bvh itself and through the handle (one dispatch per
// batch), closest hits and occlusion, on the built-in stadium (a 50K-triangle knot in an arena).
// Run (both cores, interleaved repetitions, medians):
//   build/bin/visfield-microbench --benchmark_filter=Handle --benchmark_repetitions=9
//     --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true   (one line)

#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "visfield/accel/batch.hpp"
#include "visfield/core/rng.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/registry/structure.hpp"
#include "visfield/scenes/builtin.hpp"

namespace {

struct Workload {
  vf::Structure handle;
  std::vector<vf::Ray> rays;
};

const Workload& workload() {
  static const Workload w = [] {
    const vf::Scene scene = vf::make_builtin_scene("stadium");
    Workload out{vf::Structure::build(scene, "bvh"), {}};
    const vf::Bounds3f b = scene.bounds();
    vf::Rng rng(7, 1);
    out.rays.resize(1'000'000);
    for (vf::Ray& r : out.rays) {
      const vf::Vec3f e = b.hi - b.lo;
      const vf::Vec3f origin{b.lo.x + e.x * rng.uniform(), b.lo.y + e.y * rng.uniform(), b.lo.z + e.z * rng.uniform()};
      r = vf::Ray{origin, vf::uniform_sphere(rng.uniform(), rng.uniform())};
    }
    return out;
  }();
  return w;
}

template <bool ThroughHandle, bool Occlusion>
void trace(benchmark::State& state) {
  const Workload& w = workload();
  const vf::Bvh& bvh = *w.handle.get<vf::Bvh>();
  std::vector<vf::Hit> hits(w.rays.size());
  std::vector<std::uint8_t> blocked(w.rays.size());
  for (auto _ : state) {
    if constexpr (Occlusion) {
      if constexpr (ThroughHandle) w.handle.occluded(w.rays, blocked);
      else vf::occluded_batch(bvh, std::span<const vf::Ray>(w.rays), std::span<std::uint8_t>(blocked));
      benchmark::DoNotOptimize(blocked.data());
    } else {
      if constexpr (ThroughHandle) w.handle.intersect(w.rays, hits);
      else vf::intersect_batch(bvh, std::span<const vf::Ray>(w.rays), std::span<vf::Hit>(hits));
      benchmark::DoNotOptimize(hits.data());
    }
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(w.rays.size()));
}

BENCHMARK(trace<false, false>)->Name("Handle/closest/bvh_itself")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(trace<true, false>)->Name("Handle/closest/vf_structure")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(trace<false, true>)->Name("Handle/occluded/bvh_itself")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(trace<true, true>)->Name("Handle/occluded/vf_structure")->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
