#pragma once
/// \file Memory layout of the committed InstanceLayer (private to the accel module): the top level's
/// 8-wide nodes, whose leaves are runs of placed objects.

#include <memory>
#include <vector>

#include "bvh/wide_nodes.hpp"
#include "visfield/accel/aligned_vector.hpp"
#include "visfield/accel/instance_layer.hpp"

namespace vf::instances {

/// One object as the queries need it.
struct PlacedObject {
  InverseTransform to_object;  ///< World rays into object space.
  Transform to_world;          ///< Object normals back to world space.
  ObjectId id = kInvalidId;
  const MeshStructure* mesh = nullptr;  ///< Owned by InstanceLayout::meshes.
};

/// The committed state: the mesh structures in use (shared with the layer), the objects in leaf
/// order and the top level's nodes (nodes[0] the root whenever there is an object).
struct InstanceLayout {
  std::vector<std::shared_ptr<const MeshStructure>> meshes;
  std::vector<PlacedObject> placed;
  AlignedVector<bvh::Node8> nodes;
  AccelStats stats;
};

}  // namespace vf::instances
