#pragma once
/// \file A scene: meshes, instances of them, materials, camera and lights.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "visfield/core/mesh.hpp"
#include "visfield/core/transform.hpp"

namespace vf {

/// Simple material: Lambertian colour plus an optional mirror/glossy lobe and emission.
struct Material {
  std::string name = "default";
  Vec3f diffuse{0.8f};        ///< Diffuse albedo in [0,1].
  Vec3f specular{0.0f};       ///< Mirror/glossy reflectance in [0,1]; zero means purely diffuse.
  float roughness = 0.0f;     ///< 0 = perfect mirror, up to 1 = very glossy lobe.
  Vec3f emission{0.0f};       ///< Emitted radiance (area lights from meshes).
};

/// One placement of a mesh in the world.
struct Instance {
  std::uint32_t mesh = 0;                        ///< Index into Scene::meshes.
  Transform transform;                           ///< Object to world.
  std::optional<std::uint32_t> material;         ///< Overrides the mesh's per-triangle materials when set.
};

/// Pinhole camera; fov is the vertical field of view in degrees.
struct Camera {
  Vec3f position{0.0f, 0.0f, 1.0f};
  Vec3f look_at{0.0f};
  Vec3f up{0.0f, 1.0f, 0.0f};
  float fov_degrees = 45.0f;
  int width = 512;
  int height = 512;
};

/// Isotropic point light; intensity in W/sr per channel.
struct PointLight {
  Vec3f position;
  Vec3f intensity{1.0f};
};

/// Spherical area light of uniform radiance.
struct SphereLight {
  Vec3f center;
  float radius = 1.0f;
  Vec3f radiance{1.0f};
};

/// Everything a render needs. Value type; meshes are shared by index between instances.
struct Scene {
  std::string name;                      ///< For messages and reports.
  std::vector<TriangleMesh> meshes;
  std::vector<Instance> instances;
  std::vector<Material> materials{Material{}};  ///< Index 0 is the default material.
  std::optional<Camera> camera;                 ///< When absent, frame_camera() chooses one.
  std::vector<PointLight> point_lights;
  std::vector<SphereLight> sphere_lights;

  /// World-space bounds of all instances; O(instances * 8) using mesh bounds.
  Bounds3f bounds() const;
  /// Total triangles over all instances.
  std::size_t instanced_triangle_count() const;
  /// The scene camera (resized when width/height > 0), or one framing the bounds from the front (+z)
  /// when the scene has none.
  Camera camera_or_default(int width, int height) const;
  /// Unit world-space geometric normal of the triangle a hit names (instance, prim); not flipped.
  Vec3f geometric_normal(std::uint32_t instance, std::uint32_t prim) const;
  /// Material of triangle `prim` of instance `instance` (instance override, else per-triangle id, else 0).
  const Material& material_of(std::uint32_t instance, std::uint32_t prim) const;
};

/// A scene holding one mesh with one identity instance.
Scene scene_from_mesh(TriangleMesh mesh);

}  // namespace vf
