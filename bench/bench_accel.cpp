#include "bench_accel.hpp"

#include "bench_options.hpp"

namespace vf::bench {

std::vector<std::string> bench_accel_names() {
  std::vector<std::string> names = accel_names();
  names.emplace_back(kAutoAccelName);
  if (kHaveEmbree) names.emplace_back(kEmbreeName);
  return names;
}

BenchAccel build_bench_accel(const std::string& name, const TriangleSet& set, [[maybe_unused]] int threads) {
#if VISFIELD_HAVE_EMBREE
  if (name == kEmbreeName) return EmbreeScene::build(set, threads);
#endif
  return build_accel(name, set);
}

AccelStats bench_accel_stats(const BenchAccel& accel) {
  return visit_accel(accel, [](const auto& structure) -> AccelStats { return structure.stats(); });
}

}  // namespace vf::bench
