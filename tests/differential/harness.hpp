#pragma once
/// \file Differential testing of exact structures against an oracle. The oracle is BruteForce over
/// the flattened triangles for single-level structures, and InstancedOracle (BruteForce per mesh,
/// every object tried in id order) for the instance layer. The harness compares closest hits
/// (t, triangle, object, normal) and occlusion answers ray by ray and prints the first mismatches
/// with the ray in hexadecimal floats.

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>

#include "visfield/accel/brute_force.hpp"
#include "visfield/accel/query.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/core/parallel.hpp"
#include "support/same_hit.hpp"

namespace vf::test {

/// How much to print.
struct DiffOptions {
  int max_reports = 5;  ///< Mismatches printed (the first ones, by ray index).
  std::string label;    ///< Printed with each mismatch (scene and ray set).
};

/// Counts of disagreements with the oracle over a ray set.
struct DiffReport {
  std::size_t rays = 0;
  std::size_t oracle_hits = 0;          ///< Rays the oracle reports a closest hit for.
  std::size_t oracle_occluded = 0;      ///< Rays the oracle reports occluded.
  std::size_t closest_mismatches = 0;   ///< Closest hits that differ from the oracle's in any bit.
  std::size_t occluded_mismatches = 0;  ///< occluded() differs from the oracle.
};

/// The oracle's answers for one ray set, computed once and compared against any number of structures.
struct OracleAnswers {
  std::vector<Hit> closest;
  std::vector<std::uint8_t> occluded;
};

/// The exact answer for a scene of objects: every object tried in increasing id order with the ray
/// mapped into its space (Transform::inverse), its mesh's triangles tested by BruteForce; the nearest
/// t wins, an equal t going to the lower object id. The definition the instance layer must reproduce.
class InstancedOracle {
 public:
  explicit InstancedOracle(const Scene& scene) : InstancedOracle(scene.instances(), scene.meshes) {}
  /// The oracle of `objects` (in increasing id order) placing `meshes`.
  InstancedOracle(std::vector<Instance> objects, const std::vector<TriangleMesh>& meshes) : objects_(std::move(objects)) {
    meshes_.resize(meshes.size());
    for (const Instance& o : objects_)
      if (!meshes_[o.mesh]) meshes_[o.mesh] = std::make_shared<BruteForce>(BruteForce::build(mesh_triangles(meshes[o.mesh])));
  }
  Hit intersect(const Ray& ray) const {
    Hit best;
    for (const Instance& o : objects_) {
      Ray local = o.transform.inverse().apply(ray);
      if (best) local.tmax = best.t;
      const Hit hit = meshes_[o.mesh]->intersect(local);
      if (!hit || (best && !(hit.t < best.t))) continue;
      best = hit;
      best.instance = o.id;
      if (!o.transform.is_identity()) best.normal = o.transform.apply_normal(hit.normal);
    }
    return best;
  }
  bool occluded(const Ray& ray) const {
    for (const Instance& o : objects_)
      if (meshes_[o.mesh]->occluded(o.transform.inverse().apply(ray))) return true;
    return false;
  }
  AccelStats stats() const { return {}; }
  static std::string name() { return "instanced-oracle"; }
  static constexpr Exactness exactness = Exactness::exact;

 private:
  std::vector<Instance> objects_;
  std::vector<std::shared_ptr<BruteForce>> meshes_;
};

/// Runs `oracle` over `rays` (parallel). Occlusion is by definition "a closest hit exists in
/// [tmin, tmax]"; with `query_occluded` the oracle's own occluded() is called as well and must agree
/// (its disagreements are counted in `oracle_inconsistencies`). Cost O(rays * triangles).
template <Accelerator O>
OracleAnswers oracle_answers(const O& oracle, std::span<const Ray> rays, bool query_occluded,
                             std::size_t* oracle_inconsistencies = nullptr) {
  OracleAnswers answers;
  answers.closest.resize(rays.size());
  answers.occluded.resize(rays.size());
  std::vector<std::uint8_t> inconsistent(rays.size(), 0);
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 16), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      answers.closest[i] = oracle.intersect(rays[i]);
      answers.occluded[i] = answers.closest[i] ? 1 : 0;
      if (query_occluded && oracle.occluded(rays[i]) != answers.closest[i].found) inconsistent[i] = 1;
    }
  });
  if (oracle_inconsistencies) {
    *oracle_inconsistencies = 0;
    for (std::uint8_t x : inconsistent) *oracle_inconsistencies += x;
  }
  return answers;
}

