// Building and editing the instance layer: mesh structures built once per mesh, the top level rebuilt
// from the staged objects at every commit.

#include <algorithm>
#include <string>

#include "bvh/binary_builder.hpp"
#include "bvh/collapse.hpp"
#include "instances/instance_layout.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/stopwatch.hpp"

namespace vf {
namespace {

// The top level holds one object per leaf, as Embree's does: an object test costs a ray transform and
// a whole traversal, so a leaf of several objects would rarely be cheaper than one more node.
BvhConfig top_level_config() {
  BvhConfig config;
  config.max_leaf_size = 1;
  return config;
}

void add_stats(AccelStats& total, const AccelStats& part) {
  total.memory_bytes += part.memory_bytes;
  total.node_count += part.node_count;
  total.leaf_count += part.leaf_count;
  total.reference_count += part.reference_count;
}

}  // namespace

InstanceLayer::InstanceLayer() = default;
InstanceLayer::InstanceLayer(InstanceLayer&&) noexcept = default;
InstanceLayer& InstanceLayer::operator=(InstanceLayer&&) noexcept = default;
InstanceLayer::~InstanceLayer() = default;

const AccelStats& InstanceLayer::stats() const { return layout_->stats; }

InstanceLayer InstanceLayer::build(const Scene& scene, MeshStructureBuilder build_mesh) {
  const Stopwatch watch;
  InstanceLayer layer;
  layer.build_mesh_ = std::move(build_mesh);
  layer.layout_ = std::make_unique<instances::InstanceLayout>();
  for (const Instance& inst : scene.instances()) layer.insert(scene, inst.id);
  layer.commit();
  layer.layout_->stats.build_ms = watch.elapsed_ms();
  return layer;
}

std::vector<InstanceLayer::Object>::iterator InstanceLayer::find(ObjectId id) {
  const auto it =
      std::lower_bound(objects_.begin(), objects_.end(), id, [](const Object& o, ObjectId value) { return o.id < value; });
  return it != objects_.end() && it->id == id ? it : objects_.end();
}

void InstanceLayer::remove(ObjectId id) {
  const auto it = find(id);
  if (it == objects_.end()) throw Error("instances: remove: object " + std::to_string(id) + " is not in the structure");
  objects_.erase(it);
  staged_ = true;
}

void InstanceLayer::insert(const Scene& scene, ObjectId id) {
  const Instance& inst = scene.instance(id);
  if (find(id) != objects_.end()) throw Error("instances: insert: object " + std::to_string(id) + " is already in the structure");
  const auto at =
      std::lower_bound(objects_.begin(), objects_.end(), id, [](const Object& o, ObjectId value) { return o.id < value; });
  objects_.insert(at, Object{id, inst.mesh, inst.transform});
  const bool built = inst.mesh < meshes_.size() && meshes_[inst.mesh] != nullptr;
  if (!built && !new_meshes_.contains(inst.mesh)) new_meshes_.emplace(inst.mesh, mesh_triangles(scene.meshes[inst.mesh]));
  staged_ = true;
}

void InstanceLayer::move(ObjectId id, const Transform& transform) {
  const auto it = find(id);
  if (it == objects_.end()) throw Error("instances: move: object " + std::to_string(id) + " is not in the structure");
  if (!transform.is_valid()) throw Error("instances: move: object " + std::to_string(id) + ": the transform must be finite with a scale > 0");
  it->transform = transform;
  staged_ = true;
}

void InstanceLayer::commit() {
  const Stopwatch watch;
  // Mesh structures: build the new ones, keep those still used, drop the rest.
  for (auto& [mesh, triangles] : new_meshes_) {
    if (mesh >= meshes_.size()) {
      meshes_.resize(mesh + 1);
      mesh_bounds_.resize(mesh + 1);
    }
    meshes_[mesh] = std::make_shared<const MeshStructure>(build_mesh_(triangles));
    mesh_bounds_[mesh] = triangles.bounds;
  }
  new_meshes_.clear();
  std::vector<std::uint8_t> used(meshes_.size(), 0);
  for (const Object& o : objects_) used[o.mesh] = 1;
  for (std::size_t m = 0; m < meshes_.size(); ++m)
    if (!used[m]) meshes_[m].reset();

  auto layout = std::make_unique<instances::InstanceLayout>();
  layout->meshes = meshes_;
  // Objects whose mesh has no triangle left (all of zero area) can never be hit.
  std::vector<const Object*> placed;
  std::vector<Bounds3f> boxes;
  for (const Object& o : objects_) {
    if (mesh_bounds_[o.mesh].empty()) continue;
    placed.push_back(&o);
    boxes.push_back(o.transform.apply_bounds(mesh_bounds_[o.mesh]));
  }
  const bvh::BinaryTree tree = bvh::build_binary_tree(boxes, top_level_config(), 1);
  layout->placed.reserve(placed.size());
  bvh::collapse_to_wide(tree, layout->nodes, layout->stats, [&](const bvh::BinaryNode& leaf) {
    const auto first = static_cast<std::uint32_t>(layout->placed.size());
    for (std::uint32_t j = 0; j < leaf.count; ++j) {
      const Object& o = *placed[tree.order[leaf.begin + j]];
      layout->placed.push_back({o.transform.inverse(), o.transform, o.id, meshes_[o.mesh].get()});
    }
    layout->stats.reference_count += leaf.count;
    return bvh::leaf_ref(first, leaf.count);
  });

  AccelStats& s = layout->stats;
  s.memory_bytes = layout->nodes.capacity() * sizeof(bvh::Node8) +
                   layout->placed.capacity() * sizeof(instances::PlacedObject);
  int mesh_depth = 0;
  for (const std::shared_ptr<const MeshStructure>& mesh : meshes_) {
    if (!mesh) continue;
    const AccelStats part = std::visit([](const auto& m) { return m.stats(); }, *mesh);
    add_stats(s, part);
    mesh_depth = std::max(mesh_depth, part.max_depth);
  }
  s.max_depth += mesh_depth;
  s.build_ms = watch.elapsed_ms();
  layout_ = std::move(layout);
  staged_ = false;
}

}  // namespace vf
