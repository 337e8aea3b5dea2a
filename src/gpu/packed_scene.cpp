#include "visfield/gpu/packed_scene.hpp"

#include <algorithm>
#include <cstring>

#include "visfield/core/error.hpp"
#include "visfield/core/triangle_set.hpp"

namespace vf::gpu {
namespace {

// FieldForm::defaults is ObjectFieldConfig's defaults.
constexpr field::ObjectFieldConfig kDefaultConfig{};
static_assert(kDefaultConfig.mapping == field::HemisphereMapping::concentric_malley && kDefaultConfig.storage == field::CellStorage::u8 &&
                  kDefaultConfig.normals == field::NormalStorage::none &&
                  kDefaultConfig.direction_lookup == field::DirectionLookup::nearest &&
                  kDefaultConfig.position_lookup == field::PositionLookup::nearest &&
                  kDefaultConfig.sample_line == field::SampleLine::through,
              "FieldForm::defaults (gpu/field_scene_view.hpp) must be ObjectFieldConfig's default choices");

/// Appends `bytes` bytes from `data` to `buffer` at the next kTableAlignment boundary and returns
/// where they start, or kNoTable when there is nothing to append. `padding` zero bytes follow (the
/// field's own tables end with 4, so that a 32-bit read at any cell stays inside).
unsigned long long append(std::vector<unsigned char>& buffer, const void* data, std::size_t bytes, std::size_t padding = 0) {
  if (bytes == 0 || data == nullptr) return kNoTable;
  const std::size_t start = (buffer.size() + kTableAlignment - 1) / kTableAlignment * kTableAlignment;
  buffer.resize(start + bytes + padding, 0);
  std::memcpy(buffer.data() + start, data, bytes);
  return start;
}

/// One field's tables appended to `buffer`, and its slot.
FieldSlot pack_field(const field::ObjectField& f, std::vector<unsigned char>& buffer) {
  FieldSlot slot;
  slot.tables = f.tables();
  const field::FieldTables& t = slot.tables;
  const std::size_t side = static_cast<std::size_t>(t.lattice_n) + 1;
  slot.upper = append(buffer, t.upper, static_cast<std::size_t>(t.upper_count) * sizeof(hd::Vec3<float>));
  slot.quadrant = append(buffer, t.quadrant, side * side * sizeof(unsigned long long));
  slot.cells = append(buffer, f.cell_table().data(), f.cell_table().size(), 4);
  slot.averages = append(buffer, f.averages().data(), f.averages().size() * sizeof(float));
  slot.normal_cells = append(buffer, f.normal_table().data(), f.normal_table().size(), 4);
  slot.cell_centres = append(buffer, t.cell_centres, static_cast<std::size_t>(t.directions) * static_cast<std::size_t>(t.directions) * sizeof(hd::Vec3<float>));
  slot.tables.upper = nullptr;
  slot.tables.quadrant = nullptr;
  slot.tables.cells = nullptr;
  slot.tables.averages = nullptr;
  slot.tables.normal_cells = nullptr;
  slot.tables.cell_centres = nullptr;
  return slot;
}

/// Appends to `nodes` the subtree over items[begin, end) (indices into `boxes`) at node `at`,
/// split at the median centroid of the widest axis (ties by index: the same tree every time).
void build_subtree(const std::vector<Bounds3f>& boxes, std::vector<unsigned int>& items, unsigned int begin, unsigned int end,
                   unsigned int at, int depth, std::vector<ObjectNode>& nodes) {
  if (depth >= kObjectStack) throw Error("packed field scene: the tree over the objects is too deep");
  Bounds3f box, centres;
  for (unsigned int i = begin; i < end; ++i) {
    box.extend(boxes[items[i]]);
    centres.extend((boxes[items[i]].lo + boxes[items[i]].hi) * 0.5f);
  }
  ObjectNode& node = nodes[at];
  for (int a = 0; a < 3; ++a) node.lo[a] = box.lo[a], node.hi[a] = box.hi[a];
  if (end - begin <= kObjectLeafSize) {
    node.first = begin;
    node.count = end - begin;
    return;
  }
  const Vec3f e = centres.extent();
  const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
  const unsigned int mid = begin + (end - begin) / 2;
  std::nth_element(items.begin() + begin, items.begin() + mid, items.begin() + end, [&](unsigned int a, unsigned int b) {
    const float ca = boxes[a].lo[axis] + boxes[a].hi[axis], cb = boxes[b].lo[axis] + boxes[b].hi[axis];
    return ca < cb || (ca == cb && a < b);
  });
  const auto children = static_cast<unsigned int>(nodes.size());
  node.first = children;
  node.count = kInteriorNode + static_cast<unsigned int>(axis);
  nodes.resize(nodes.size() + 2);  // `node` is not used past this point
  build_subtree(boxes, items, begin, mid, children, depth + 1, nodes);
  build_subtree(boxes, items, mid, end, children + 1, depth + 1, nodes);
}

}  // namespace

PackedFieldScene PackedFieldScene::pack(const Scene& scene, const field::FieldScene& fields) {
  PackedFieldScene out;
  std::vector<unsigned int> slot_of(scene.meshes.size(), ~0u);
  for (std::uint32_t mesh = 0; mesh < scene.meshes.size(); ++mesh) {
    const field::ObjectField* f = fields.mesh_field(mesh);
    if (!f) continue;
    slot_of[mesh] = static_cast<unsigned int>(out.slots_.size());
    out.slots_.push_back(pack_field(*f, out.buffer_));
  }
  // FieldScene::build's split: an object whose mesh has a field is a field object, in id order;
  // every other object's world-space triangles go to the exact part, in id order.
  TriangleSet exact;
  for (const Instance& object : scene.instances()) {
    const field::ObjectField* f = fields.mesh_field(object.mesh);
    if (!f) {
      const TriangleSet part = object_triangles(scene.meshes[object.mesh], object.transform, object.id);
      exact.triangles.insert(exact.triangles.end(), part.triangles.begin(), part.triangles.end());
      exact.prim.insert(exact.prim.end(), part.prim.begin(), part.prim.end());
      exact.instance.insert(exact.instance.end(), part.instance.begin(), part.instance.end());
      exact.bounds.extend(part.bounds);
      continue;
    }
    const field::BoundingSphere& s = f->sphere();
    out.objects_.push_back(FieldObject{object.id, slot_of[object.mesh], object.transform.inverse(), object.transform.rotation,
                                       object.transform.apply_point(s.centre), s.radius * object.transform.scale});
  }
  out.exact_ = GpuBvh::build(exact);
  out.host_tables_ = out.tables_at(out.buffer_.data());
  if (fields.uses_tree()) {
    const std::vector<Bounds3f> boxes = fields.object_boxes();  // FieldScene's objects are these, in this order
    if (boxes.size() != out.objects_.size()) throw Error("packed field scene: the field scene was built over another scene");
    out.tree_items_.resize(boxes.size());
    for (unsigned int k = 0; k < out.tree_items_.size(); ++k) out.tree_items_[k] = k;
    out.tree_nodes_.resize(1);
    build_subtree(boxes, out.tree_items_, 0, static_cast<unsigned int>(boxes.size()), 0, 0, out.tree_nodes_);
  }
  const auto is_default = [](const FieldSlot& slot) { return has_form(slot.tables, FieldForm::defaults); };
  if (!out.slots_.empty() && std::all_of(out.slots_.begin(), out.slots_.end(), is_default)) out.form_ = FieldForm::defaults;
  return out;
}

std::vector<field::FieldTables> PackedFieldScene::tables_at(const unsigned char* base) const {
  std::vector<field::FieldTables> tables;
  tables.reserve(slots_.size());
  for (const FieldSlot& slot : slots_) tables.push_back(slot.rebase(base));
  return tables;
}

FieldSceneView PackedFieldScene::view(const std::vector<field::FieldTables>& tables) const {
  return FieldSceneView{tables.data(), objects_.data(), static_cast<unsigned int>(objects_.size()), exact_.view(), form_, tree_view()};
}

// The host answers through the queries a device compiles for the same form, so that the unit tests
// pin those too.
Hit PackedFieldScene::intersect(const Ray& ray) const {
  const FieldSceneView v = view(host_tables_);
  return form_ == FieldForm::defaults ? gpu::intersect<kStackSize, FieldForm::defaults>(v, ray) : gpu::intersect(v, ray);
}

bool PackedFieldScene::occluded(const Ray& ray) const {
  const FieldSceneView v = view(host_tables_);
  return form_ == FieldForm::defaults ? gpu::occluded<kStackSize, FieldForm::defaults>(v, ray) : gpu::occluded(v, ray);
}

std::size_t PackedFieldScene::device_bytes() const {
  return buffer_.size() + slots_.size() * sizeof(field::FieldTables) + objects_.size() * sizeof(FieldObject) +
         tree_nodes_.size() * sizeof(ObjectNode) + tree_items_.size() * sizeof(unsigned int) +
         exact_.stats().memory_bytes;
}

}  // namespace vf::gpu
