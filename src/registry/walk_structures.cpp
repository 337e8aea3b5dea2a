#include "visfield/registry/walk_structures.hpp"

namespace vf {

RegistryWalkStructures::RegistryWalkStructures(const Scene& scene, std::string accel, std::string occluder, const BuildContext& context)
    : accel_spec_(std::move(accel)), occluder_spec_(std::move(occluder)), context_(context) {
  build(scene, true, !occluder_spec_.empty());
}

void RegistryWalkStructures::build(const Scene& scene, bool closest, bool occluder) {
  SceneGeometry geometry(scene);
  if (closest) closest_.emplace(build_structure(accel_spec_, geometry, context_));
  if (occluder) occluder_.emplace(build_structure(occluder_spec_, geometry, context_, "--occluder "));
  queries_ = scene_queries(closest_->structure, occluder_ ? occluder_->structure : closest_->structure);
}

bool RegistryWalkStructures::follow(const Scene& scene, std::span<const ObjectId> moved) {
  // Try the in-place update object by object; a structure that cannot update is rebuilt once.
  // A BeamField whose object left its bounding sphere rebuilt itself inside commit(): that counts too.
  bool rebuilt_inside = false;
  auto updated = [&](BuiltStructure& built) {
    for (const ObjectId id : moved) {
      if (!update_in_place(built.structure, id, scene.instance(id).transform)) return false;
      if (const auto* beam = std::get_if<BeamField>(&built.structure)) rebuilt_inside |= beam->beam_stats().last_commit_rebuilt;
    }
    return true;
  };
  const bool rebuild_closest = !updated(*closest_);
  const bool rebuild_occluder = occluder_ && !updated(*occluder_);
  if (rebuild_closest || rebuild_occluder) build(scene, rebuild_closest, rebuild_occluder);
  return rebuild_closest || rebuild_occluder || rebuilt_inside;
}

std::string RegistryWalkStructures::label() const {
  return closest_->resolved + (occluder_ ? " + " + occluder_->resolved : std::string());
}

}  // namespace vf
