#include "visfield/core/scene.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "visfield/core/error.hpp"

namespace vf {
namespace {

void check_transform(const Transform& t, const std::string& what) {
  if (!t.is_valid())
    throw Error(what + ": the transform must be a rotation (orthonormal, determinant +1), a finite translation and a finite scale > 0");
}

}  // namespace

ObjectId Scene::add_instance(Instance instance) {
  if (instance.mesh >= meshes.size())
    throw Error("scene: instance of mesh " + std::to_string(instance.mesh) + ", but the scene has " +
                std::to_string(meshes.size()) + " meshes");
  if (instance.material && *instance.material >= materials.size())
    throw Error("scene: instance material " + std::to_string(*instance.material) + " is out of range (" +
                std::to_string(materials.size()) + " materials)");
  check_transform(instance.transform, "scene: instance of mesh " + std::to_string(instance.mesh));
  if (next_id_ == kInvalidId) throw Error("scene: no object ids left");
  instance.id = next_id_++;
  instances_.push_back(instance);
  return instance.id;
}

ObjectId Scene::add_instance(std::uint32_t mesh, const Transform& transform) {
  return add_instance(Instance{kInvalidId, mesh, transform, std::nullopt});
}

const Instance* Scene::find_instance(ObjectId id) const {
  const auto it = std::lower_bound(instances_.begin(), instances_.end(), id,
                                   [](const Instance& a, ObjectId b) { return a.id < b; });
  return it != instances_.end() && it->id == id ? &*it : nullptr;
}

const Instance& Scene::instance(ObjectId id) const {
  const Instance* found = find_instance(id);
  if (!found) throw Error("scene: no object has id " + std::to_string(id));
  return *found;
}

void Scene::remove_instance(ObjectId id) {
  const Instance& found = instance(id);
  instances_.erase(instances_.begin() + (&found - instances_.data()));
}

void Scene::set_transform(ObjectId id, const Transform& transform) {
  const Instance& found = instance(id);
  check_transform(transform, "scene: object " + std::to_string(id));
  instances_[static_cast<std::size_t>(&found - instances_.data())].transform = transform;
}

namespace {
// Each mesh's bounds, read once however many objects share it (1,024 copies of a 35K-vertex mesh
// read 36M vertices when each object read its mesh's).
std::vector<Bounds3f> bounds_of_meshes(const std::vector<TriangleMesh>& meshes) {
  std::vector<Bounds3f> bounds;
  bounds.reserve(meshes.size());
  for (const TriangleMesh& mesh : meshes) bounds.push_back(mesh.bounds());
  return bounds;
}
}  // namespace

Bounds3f Scene::bounds() const {
  const std::vector<Bounds3f> mesh_bounds = bounds_of_meshes(meshes);
  Bounds3f b;
  for (const Instance& inst : instances_) b.extend(inst.transform.apply_bounds(mesh_bounds[inst.mesh]));
  return b;
}

void Scene::check_coordinate_range(const std::string& what) const {
  const std::vector<Bounds3f> mesh_bounds = bounds_of_meshes(meshes);
  for (const Instance& inst : instances_) {
    const Bounds3f world = inst.transform.apply_bounds(mesh_bounds[inst.mesh]);
    if (world.empty()) continue;
    const float reach = std::fmax(max_component(abs(world.lo)), max_component(abs(world.hi)));
    if (!(reach <= kMaxCoordinate)) {
      std::ostringstream msg;
      msg << what << ": object " << inst.id << " (mesh " << inst.mesh
          << (meshes[inst.mesh].name.empty() ? "" : " \"" + meshes[inst.mesh].name + "\"") << ") reaches coordinate "
          << reach << " in world space, beyond the ±" << kMaxCoordinate << " visfield supports";
      throw Error(msg.str());
    }
  }
}

std::size_t Scene::instanced_triangle_count() const {
  std::size_t n = 0;
  for (const Instance& inst : instances_) n += meshes[inst.mesh].triangles.size();
  return n;
}

Camera framing_camera(const Bounds3f& target, const Vec3f& view_direction, float fov_degrees) {
  Camera camera;
  camera.fov_degrees = fov_degrees;
  const float radius = 0.5f * length(target.extent());
  const float half_fov = 0.5f * fov_degrees * std::numbers::pi_v<float> / 180.0f;
  camera.look_at = target.center();
  camera.position = camera.look_at + normalize(view_direction) * (radius / std::sin(half_fov) * 1.05f);
  return camera;
}

Camera Scene::camera_or_default(int width, int height) const {
  if (!camera) return framed_view(*this, Vec3f{0.0f, 1.0f, 0.0f}, kDefaultAzimuth, kDefaultElevation, Camera{}.fov_degrees, width, height);
  Camera c = *camera;
  if (width > 0) c.width = width;
  if (height > 0) c.height = height;
  return c;
}

namespace {

// The points a framing keeps in view: every object's vertices, or each object's 8 box corners when
// there are more than a million vertices in all (or the scene's 8 when even those are too many).
std::vector<Vec3f> framing_points(const Scene& scene) {
  constexpr std::size_t kMaxPoints = 1u << 20;
  std::size_t vertices = 0;
  for (const Instance& inst : scene.instances()) vertices += scene.meshes[inst.mesh].positions.size();
  std::vector<Vec3f> points;
  auto corners = [&points](const Bounds3f& b) {
    if (b.empty()) return;
    for (int k = 0; k < 8; ++k) points.push_back(Vec3f{(k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z});
  };
  if (vertices <= kMaxPoints) {
    points.reserve(vertices);
    for (const Instance& inst : scene.instances())
      for (const Vec3f& p : scene.meshes[inst.mesh].positions) points.push_back(inst.transform.apply_point(p));
  } else if (8 * scene.instances().size() <= kMaxPoints) {
    const std::vector<Bounds3f> mesh_bounds = bounds_of_meshes(scene.meshes);
    for (const Instance& inst : scene.instances()) corners(inst.transform.apply_bounds(mesh_bounds[inst.mesh]));
  } else {
    corners(scene.bounds());
  }
  return points;
}

}  // namespace

Camera framed_view(const Scene& scene, const Vec3f& up, float azimuth_degrees, float elevation_degrees, float fov_degrees,
                   int width, int height) {
  if (!is_finite(up) || !(length(up) > 0.0f)) throw Error("view: the up direction must be finite and non-zero");
  if (!std::isfinite(azimuth_degrees)) throw Error("view: the azimuth must be a finite number of degrees");
  if (!(elevation_degrees >= -90.0f && elevation_degrees <= 90.0f))
    throw Error("view: the elevation must be within [-90, 90] degrees, got " + std::to_string(elevation_degrees));
  if (!(fov_degrees > 0.0f && fov_degrees < 180.0f)) throw Error("view: the field of view must be in (0, 180) degrees");
  Camera camera;
  camera.fov_degrees = fov_degrees;
  if (width > 0) camera.width = width;
  if (height > 0) camera.height = height;

  // The view's frame: `u` up, `f` the front (azimuth 0), `r` the right; `w` points from the scene to the camera.
  const Vec3f u = normalize(up);
  Vec3f r = std::fabs(u.x) > 0.5f ? Vec3f{0.0f, 1.0f, 0.0f} : Vec3f{1.0f, 0.0f, 0.0f};
  r = normalize(r - u * dot(r, u));
  const Vec3f f = cross(r, u);
  const float degree = std::numbers::pi_v<float> / 180.0f;
  const float az = azimuth_degrees * degree, el = elevation_degrees * degree;
  const Vec3f horizontal = f * std::cos(az) + r * std::sin(az);
  const Vec3f w = normalize(horizontal * std::cos(el) + u * std::sin(el));
  // Looking straight down (or up) the world's up is the view direction: the far side is the image's up.
  camera.up = std::fabs(elevation_degrees) < 89.9f ? u : horizontal * (elevation_degrees > 0.0f ? -1.0f : 1.0f);
  // The camera's own axes, as PinholeCamera makes them.
  const Vec3f right = normalize(cross(-w, camera.up));
  const Vec3f image_up = cross(right, -w);

  const Bounds3f bounds = scene.bounds();
  const Vec3f center = bounds.empty() ? Vec3f{0.0f} : bounds.center();
  const double radius = bounds.empty() ? 0.0 : 0.5 * static_cast<double>(length(bounds.extent()));
  if (!(radius > 0.0)) {
    camera.look_at = center;
    camera.position = center + w;
    return camera;
  }
  struct Local {
    double x, y, z;
  };
  std::vector<Local> local;
  for (const Vec3f& p : framing_points(scene)) {
    const Vec3f d = p - center;
    local.push_back({dot(d, right), dot(d, image_up), dot(d, w)});
  }
  constexpr double kFill = 0.9;
  const double tan_y = std::tan(0.5 * static_cast<double>(fov_degrees) * std::numbers::pi / 180.0);
  const double tan_x = tan_y * camera.width / camera.height;
  double shift_x = 0.0, shift_y = 0.0, distance = 0.0;
  // The distance that keeps every point within kFill of the image for the current shift; then the
  // shift that centres the projection. A few rounds settle both.
  for (int round = 0; round < 4; ++round) {
    distance = 0.0;
    double z_max = -radius;
    for (const Local& p : local) {
      z_max = std::max(z_max, p.z);
      distance = std::max({distance, p.z + std::fabs(p.x - shift_x) / (kFill * tan_x), p.z + std::fabs(p.y - shift_y) / (kFill * tan_y)});
    }
    distance = std::max(distance, z_max + 0.01 * radius);
    if (round == 3) break;
    double x_lo = 1e300, x_hi = -1e300, y_lo = 1e300, y_hi = -1e300;
    for (const Local& p : local) {
      const double depth = distance - p.z;
      x_lo = std::min(x_lo, (p.x - shift_x) / depth), x_hi = std::max(x_hi, (p.x - shift_x) / depth);
      y_lo = std::min(y_lo, (p.y - shift_y) / depth), y_hi = std::max(y_hi, (p.y - shift_y) / depth);
    }
    shift_x += 0.5 * (x_lo + x_hi) * distance;
    shift_y += 0.5 * (y_lo + y_hi) * distance;
  }
  camera.look_at = center + right * static_cast<float>(shift_x) + image_up * static_cast<float>(shift_y);
  camera.position = camera.look_at + w * static_cast<float>(distance);
  return camera;
}

const Material& Scene::material_of(ObjectId id, std::uint32_t prim) const {
  const Instance& inst = instance(id);
  if (inst.material) return materials[*inst.material];
  const TriangleMesh& mesh = meshes[inst.mesh];
  if (mesh.material_ids.empty()) return materials[0];
  return materials[mesh.material_ids[prim == kInvalidId ? 0 : prim]];
}

Scene scene_from_mesh(TriangleMesh mesh) {
  Scene scene;
  scene.name = mesh.name;
  scene.meshes.push_back(std::move(mesh));
  scene.add_instance(0);
  return scene;
}

}  // namespace vf
