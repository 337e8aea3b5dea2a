#pragma once
/// \file A scene: meshes, objects (instances of them) with stable ids, materials, camera and lights.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "visfield/core/animation.hpp"
#include "visfield/core/mesh.hpp"
#include "visfield/core/ray.hpp"
#include "visfield/core/transform.hpp"

namespace vf {

/// Simple material: Lambertian colour plus an optional mirror/glossy lobe, refraction and emission
/// (render/bsdf.hpp says how the integrators combine them).
struct Material {
  std::string name = "default";
  Vec3f diffuse{0.8f};        ///< Diffuse albedo in [0,1].
  Vec3f specular{0.0f};       ///< Mirror/glossy reflectance in [0,1]; zero means purely diffuse.
  float roughness = 0.0f;     ///< 0 = perfect mirror, up to 1 = very glossy lobe (GGX alpha = roughness^2).
  Vec3f emission{0.0f};       ///< Emitted radiance (area lights from meshes).
  float transmission = 0.0f;  ///< In [0,1]: the fraction that is a smooth dielectric (glass); 0 = opaque.
  float ior = 1.5f;           ///< Index of refraction of a transmissive material (>= 1).
};

/// One object of a scene: a placement of a mesh in the world.
struct Instance {
  ObjectId id = kInvalidId;                      ///< Set by Scene::add_instance; stable for the object's life.
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
  /// Stands in for an emitting surface of the scene (the Cornell room's ceiling lamp) for the
  /// integrators that light by point lights; the path tracer, which samples that surface itself, skips it.
  bool proxy = false;
};

/// Spherical area light of uniform radiance.
struct SphereLight {
  Vec3f center;
  float radius = 1.0f;
  Vec3f radiance{1.0f};
};

/// Everything a render needs. Value type (copies are deep). Meshes are shared by index between
/// objects; objects are added, moved and removed through the methods below, which keep their ids
/// stable (an id is never reused, and edits do not renumber other objects). Not thread-safe to edit.
class Scene {
 public:
  std::string name;                      ///< For messages and reports.
  std::vector<TriangleMesh> meshes;      ///< Object-space meshes; only ever appended to.
  std::vector<Material> materials{Material{}};  ///< Index 0 is the default material.
  std::optional<Camera> camera;                 ///< When absent, camera_or_default() chooses one.
  std::vector<PointLight> point_lights;
  std::vector<SphereLight> sphere_lights;
  SceneAnimation animation;  ///< Keyframed camera and object motion for walkthroughs (scene JSON "camera_path", "keyframes").

  /// Adds an object (`instance.id` is ignored) and returns its new id, larger than every id given
  /// before. Throws vf::Error when the mesh or material index is out of range or the transform is
  /// not a rotation, a finite translation and a finite scale > 0 (Transform::is_valid). O(1) amortised.
  ObjectId add_instance(Instance instance);
  /// Adds an object of mesh `mesh` placed by `transform`; see above.
  ObjectId add_instance(std::uint32_t mesh, const Transform& transform = {});
  /// Removes object `id`; throws vf::Error when no object has that id. O(objects).
  void remove_instance(ObjectId id);
  /// Moves object `id` to `transform`; throws vf::Error on an unknown id or a bad transform. O(log objects).
  void set_transform(ObjectId id, const Transform& transform);
  /// The objects, in increasing id order.
  const std::vector<Instance>& instances() const { return instances_; }
  /// The object with id `id`; throws vf::Error when there is none. O(log objects).
  const Instance& instance(ObjectId id) const;
  /// The object with id `id`, or nullptr. O(log objects).
  const Instance* find_instance(ObjectId id) const;

  /// World-space bounds of all objects: each mesh's bounds once, then 8 corners an object.
  Bounds3f bounds() const;
  /// Throws vf::Error "<what>: object ID (mesh ...) reaches coordinate ..." for the first object whose
  /// world-space bounds reach beyond ±kMaxCoordinate (through its translation or scale).
  /// O(vertices of the meshes + objects).
  void check_coordinate_range(const std::string& what) const;
  /// Total triangles over all objects.
  std::size_t instanced_triangle_count() const;
  /// The scene camera (resized when width/height > 0), or, when the scene has none, the three-quarter
  /// view framed_view(*this, +Y, kDefaultAzimuth, kDefaultElevation, 45°, width, height).
  Camera camera_or_default(int width, int height) const;
  /// Material of triangle `prim` of object `id` (instance override, else per-triangle id, else 0). A hit
  /// without a triangle (prim == kInvalidId, a field's answer) gets the override, else the mesh's first
  /// triangle's material.
  const Material& material_of(ObjectId id, std::uint32_t prim) const;

 private:
  std::vector<Instance> instances_;
  ObjectId next_id_ = 0;
};

/// A camera looking at the centre of `target` from `view_direction` (need not be unit), far enough
/// that the bounding sphere of `target` fills the vertical field of view `fov_degrees` with a 5% margin.
Camera framing_camera(const Bounds3f& target, const Vec3f& view_direction, float fov_degrees);

/// The default view's angles in degrees (Scene::camera_or_default(), `visfield render --up` alone): a
/// three-quarter view from the front-right and above.
inline constexpr float kDefaultAzimuth = 35.0f;
inline constexpr float kDefaultElevation = 25.0f;

/// A camera looking at every object of `scene` from `azimuth_degrees` around the world axis `up`
/// (0 = the front: +Z for up +Y, -Y for up +Z, -Z for up +X; positive turns towards the right) and
/// `elevation_degrees` above the horizon ([-90, 90]; at ±90 the image's up is the far side), with a
/// vertical field of view `fov_degrees`, `width` x `height` pixels (0: 512). It is shifted and moved
/// as close as keeps every vertex inside 90% of the image's half-width and half-height, centred: the
/// scene's projection spans 90% of the image along its tighter side. Scenes over a million vertices
/// are framed by their objects' bounding boxes instead. Throws vf::Error when `up` is zero or not
/// finite, an angle is out of range or the fov is outside (0, 180).
Camera framed_view(const Scene& scene, const Vec3f& up, float azimuth_degrees, float elevation_degrees, float fov_degrees,
                   int width, int height);

/// A scene holding one mesh with one identity object.
Scene scene_from_mesh(TriangleMesh mesh);

}  // namespace vf
