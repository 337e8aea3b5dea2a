#include "visfield/registry/structure_queries.hpp"

#include <algorithm>
#include <string>
#include <type_traits>
#include <vector>

#include <tbb/blocked_range.h>

#include "visfield/accel/batch.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"

namespace vf {
namespace {

// Rays converted per step of the array queries: 2 MiB of rays, enough for a structure's batch to
// spread over the threads (BeamField groups them by line) while staying far below the ray set.
constexpr std::size_t kChunk = 1u << 16;

// Runs `body(first, count)` over [0, total) in chunks of kChunk, in order.
template <class Body>
void for_each_chunk(std::size_t total, Body&& body) {
  for (std::size_t first = 0; first < total; first += kChunk) body(first, std::min(kChunk, total - first));
}

// Converts rays [first, first + count) of `rays` into `out` (resized), in parallel.
void gather_rays(const RayArrays& rays, std::size_t first, std::size_t count, std::vector<Ray>& out) {
  out.resize(count);
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096), [&](const auto& range) {
    for (std::size_t k = range.begin(); k != range.end(); ++k) out[k] = rays.at(first + k);
  });
}

template <class Edit>
void edit(AnyStructure& structure, const char* what, Edit&& edit_one) {
  std::visit(
      [&](auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (UpdatableStructure<S>) {
          edit_one(s);
        } else {
          throw Error(std::string(what) + ": the structure " + std::string(S::name()) +
                      " cannot be edited after its build (rebuild it, or use one whose objects move: " +
                      "visfield structures lists them)");
        }
      },
      structure);
}

}  // namespace

void intersect_batch(const AnyStructure& structure, std::span<const Ray> rays, std::span<Hit> hits) {
  if (rays.size() != hits.size()) throw Error("intersect: " + std::to_string(rays.size()) + " rays but room for " + std::to_string(hits.size()) + " hits");
  std::visit([&](const auto& s) { intersect_batch(s, rays, hits); }, structure);
}

void occluded_batch(const AnyStructure& structure, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  if (rays.size() != occluded.size())
    throw Error("occluded: " + std::to_string(rays.size()) + " rays but room for " + std::to_string(occluded.size()) + " answers");
  std::visit([&](const auto& s) { occluded_batch(s, rays, occluded); }, structure);
}

void intersect_arrays(const AnyStructure& structure, const RayArrays& rays, const HitArrays& out) {
  std::vector<Ray> chunk;
  std::vector<Hit> hits;
  for_each_chunk(rays.count, [&](std::size_t first, std::size_t count) {
    gather_rays(rays, first, count, chunk);
    hits.resize(count);
    intersect_batch(structure, chunk, hits);
    vf::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096), [&](const auto& range) {
      for (std::size_t k = range.begin(); k != range.end(); ++k) {
        const Hit& h = hits[k];
        const std::size_t i = first + k;
        out.t.set(i, h.t);
        out.u.set(i, h.u);
        out.v.set(i, h.v);
        out.prim.set(i, h.prim);
        out.instance.set(i, h.instance);
        out.nx.set(i, h.normal.x);
        out.ny.set(i, h.normal.y);
        out.nz.set(i, h.normal.z);
      }
    });
  });
}

void occluded_arrays(const AnyStructure& structure, const RayArrays& rays, const StridedOut<std::uint8_t>& occluded) {
  std::vector<Ray> chunk;
  std::vector<std::uint8_t> answers;
  for_each_chunk(rays.count, [&](std::size_t first, std::size_t count) {
    gather_rays(rays, first, count, chunk);
    answers.resize(count);
    occluded_batch(structure, chunk, answers);
    for (std::size_t k = 0; k < count; ++k) occluded.set(first + k, answers[k]);
  });
}

bool is_updatable(const AnyStructure& structure) {
  return std::visit([](const auto& s) { return UpdatableStructure<std::decay_t<decltype(s)>>; }, structure);
}

void remove_object(AnyStructure& structure, ObjectId id) {
  edit(structure, "remove", [&](auto& s) { s.remove(id); });
}

void insert_object(AnyStructure& structure, const Scene& scene, ObjectId id) {
  edit(structure, "insert", [&](auto& s) { s.insert(scene, id); });
}

void move_object(AnyStructure& structure, ObjectId id, const Transform& t) {
  edit(structure, "move", [&](auto& s) { s.move(id, t); });
}

void commit_objects(AnyStructure& structure) {
  edit(structure, "commit", [&](auto& s) { s.commit(); });
}

}  // namespace vf
