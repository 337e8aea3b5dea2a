#pragma once
/// \file Walkthrough structures built from registry specs (what `visfield walk --accel` names).

#include <memory>
#include <optional>
#include <string>

#include "visfield/registry/registry.hpp"
#include "visfield/render/walkthrough.hpp"

namespace vf {

/// WalkStructures over registry specs: camera rays through `accel`, every other ray through
/// `occluder` ("" = the accel structure). An updatable structure (BeamField) moves the objects in
/// place; any other is rebuilt over the moved scene. Not thread-safe.
class RegistryWalkStructures final : public WalkStructures {
 public:
  /// Builds both structures over `scene` as it is now; throws vf::Error on a bad spec or build.
  RegistryWalkStructures(const Scene& scene, std::string accel, std::string occluder, const BuildContext& context);
  bool follow(const Scene& scene, std::span<const ObjectId> moved) override;
  const SceneQueries& queries() const override { return *queries_; }
  /// The camera structure as resolved, and the occluder's after " + " when there is one.
  std::string label() const override;

 private:
  void build(const Scene& scene, bool closest, bool occluder);
  std::string accel_spec_, occluder_spec_;
  BuildContext context_;
  std::optional<BuiltStructure> closest_, occluder_;
  std::unique_ptr<SceneQueries> queries_;
};

}  // namespace vf
