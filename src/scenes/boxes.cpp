// "boxes": a stepped pyramid of boxes on a ground plane. Every box is an instance of one cube mesh
// (so instancing is exercised), with a small seeded yaw and colour per box.

#include <cmath>

#include "generators.hpp"
#include "mesh_builders.hpp"
#include "visfield/core/rng.hpp"

namespace vf::scenes {
namespace {

constexpr float kBoxSize = 0.9f;      // edge length; boxes sit on a 1.0 grid, so a gap of 0.1 separates them
constexpr float kMaxYawDegrees = 5.0f;  // a 0.9 box turned by 5 degrees still fits in its 1.0 cell

}  // namespace

Scene make_boxes_scene(std::uint64_t seed, std::size_t box_count) {
  Scene scene;
  const std::uint32_t ground = add_material(scene, make_material("ground", Vec3f{0.7f}));
  const Vec3f palette[] = {{0.8f, 0.3f, 0.25f}, {0.25f, 0.5f, 0.8f}, {0.85f, 0.75f, 0.3f}, {0.35f, 0.7f, 0.4f},
                           {0.75f, 0.75f, 0.75f}};
  const auto first_colour = static_cast<std::uint32_t>(scene.materials.size());
  for (const Vec3f& colour : palette) add_material(scene, make_material("box", colour));

  // Base layer side: the smallest b with 1 + 4 + ... + b^2 >= box_count; layers are filled bottom-up,
  // so only the top layer may be partial.
  std::size_t base = 1;
  while (base * (base + 1) * (2 * base + 1) / 6 < box_count) ++base;

  scene.meshes.push_back(make_ground_mesh("ground", 0.0f, 0.0f, 4.0f * static_cast<float>(base) + 4.0f, 0.0f, ground));
  scene.meshes.push_back(make_box_mesh("cube", {Vec3f{-0.5f}, Vec3f{0.5f}}));
  scene.add_instance(Instance{});

  std::size_t placed = 0;
  for (std::size_t layer = 0; placed < box_count; ++layer) {
    const std::size_t side = base - layer;
    const float offset = -0.5f * static_cast<float>(side - 1);
    for (std::size_t row = 0; row < side && placed < box_count; ++row) {
      for (std::size_t col = 0; col < side && placed < box_count; ++col, ++placed) {
        Rng rng(seed, placed);
        Instance box;
        box.mesh = 1;
        box.transform.scale = kBoxSize;
        box.transform.rotation = Mat3::rotation({0, 1, 0}, kMaxYawDegrees * (2.0f * rng.uniform() - 1.0f));
        box.transform.translation = {offset + static_cast<float>(col), (static_cast<float>(layer) + 0.5f) * kBoxSize,
                                     offset + static_cast<float>(row)};
        box.material = first_colour + static_cast<std::uint32_t>(rng.next_u32() % std::size(palette));
        scene.add_instance(box);
      }
    }
  }

  Bounds3f pyramid;
  for (std::size_t i = 1; i < scene.instances().size(); ++i)
    pyramid.extend(scene.instances()[i].transform.apply_bounds(scene.meshes[1].bounds()));
  pyramid.extend(Vec3f{pyramid.lo.x - 1.0f, 0.0f, pyramid.lo.z - 1.0f});  // some ground around the base
  pyramid.extend(Vec3f{pyramid.hi.x + 1.0f, 0.0f, pyramid.hi.z + 1.0f});
  scene.camera = framing_camera(pyramid, {0.6f, 0.55f, 1.0f}, 40.0f);
  const float height = pyramid.hi.y;
  scene.point_lights.push_back(PointLight{{0.5f * static_cast<float>(base), 3.0f * height + 3.0f, static_cast<float>(base) + 2.0f},
                                          Vec3f{4.0f * (height + 2.0f) * (height + 2.0f)}});
  return scene;
}

}  // namespace vf::scenes
