// Builds a built-in scene and a BVH through the installed package, traces one ray.
#include <cstdio>

#include "visfield/accel/bvh.hpp"
#include "visfield/scenes/builtin.hpp"

int main() {
  const vf::Scene scene = vf::make_builtin_scene("sphere", {});
  const vf::Bvh bvh = vf::Bvh::build(vf::flatten(scene));
  const vf::Vec3f c = scene.bounds().center();
  const auto hit = bvh.intersect(vf::Ray{{c.x, c.y + 1000.0f, c.z}, {0.0f, -1.0f, 0.0f}});
  std::printf("hit: %s\n", hit ? "yes" : "no");
  return hit ? 0 : 1;
}
