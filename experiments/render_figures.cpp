#include "render_figures.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "casters.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/parallel_threads.hpp"
#include "visfield/core/text.hpp"
#include "visfield/field/object_field.hpp"
#include "visfield/io/image_io.hpp"
#include "visfield/io/mesh_loader.hpp"
#include "visfield/registry/registry.hpp"
#include "visfield/render/compare.hpp"
#include "visfield/render/integrators.hpp"

namespace vf::experiments {
namespace {

// RMS on the 0-255 scale of two images clamped to [0, 1], as 8-bit pictures would compare.
double rms_255(Image a, Image b) {
  for (Image* image : {&a, &b})
    for (Vec3f& p : image->pixels) p = min(max(p, Vec3f{0.0f}), Vec3f{1.0f});
  return 255.0 * compare_images(a, b).rms;
}

// The casters (fields) standing on an exact ground square of half-width `ground`, each scaled to its
// placement's sphere radius; materials: casters `caster`, ground `floor`.
Scene casters_on_ground(const std::vector<std::string>& paths, const std::vector<Placement>& placements, float ground,
                        const Material& caster, const Material& floor) {
  Scene scene;
  scene.materials = {caster, floor};
  for (std::size_t c = 0; c < paths.size(); ++c) {
    LoadedMesh loaded = load_mesh(paths[c]);
    const TriangleSet set = mesh_triangles(loaded.mesh);
    if (set.size() == 0) throw Error(paths[c] + ": no triangles of non-zero area");
    Instance object;
    object.mesh = static_cast<std::uint32_t>(scene.meshes.size());
    object.material = 0;
    object.transform = standing_transform(set, placements[c]);
    loaded.mesh.occluder = MeshOccluder::field;
    loaded.mesh.material_ids.clear();
    scene.meshes.push_back(std::move(loaded.mesh));
    scene.add_instance(object);
  }
  TriangleMesh plane;
  plane.name = "ground";
  plane.occluder = MeshOccluder::exact;
  plane.positions = {{-ground, 0.0f, -ground}, {ground, 0.0f, -ground}, {ground, 0.0f, ground}, {-ground, 0.0f, ground}};
  plane.triangles = {{0, 2, 1}, {0, 3, 2}};
  scene.meshes.push_back(std::move(plane));
  Instance floor_object;
  floor_object.mesh = static_cast<std::uint32_t>(scene.meshes.size() - 1);
  floor_object.material = 1;
  scene.add_instance(floor_object);
  return scene;
}

Material diffuse_material(const Vec3f& colour) {
  Material m;
  m.diffuse = colour;
  return m;
}

/// Where a figure's images go: `folder`/`figure`-WHAT.png, or nowhere when folder is "".
struct ImageSink {
  std::string folder, figure;
  void keep(const std::string& what, const Image& image) const {
    if (!folder.empty()) write_image(std::filesystem::path(folder) / (figure + "-" + what + ".png"), image);
  }
};

/// One render: its image, wall seconds (median of 3 after a warm-up) and rays.
struct Render {
  Image image;
  double seconds = 0.0;
  RenderStats stats;
};

Render render(Integrator integrator, const SceneQueries& queries, const Scene& scene, const Camera& camera,
              const ShadingOptions& options, int repetitions = 3) {
  Render r;
  std::vector<double> seconds;
  for (int k = 0; k <= repetitions; ++k) {
    RenderStats stats;
    r.image = render_shaded(integrator, queries, scene, camera, options, &stats);
    if (k > 0) seconds.push_back(stats.seconds);
    r.stats = stats;
  }
  std::sort(seconds.begin(), seconds.end());
  r.seconds = seconds.empty() ? r.stats.seconds : seconds[seconds.size() / 2];
  return r;
}

/// A structure built over a scene, with the queries that send camera rays to `camera` (an exact BVH,
/// as the paper's primary rays test triangles) and every other ray to it.
struct Built {
  Built(SceneGeometry& geometry, const BuiltStructure& camera, const std::string& spec)
      : structure(build_structure(spec, geometry)), queries(scene_queries(camera.structure, structure.structure)) {}
  BuiltStructure structure;
  std::unique_ptr<SceneQueries> queries;
  std::size_t bytes() const { return structure_stats(structure.structure).memory_bytes; }
};

ShadingOptions soft_options(int shadow_rays) {
  ShadingOptions o;
  o.progress = false;
  o.shadow_rays = shadow_rays;
  return o;
}

// Three sphere lights of radius `radius` above and around the origin, at about `distance`.
void add_three_lights(Scene& scene, float distance, float radius, float radiance) {
  scene.sphere_lights.push_back(SphereLight{Vec3f{-0.5f, 1.0f, 0.6f} * distance, radius, Vec3f{radiance}});
  scene.sphere_lights.push_back(SphereLight{Vec3f{0.6f, 0.9f, 0.5f} * distance, radius, Vec3f{radiance}});
  scene.sphere_lights.push_back(SphereLight{Vec3f{0.1f, 1.1f, -0.4f} * distance, radius, Vec3f{radiance}});
}

Camera view(const Vec3f& position, const Vec3f& target, int size, float fov) {
  Camera c;
  c.position = position;
  c.look_at = target;
  c.width = c.height = size;
  c.fov_degrees = fov;
  return c;
}

/// The exact renders a soft-shadow figure compares with: 256 rays per light and pixel (the
/// reference, rendered once) and the fields' 20 (timed), both kept in `sink`.
struct ExactSoftShadows {
  Render reference, same_rays;
};
ExactSoftShadows exact_soft_shadows(const SceneQueries& exact, const Scene& scene, const Camera& camera, const ImageSink& sink) {
  ExactSoftShadows e{render(Integrator::softshadow, exact, scene, camera, soft_options(256), 0),
                     render(Integrator::softshadow, exact, scene, camera, soft_options(20))};
  sink.keep("exact256", e.reference.image);
  sink.keep("exact20", e.same_rays.image);
  return e;
}

// GPU paper Figure 7: the caster's soft shadows on the ground from 3 sphere lights, 20 shadow rays
// per light and pixel, fields at {4226, 16642} x {32^2, 64^2, 128^2}; reference: exact, 256 rays.
void figure7(const std::string& caster, const ImageSink& sink, std::ostream& out) {
  Scene scene = casters_on_ground({caster}, {{1.0f, 0.0f, 0.0f}}, 6.0f, diffuse_material(Vec3f{0.8f}), diffuse_material(Vec3f{0.7f}));
  add_three_lights(scene, 4.0f, 0.3f, 60.0f);
  const Camera camera = view({0.0f, 2.2f, 3.6f}, {0.0f, 0.7f, 0.0f}, 256, 45.0f);
  SceneGeometry geometry(scene);
  const BuiltStructure bvh = build_structure("bvh", geometry);
  const Built exact(geometry, bvh, "bvh");
  const auto [reference, exact20] = exact_soft_shadows(*exact.queries, scene, camera, sink);
  out << "256x256 pixels, 3 sphere lights, 20 shadow rays per light and pixel (" << exact20.stats.by_kind.shadow
      << " shadow rays). Reference: exact (BVH), 256 rays per light and pixel, " << formatted("%.2f s", reference.seconds)
      << ". Exact with the same 20 rays: " << formatted("%.3f s, RMS %.2f", exact20.seconds, rms_255(exact20.image, reference.image))
      << " (the noise of 20 rays alone).\n\n"
      << "Each cell: render s / RMS (0-255) against the reference / field memory; the GPU paper's (its 2010 GPU, 20 rays) below.\n\n"
      << "| positions | 32x32 | 64x64 | 128x128 |\n|---|---|---|---|\n";
  const char* const paper[2][3] = {{"348.0 ms / 5.95 / 4.1 MB", "348.5 ms / 4.82 / 16.5 MB", "348.7 ms / 4.44 / 66.0 MB"},
                                   {"348.5 ms / 5.94 / 16.3 MB", "348.6 ms / 4.80 / 65.0 MB", "-"}};
  const int positions[] = {4226, 16642};
  for (int p = 0; p < 2; ++p) {
    out << "| " << positions[p];
    for (const int n : {32, 64, 128}) {
      const Built fields(geometry, bvh, "field:meshes=marked,positions=" + std::to_string(positions[p]) + ",directions=" + std::to_string(n));
      const Render r = render(Integrator::softshadow, *fields.queries, scene, camera, soft_options(20));
      sink.keep("field" + std::to_string(positions[p]) + "x" + std::to_string(n), r.image);
      out << " | " << formatted("%.3f s / %.2f / ", r.seconds, rms_255(r.image, reference.image)) << format_bytes(static_cast<double>(fields.bytes()));
    }
    out << " |\n| paper | " << paper[p][0] << " | " << paper[p][1] << " | " << paper[p][2] << " |\n";
  }
}

// GPU paper Figure 8: three models together under 3 sphere lights, 20 shadow rays, 4226 x 64^2.
void figure8(const std::string& folder, const ImageSink& sink, std::ostream& out) {
  std::vector<std::string> paths;
  for (const char* name : {"bun_zipper.ply", "dragon_vrip_res2.ply", "Armadillo.ply"}) {
    const std::filesystem::path path = std::filesystem::path(folder) / name;
    if (!std::filesystem::exists(path)) throw Error("--figure gpu8: " + path.string() + " not found (--scene is the models' folder)");
    paths.push_back(path.string());
  }
  Scene scene = casters_on_ground(paths, {{0.8f, -1.8f, 0.0f}, {0.8f, 0.0f, -0.6f}, {0.8f, 1.8f, 0.0f}}, 8.0f,
                                  diffuse_material(Vec3f{0.8f}), diffuse_material(Vec3f{0.7f}));
  add_three_lights(scene, 5.0f, 0.6f, 30.0f);
  const Camera camera = view({0.0f, 3.0f, 5.5f}, {0.0f, 0.6f, 0.0f}, 256, 45.0f);
  SceneGeometry geometry(scene);
  const BuiltStructure bvh = build_structure("bvh", geometry);
  const Built exact(geometry, bvh, "bvh");
  const auto [reference, exact20] = exact_soft_shadows(*exact.queries, scene, camera, sink);
  const Built fields(geometry, bvh, "field:meshes=marked,positions=4226,directions=64");
  const Render field20 = render(Integrator::softshadow, *fields.queries, scene, camera, soft_options(20));
  Scene sharp_scene = scene;  // the paper's BVH comparison: sharp shadows, one ray per light (point lights)
  sharp_scene.sphere_lights.clear();
  for (const SphereLight& l : scene.sphere_lights)
    sharp_scene.point_lights.push_back(PointLight{l.center, l.radiance * (3.14159265f * l.radius * l.radius)});
  const Render sharp = render(Integrator::softshadow, *exact.queries, sharp_scene, camera, soft_options(1));
  sink.keep("field4226x64", field20.image);
  sink.keep("sharp", sharp.image);
  out << scene.instanced_triangle_count() << " triangles (bunny, dragon, Armadillo on a ground), 256x256 pixels, 3 sphere lights, "
      << "20 shadow rays per light and pixel (" << field20.stats.by_kind.shadow << " shadow rays); fields 4226 x 64x64 u8 ("
      << format_bytes(static_cast<double>(fields.bytes())) << ").\n\n"
      << "| render | s | ns per shadow ray | RMS (0-255) vs exact 256-ray reference |\n|---|---:|---:|---:|\n"
      << "| fields, 20 rays | " << formatted("%.3f | %.1f", field20.seconds, field20.seconds * 1e9 / static_cast<double>(field20.stats.by_kind.shadow))
      << " | " << formatted("%.2f", rms_255(field20.image, reference.image)) << " |\n"
      << "| exact BVH, 20 rays | " << formatted("%.3f | %.1f", exact20.seconds, exact20.seconds * 1e9 / static_cast<double>(exact20.stats.by_kind.shadow))
      << " | " << formatted("%.2f", rms_255(exact20.image, reference.image)) << " |\n"
      << "| exact BVH, sharp (1 ray per point light) | " << formatted("%.3f | %.1f", sharp.seconds, sharp.seconds * 1e9 / static_cast<double>(std::max<std::uint64_t>(1, sharp.stats.by_kind.shadow)))
      << " | - |\n\n"
      << "The paper (its 2010 GPU): fields 3268 ms for 11.8M shadow rays (1.9e-4 ms each); its GPU BVH 48047 ms for sharp shadows.\n";
}

// GPU paper Figure 9: a model on a polished floor, 4 reflection rays per reflective pixel; fields
// with normal fields answer the reflection rays that meet the model.
void figure9(const std::string& caster, const ImageSink& sink, std::ostream& out) {
  Material floor;
  floor.diffuse = Vec3f{0.25f};
  floor.specular = Vec3f{0.7f};
  floor.roughness = 0.12f;  // polished
  Scene scene = casters_on_ground({caster}, {{1.0f, 0.0f, 0.0f}}, 6.0f, diffuse_material(Vec3f{0.8f, 0.6f, 0.4f}), floor);
  scene.point_lights.push_back(PointLight{{2.0f, 5.0f, 4.0f}, Vec3f{60.0f}});
  const Camera camera = view({0.0f, 1.1f, 4.2f}, {0.0f, 0.5f, 0.0f}, 256, 45.0f);
  SceneGeometry geometry(scene);
  const BuiltStructure bvh = build_structure("bvh", geometry);
  const Built exact(geometry, bvh, "bvh");
  ShadingOptions o;
  o.progress = false;
  o.glossy_rays = 4;
  const Render reference = render(Integrator::glossy, *exact.queries, scene, camera, o);
  const Render raycast = render(Integrator::raycast, *exact.queries, scene, camera, o);
  const std::string model = std::filesystem::path(caster).stem().string();
  sink.keep(model + "-exact", reference.image);
  out << "256x256 pixels, " << reference.stats.by_kind.reflection << " reflection rays (4 per reflective pixel). Exact (BVH): "
      << formatted("%.3f s", reference.seconds) << "; ray casting alone: " << formatted("%.3f s", raycast.seconds) << ".\n\n"
      << "| fields (u8 distances, oct16 normals) | render s | RMS (0-255) vs exact, same rays | memory |\n|---|---:|---:|---:|\n";
  for (const int n : {32, 64}) {
    const std::string spec = "field:meshes=marked,positions=4226,directions=" + std::to_string(n) + ",normals=oct16";
    const Built fields(geometry, bvh, spec);
    const Render r = render(Integrator::glossy, *fields.queries, scene, camera, o);
    sink.keep(model + "-field4226x" + std::to_string(n), r.image);
    out << "| 4226 x " << n << "x" << n << " | " << formatted("%.3f | %.2f", r.seconds, rms_255(r.image, reference.image)) << " | "
        << format_bytes(static_cast<double>(fields.bytes())) << " |\n";
  }
  out << "\nThe paper (its 2010 GPU, the bunny): 4226 x 64^2 1900 ms, RMS 8.14, 66 MB; 4226 x 32^2 1897 ms, RMS 9.39, 16.5 MB; "
         "its GPU BVH reference 112910 ms.\n";
}

}  // namespace

std::vector<std::string> render_figure_names() { return {"gpu7", "gpu8", "gpu9"}; }

void run_render_figure(const std::string& name, const std::string& scene_path, const std::string& images, std::ostream& out) {
  const ImageSink sink{images, name};
  out << "## " << name << ": the GPU paper's Figure " << name.substr(3) << " on the CPU: " << scene_path << ", "
      << threads_in_force() << " threads\n\n";
  if (name == "gpu7") figure7(scene_path, sink, out);
  else if (name == "gpu8") figure8(scene_path, sink, out);
  else if (name == "gpu9") figure9(scene_path, sink, out);
  else throw Error("--figure " + name + ": unknown figure");
}

}  // namespace vf::experiments
