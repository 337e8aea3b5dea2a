#include "visfield/cuda/device_scene.hpp"

#include <span>
#include <vector>

namespace vf::cuda {

DeviceBvh DeviceBvh::upload(const gpu::GpuBvh& bvh) {
  DeviceBvh d;
  d.nodes_ = DeviceArray<gpu::WideNode>::from(std::span<const gpu::WideNode>(bvh.nodes()));
  d.triangles_ = DeviceArray<gpu::WideTriangle>::from(std::span<const gpu::WideTriangle>(bvh.triangles()));
  d.prim_ = DeviceArray<std::uint32_t>::from(std::span<const std::uint32_t>(bvh.prim()));
  d.instance_ = DeviceArray<std::uint32_t>::from(std::span<const std::uint32_t>(bvh.instance()));
  d.stack_bound_ = bvh.stack_bound();
  return d;
}

gpu::BvhView DeviceBvh::view() const {
  return gpu::BvhView{nodes_.data(), triangles_.data(), prim_.data(), instance_.data(), static_cast<unsigned int>(nodes_.size()),
                      stack_bound_};
}

DeviceFieldScene DeviceFieldScene::upload(const gpu::PackedFieldScene& packed, FieldKernels kernels) {
  DeviceFieldScene d;
  d.buffer_ = DeviceBuffer(packed.buffer().size());
  d.buffer_.upload(packed.buffer().data(), packed.buffer().size());
  // The slots' offsets become pointers into the device copy: computed here, read there.
  const std::vector<field::FieldTables> tables = packed.tables_at(static_cast<const unsigned char*>(d.buffer_.data()));
  d.tables_ = DeviceArray<field::FieldTables>::from(std::span<const field::FieldTables>(tables));
  d.objects_ = DeviceArray<gpu::FieldObject>::from(std::span<const gpu::FieldObject>(packed.objects()));
  d.exact_ = DeviceBvh::upload(packed.exact());
  if (kernels == FieldKernels::fitted) d.form_ = packed.form();
  d.tree_nodes_ = DeviceArray<gpu::ObjectNode>::from(std::span<const gpu::ObjectNode>(packed.tree_nodes()));
  d.tree_items_ = DeviceArray<unsigned int>::from(std::span<const unsigned int>(packed.tree_items()));
  return d;
}

gpu::FieldSceneView DeviceFieldScene::view() const {
  return gpu::FieldSceneView{tables_.data(), objects_.data(), static_cast<unsigned int>(objects_.size()), exact_.view(), form_,
                            gpu::ObjectTreeView{tree_nodes_.data(), tree_items_.data(), static_cast<unsigned int>(tree_nodes_.size())}};
}

}  // namespace vf::cuda