namespace detail {

inline std::string describe(const Hit& h) {
  if (!h) return "miss";
  char buf[200];
  std::snprintf(buf, sizeof buf, "t=%a (%.9g) u=%a v=%a prim=%u instance=%u normal=(%a, %a, %a)", h.t, h.t, h.u, h.v, h.prim,
                h.instance, h.normal.x, h.normal.y, h.normal.z);
  return buf;
}

inline std::string describe(const Ray& r) {
  char buf[320];
  std::snprintf(buf, sizeof buf, "org=(%a, %a, %a) dir=(%a, %a, %a) tmin=%a tmax=%a", r.org.x, r.org.y, r.org.z,
                r.dir.x, r.dir.y, r.dir.z, r.tmin, r.tmax);
  return buf;
}

/// Why `got` differs from `expected` in any bit, or nullptr when it does not (the first difference
/// in the order hit, t, triangle and object, u and v, normal).
inline const char* closest_mismatch(const Hit& expected, const Hit& got) {
  if (same_bits(expected, got)) return nullptr;
  if (expected.found != got.found) return expected ? "missed a hit" : "reported a hit the oracle misses";
  if (std::bit_cast<std::uint32_t>(got.t) != std::bit_cast<std::uint32_t>(expected.t)) return "t differs";
  if (got.prim != expected.prim || got.instance != expected.instance) return "another triangle at the same t (the tie goes to the lowest index)";
  if (std::bit_cast<std::uint32_t>(got.u) != std::bit_cast<std::uint32_t>(expected.u) ||
      std::bit_cast<std::uint32_t>(got.v) != std::bit_cast<std::uint32_t>(expected.v))
    return "u or v differs";
  return "normal differs";
}

}  // namespace detail

/// Compares `structure` (named `name` in reports) with precomputed oracle answers for the same rays;
/// prints the first mismatches.
template <Accelerator A>
DiffReport compare_answers(const A& structure, const std::string& name, std::span<const Ray> rays,
                           const OracleAnswers& oracle, const DiffOptions& options = {}) {
  std::vector<const char*> closest_why(rays.size(), nullptr);
  std::vector<Hit> got(rays.size());
  std::vector<std::uint8_t> occluded_wrong(rays.size(), 0);
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, rays.size(), 64), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      got[i] = structure.intersect(rays[i]);
      closest_why[i] = detail::closest_mismatch(oracle.closest[i], got[i]);
      occluded_wrong[i] = (structure.occluded(rays[i]) ? 1 : 0) != oracle.occluded[i] ? 1 : 0;
    }
  });
  DiffReport report;
  report.rays = rays.size();
  int printed = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    report.oracle_hits += oracle.closest[i] ? 1 : 0;
    report.oracle_occluded += oracle.occluded[i];
    if (!closest_why[i] && !occluded_wrong[i]) continue;
    report.closest_mismatches += closest_why[i] ? 1 : 0;
    report.occluded_mismatches += occluded_wrong[i];
    if (printed++ >= options.max_reports) continue;
    std::printf("[%s] %s mismatch on ray %zu: %s\n  ray    %s\n  oracle %s (occluded %d)\n  got    %s\n",
                options.label.c_str(), name.c_str(), i, closest_why[i] ? closest_why[i] : "occluded() differs",
                detail::describe(rays[i]).c_str(), detail::describe(oracle.closest[i]).c_str(), oracle.occluded[i],
                detail::describe(got[i]).c_str());
  }
  return report;
}

/// compare_answers for whichever structure `built` holds.
inline DiffReport compare_built(const BuiltStructure& built, std::span<const Ray> rays, const OracleAnswers& oracle,
                                const DiffOptions& options = {}) {
  return std::visit([&](const auto& s) { return compare_answers(s, built.resolved, rays, oracle, options); },
                    built.structure);
}

/// True when the spec builds the instance layer, whose oracle is InstancedOracle.
inline bool is_two_level(const BuiltStructure& built) { return std::holds_alternative<InstanceLayer>(built.structure); }

}  // namespace vf::test
