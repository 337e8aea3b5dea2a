#include "field_figures.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <span>
#include <string>

#include <unistd.h>

#include "bench_accel.hpp"
#include "casters.hpp"
#include "query_runner.hpp"
#include "visfield/accel/batch.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/statistics.hpp"
#include "visfield/core/text.hpp"
#include "visfield/field/object_field.hpp"
#include "visfield/render/camera.hpp"
#include "visfield/render/ray_sets.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/sampling.hpp"
#include "visfield/io/mesh_loader.hpp"
#include "visfield/registry/scene_geometry.hpp"

namespace vf::experiments {
namespace {

using namespace vf::bench;  // the benchmark's building blocks: structures by spec, ray sets, timing

// The corner of Figure 6: three square faces of 33 x 33 vertices meeting at the origin (the floor
// y = 0 and the walls x = 0 and z = 0), side kCornerSide; the caster stands on the floor with its
// bounding sphere (radius 1) kCasterOffset from both walls.
constexpr int kCornerVertices = 33;
constexpr float kCornerSide = 3.0f;
constexpr float kCasterOffset = 1.25f;
// 256 rays per vertex: the centres of 16 x 16 cells under the concentric map, lifted by Malley.
constexpr int kRaysPerSide = 16;

struct Receiver {
  std::vector<Vec3f> points, normals;
};

Receiver corner_receiver() {
  Receiver r;
  const float step = kCornerSide / static_cast<float>(kCornerVertices - 1);
  for (int face = 0; face < 3; ++face)
    for (int a = 0; a < kCornerVertices; ++a)
      for (int b = 0; b < kCornerVertices; ++b) {
        const float u = step * static_cast<float>(a), v = step * static_cast<float>(b);
        // floor (normal +y), wall x = 0 (normal +x), wall z = 0 (normal +z)
        const Vec3f p = face == 0 ? Vec3f{u, 0.0f, v} : face == 1 ? Vec3f{0.0f, u, v} : Vec3f{u, v, 0.0f};
        const Vec3f n = face == 0 ? Vec3f{0, 1, 0} : face == 1 ? Vec3f{1, 0, 0} : Vec3f{0, 0, 1};
        r.points.push_back(p);
        r.normals.push_back(n);
      }
  return r;
}

std::vector<Ray> receiver_rays(const Receiver& r) {
  std::vector<Ray> rays;
  rays.reserve(r.points.size() * kRaysPerSide * kRaysPerSide);
  for (std::size_t v = 0; v < r.points.size(); ++v) {
    Vec3f tangent, bitangent;
    orthonormal_basis(r.normals[v], tangent, bitangent);
    for (int a = 0; a < kRaysPerSide; ++a)
      for (int b = 0; b < kRaysPerSide; ++b) {
        const Vec3f l = cosine_hemisphere((static_cast<float>(a) + 0.5f) / kRaysPerSide, (static_cast<float>(b) + 0.5f) / kRaysPerSide);
        rays.push_back(Ray{r.points[v], tangent * l.x + bitangent * l.y + r.normals[v] * l.z, 1e-4f});
      }
  }
  return rays;
}

// The casters alone (the corner only receives), each standing on the floor at its placement by its
// object transform (so that fields stay in object space, as for any instance).
Scene corner_scene(const std::vector<std::string>& caster_paths, const std::vector<Placement>& placements) {
  Scene scene;
  for (std::size_t c = 0; c < caster_paths.size(); ++c) {
    LoadedMesh loaded = load_mesh(caster_paths[c]);
    const TriangleSet set = mesh_triangles(loaded.mesh);
    if (set.size() == 0) throw Error(caster_paths[c] + ": no triangles of non-zero area");
    const Transform t = standing_transform(set, placements[c]);
    loaded.mesh.occluder = MeshOccluder::field;
    scene.meshes.push_back(std::move(loaded.mesh));
    scene.add_instance(static_cast<std::uint32_t>(c), t);
  }
  scene.name = "corner";
  return scene;
}

Scene corner_scene(const std::string& caster_path) { return corner_scene({caster_path}, {{1.0f, kCasterOffset, kCasterOffset}}); }

// Ambient occlusion per receiver vertex on the 0-255 scale (255 = unoccluded).
std::vector<double> vertex_ao(const std::vector<std::uint8_t>& occluded) {
  constexpr std::size_t per_vertex = kRaysPerSide * kRaysPerSide;
  std::vector<double> ao(occluded.size() / per_vertex);
  for (std::size_t v = 0; v < ao.size(); ++v) {
    std::size_t clear = 0;
    for (std::size_t k = 0; k < per_vertex; ++k) clear += occluded[v * per_vertex + k] ? 0 : 1;
    ao[v] = 255.0 * static_cast<double>(clear) / static_cast<double>(per_vertex);
  }
  return ao;
}

/// One structure's answers on the figure's rays: seconds (median of 3 after a warm-up) and per-vertex AO.
struct Run {
  double build_s = 0.0, ao_s = 0.0;
  std::vector<double> ao;
  std::vector<std::uint8_t> occluded;  // the answers themselves
};

/// Each of `specs` built over `geometry` and traced on `rays`, the structures' runs interleaved
/// (measure_queries: one warm-up each, then `reps` rounds of every structure once).
std::vector<Run> run_interleaved(const std::vector<std::string>& specs, SceneGeometry& geometry, const std::vector<Ray>& rays, int reps) {
  std::vector<BuiltBenchAccel> built;
  std::vector<const BenchAccel*> accels;
  built.reserve(specs.size());
  for (const std::string& spec : specs) {
    built.push_back(build_bench_accel(spec, geometry, {rays.size()}, threads_in_force()));
    accels.push_back(&built.back().accel);
  }
  const std::vector<QueryMeasurement> m = measure_queries(accels, rays, RayKind::ao, {1, reps});
  std::vector<Run> runs;
  for (std::size_t i = 0; i < specs.size(); ++i)
    runs.push_back({bench_accel_stats(built[i].accel).build_ms / 1000.0, m[i].timings.median_ms() / 1000.0,
                    vertex_ao(m[i].results.occluded), m[i].results.occluded});
  return runs;
}

Run run(const std::string& spec, SceneGeometry& geometry, const std::vector<Ray>& rays) { return run_interleaved({spec}, geometry, rays, 3).front(); }

// The paper measured Figure 6's RMS on its rendered image (against the reference image of its Figure
// 5), not per vertex: the corner drawn with its per-vertex AO interpolated over each triangle, the
// caster and the background drawn alike in both images. FigureView is that picture's geometry, seen
// once; image() draws it for a set of per-vertex AO values.
class FigureView {
 public:
  static constexpr int kSize = 256;

  FigureView(const Scene& casters, const Receiver& corner) {
    // The corner as triangles over the receiver vertices (two a quad), then the casters.
    TriangleSet set;
    constexpr std::uint32_t kCornerObject = 0xfffffff0u;
    const auto vertex = [](int face, int a, int b) { return static_cast<std::uint32_t>((face * kCornerVertices + a) * kCornerVertices + b); };
    for (int face = 0; face < 3; ++face)
      for (int a = 0; a + 1 < kCornerVertices; ++a)
        for (int b = 0; b + 1 < kCornerVertices; ++b) {
          const std::uint32_t quad[4] = {vertex(face, a, b), vertex(face, a + 1, b), vertex(face, a + 1, b + 1), vertex(face, a, b + 1)};
          for (const auto& t : {std::array<std::uint32_t, 3>{quad[0], quad[1], quad[2]}, std::array<std::uint32_t, 3>{quad[0], quad[2], quad[3]}}) {
            set.prim.push_back(static_cast<std::uint32_t>(corner_triangles_.size()));
            set.instance.push_back(kCornerObject);
            set.triangles.push_back({corner.points[t[0]], corner.points[t[1]], corner.points[t[2]]});
            corner_triangles_.push_back(t);
          }
        }
    const TriangleSet cast = flatten(casters);
    set.triangles.insert(set.triangles.end(), cast.triangles.begin(), cast.triangles.end());
    set.prim.insert(set.prim.end(), cast.prim.begin(), cast.prim.end());
    set.instance.insert(set.instance.end(), cast.instance.begin(), cast.instance.end());
    for (const auto& t : set.triangles)
      for (const Vec3f& c : t) set.bounds.extend(c);
    const Bvh bvh = Bvh::build(set);
    // Looking into the corner from the open side, a little above the caster.
    Camera camera;
    camera.position = Vec3f{5.2f, 3.1f, 5.2f};
    camera.look_at = Vec3f{1.1f, 0.7f, 1.1f};
    camera.fov_degrees = 42.0f;
    camera.width = camera.height = kSize;
    const PinholeCamera pinhole(camera);
    pixels_.resize(static_cast<std::size_t>(kSize) * kSize);
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        const Hit hit = bvh.intersect(pinhole.generate(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f));
        Pixel& p = pixels_[static_cast<std::size_t>(y) * kSize + static_cast<std::size_t>(x)];
        if (!hit) continue;
        p.kind = hit.instance == kCornerObject ? Pixel::receiver : Pixel::caster;
        p.triangle = hit.prim, p.u = hit.u, p.v = hit.v;
      }
  }

  /// The image (0-255 per pixel) for per-vertex AO `ao`: receivers interpolated, casters 128, background 255.
  std::vector<double> image(const std::vector<double>& ao) const {
    std::vector<double> out(pixels_.size());
    for (std::size_t i = 0; i < pixels_.size(); ++i) {
      const Pixel& p = pixels_[i];
      if (p.kind != Pixel::receiver) {
        out[i] = p.kind == Pixel::caster ? 128.0 : 255.0;
        continue;
      }
      const auto& t = corner_triangles_[p.triangle];
      out[i] = (1.0 - p.u - p.v) * ao[t[0]] + p.u * ao[t[1]] + p.v * ao[t[2]];
    }
    return out;
  }

  /// Pixels that show the corner (the receiver).
  std::size_t receiver_pixels() const {
    std::size_t n = 0;
    for (const Pixel& p : pixels_) n += p.kind == Pixel::receiver ? 1 : 0;
    return n;
  }

 private:
  struct Pixel {
    enum Kind : std::uint8_t { background, caster, receiver } kind = background;
    std::uint32_t triangle = 0;
    float u = 0.0f, v = 0.0f;
  };
  std::vector<std::array<std::uint32_t, 3>> corner_triangles_;
  std::vector<Pixel> pixels_;
};

// The paper's Figure 6: precompute s / AO s / RMS for positions x directions (mach. type 2).
const char* const kPaperFigure6[3][4] = {
    {"3.96 / 0.0946 / 2.82", "14.60 / 0.0958 / 2.41", "54.42 / 0.0981 / 2.32", "213.75 / 0.1016 / 2.29"},
    {"14.06 / 0.0987 / 1.07", "51.23 / 0.1022 / 1.03", "193.25 / 0.1079 / 1.03", "772 / 0.1152 / 1.03"},
    {"54.79 / 0.1083 / 0.677", "204.27 / 0.1112 / 0.632", "925.05 / 0.1150 / 0.621", "3039.72 / 0.1219 / 0.619"},
};

void figure6(SceneGeometry& geometry, const std::vector<Ray>& rays, std::ostream& out) {
  const Run exact = run("bvh", geometry, rays);
  const FigureView view(geometry.scene(), corner_receiver());
  const std::vector<double> exact_image = view.image(exact.ao);
  std::vector<std::string> image_rows;
  out << "Exact AO (our BVH): " << formatted("%.3f s", exact.ao_s);
  if (kHaveEmbree) out << ", Embree: " << formatted("%.3f s", run(kEmbreeName, geometry, rays).ao_s);
  out << " for " << rays.size() << " rays.\n\n";
  out << "Each cell: precompute s / AO s / RMS (0-255) of the per-vertex AO with the paper's lookup (one sample, one cell, read "
         "parallel to the ray) / with bilinear + blend / read through the far end (our default) / through + bilinear + blend / "
         "the ten stored lines nearest to each ray's chord voting (`lines=1`); the paper's figures (precompute / AO / RMS, its "
         "machine) below ours.\n\n";
  out << "| positions | 32x32 | 64x64 | 128x128 | 256x256 |\n|---|---|---|---|---|\n";
  const int positions[] = {290, 1090, 4226, 16642};
  // The first read of each table builds it (its precompute time); the other lookups of the same
  // table read it back from a cache folder (lookups are not stored with a table).
  const std::filesystem::path cache = std::filesystem::temp_directory_path() / ("visfield-fig6-" + std::to_string(::getpid()));
  struct RemoveCache {
    std::filesystem::path path;
    ~RemoveCache() { std::filesystem::remove_all(path); }
  } remove_cache{cache};
  for (int p = 0; p < 4; ++p) {
    out << "| " << positions[p];
    for (const int n : {32, 64, 128, 256}) {
      const std::string spec = "field:positions=" + std::to_string(positions[p]) + ",directions=" + std::to_string(n);
      const Run paper = run(spec + ",through=0", geometry, rays);
      const std::string cached = spec + ",cache=" + cache.string();
      const Run blended = run(cached + ",through=0,bilinear=1,blend=1", geometry, rays);
      const Run through = run(cached + ",through=1", geometry, rays);
      const Run best = run(cached + ",through=1,bilinear=1,blend=1", geometry, rays);
      const Run lines = run(cached + ",through=1,lines=1", geometry, rays);
      out << " | " << formatted("%.2f / %.4f / ", paper.build_s, through.ao_s)
          << formatted("%.3f / %.3f / %.3f / %.3f", rms_difference(paper.ao, exact.ao), rms_difference(blended.ao, exact.ao), rms_difference(through.ao, exact.ao), rms_difference(best.ao, exact.ao))
          << formatted(" / %.3f", rms_difference(lines.ao, exact.ao));
      image_rows.push_back(formatted("%.3f / %.3f / %.3f / %.3f", rms_difference(view.image(paper.ao), exact_image), rms_difference(view.image(blended.ao), exact_image),
                                  rms_difference(view.image(through.ao), exact_image), rms_difference(view.image(best.ao), exact_image)) +
                           formatted(" / %.3f", rms_difference(view.image(lines.ao), exact_image)));
    }
    std::filesystem::remove_all(cache);
    out << " |\n";
    if (p < 3) {
      out << "| paper";
      for (int n = 0; n < 4; ++n) out << " | " << kPaperFigure6[p][n];
      out << " |\n";
    }
  }
  out << "\nThe paper's own measure: RMS (0-255) of the rendered " << FigureView::kSize << "x" << FigureView::kSize
      << " image of the corner (per-vertex AO interpolated over its triangles; the caster and the background drawn alike in both "
         "images; the corner fills "
      << formatted("%.0f", 100.0 * static_cast<double>(view.receiver_pixels()) / (FigureView::kSize * FigureView::kSize))
      << "% of the pixels), with the paper's lookup / bilinear + blend / through / through + bilinear + blend / lines; the paper's RMS below.\n\n"
      << "| positions | 32x32 | 64x64 | 128x128 | 256x256 |\n|---|---|---|---|---|\n";
  for (int p = 0; p < 4; ++p) {
    out << "| " << positions[p];
    for (int n = 0; n < 4; ++n) out << " | " << image_rows[static_cast<std::size_t>(p * 4 + n)];
    out << " |\n";
    if (p < 3) {
      out << "| paper";
      for (int n = 0; n < 4; ++n) {
        const std::string cell = kPaperFigure6[p][n];
        out << " | " << cell.substr(cell.rfind('/') + 2);
      }
      out << " |\n";
    }
  }
  // The same memory spent on directions: 1-bit cells (the paper's Figure 7 variant) have room for
  // about √8 times the directions a side of the u8 table.
  out << "\nAt the paper's memory: 1-bit cells (a hit bit a cell and one mean hit distance a sample, the paper's Figure 7 "
         "variant) at the most directions whose table is no larger than the u8 table's, image RMS (0-255) read through the far "
         "end / through + bilinear + blend, and the precompute s; the paper's RMS (u8) below. The corner's rays are unlimited, so "
         "from outside the caster's sphere only the hit bit matters; the floor's vertices inside it compare distances, which one mean "
         "a sample answers coarsely (so do an object's own AO rays: the lookups figure).\n\n"
      << "| positions | memory of 32x32 u8 | memory of 64x64 u8 |\n|---|---|---|\n";
  for (int p = 0; p < 3; ++p) {
    out << "| " << positions[p];
    for (const int n : {32, 64}) {
      field::ObjectFieldConfig u8;
      u8.positions = positions[p];
      u8.directions = n;
      field::ObjectFieldConfig bits = u8;
      bits.storage = field::CellStorage::bit;
      while (field::ObjectField::table_bytes(bits) <= field::ObjectField::table_bytes(u8)) ++bits.directions;
      --bits.directions;
      const std::string spec = "field:positions=" + std::to_string(positions[p]) + ",directions=" + std::to_string(bits.directions) + ",storage=bit";
      const Run through = run(spec + ",cache=" + cache.string(), geometry, rays);
      const Run best = run(spec + ",cache=" + cache.string() + ",through=1,bilinear=1,blend=1", geometry, rays);
      out << " | " << bits.directions << "x" << bits.directions << " bits, "
          << format_bytes(field::ObjectField::table_bytes(bits)) << " (u8 " << format_bytes(field::ObjectField::table_bytes(u8)) << "): "
          << formatted("%.3f / %.3f / %.2f s", rms_difference(view.image(through.ao), exact_image), rms_difference(view.image(best.ao), exact_image), through.build_s);
    }
    std::filesystem::remove_all(cache);
    out << " |\n| paper";
    for (int n = 0; n < 2; ++n) {
      const std::string cell = kPaperFigure6[p][n];
      out << " | " << cell.substr(cell.rfind('/') + 2);
    }
    out << " |\n";
  }
}

void figure5(SceneGeometry& geometry, const std::vector<Ray>& rays, std::ostream& out) {
  const Run exact = run("bvh", geometry, rays);
  out << "4226 positions x 64x64 cells (equal memory), the paper's lookup, RMS (0-255) of per-vertex AO against the exact values:\n\n"
      << "| mapping / storage | RMS | paper |\n|---|---|---|\n";
  for (const char* mapping : {"polar", "rejection", "concentric", "equal-area"}) {
    const Run r = run(std::string("field:positions=4226,directions=64,through=0,mapping=") + mapping, geometry, rays);
    out << "| " << mapping << " u8 | " << formatted("%.3f", rms_difference(r.ao, exact.ao)) << " | "
        << (std::string(mapping) == "concentric" ? "0.632 (Figure 6)" : "-") << " |\n";
  }
  const Run bit = run("field:positions=4226,directions=64,through=0,storage=bit", geometry, rays);
  out << "| concentric bit (Figure 7) | " << formatted("%.3f", rms_difference(bit.ao, exact.ao)) << " | 4.403 |\n";
}

// The paper's Figure 8 (mach. type 1): triangles, ray casting s, precompute s (4226 x 32^2), AO s.
struct PaperRow {
  const char* model;
  const char* figures;
};
constexpr PaperRow kPaperFigure8[] = {{"bun_zipper", "39,000 / 331.10 / 54.79 / 0.228"}, {"igea", "67,200 / 616.35 / 243.76 / 0.204"}};

/// Timed rounds of Figure 8's structures (bvh, field, Embree interleaved; the median of each).
constexpr int kFigure8Rounds = 15;

// Figure 8: each model of `folder` alone in the corner, then three of them together, at 4226 x 32^2.
void figure8(const std::string& folder, const std::vector<Ray>& rays, std::ostream& out) {
  const char* const models[] = {"cow.obj", "bun_zipper.ply", "igea-triangles.ply", "dragon_vrip_res2.ply", "Armadillo.ply"};
  out << "4226 positions x 32x32 concentric u8 cells; " << rays.size() << " AO rays from the corner per model. Times: medians of "
      << kFigure8Rounds << " rounds, each running the BVH, the field and Embree in turn, after one warm-up.\n\n"
      << "| model | triangles | exact AO s (BVH) | exact AO s (Embree) | precompute s | field AO s | field vs Embree | RMS (0-255) | paper: triangles / ray casting s / precompute s / AO s |\n"
      << "|---|---:|---:|---:|---:|---:|---:|---:|---|\n";
  const auto row = [&](const std::string& name, const Scene& scene) {
    SceneGeometry geometry(scene);
    // The field's run is a few milliseconds: interleaved rounds keep a moment's machine load from
    // deciding its ratio to Embree.
    std::vector<std::string> specs = {"bvh", "field"};
    if (kHaveEmbree) specs.push_back(kEmbreeName);
    const std::vector<Run> runs = run_interleaved(specs, geometry, rays, kFigure8Rounds);
    const Run &exact = runs[0], &field = runs[1];
    const double embree_s = kHaveEmbree ? runs[2].ao_s : 0.0;
    std::string paper = "-";
    for (const PaperRow& p : kPaperFigure8)
      if (name.find(p.model) != std::string::npos) paper = p.figures;
    out << "| " << name << " | " << scene.instanced_triangle_count() << " | " << formatted("%.3f", exact.ao_s) << " | "
        << (kHaveEmbree ? formatted("%.3f", embree_s) : std::string("-")) << " | " << formatted("%.2f", field.build_s) << " | "
        << formatted("%.4f", field.ao_s) << " | " << (kHaveEmbree ? formatted("%.1fx", embree_s / field.ao_s) : std::string("-")) << " | "
        << formatted("%.3f", rms_difference(field.ao, exact.ao)) << " | " << paper << " |\n";
  };
  std::vector<std::string> found;
  for (const char* model : models) {
    const std::string path = (std::filesystem::path(folder) / model).string();
    if (!std::filesystem::exists(path)) {
      out << "| " << model << " | not in " << folder << " | | | | | | | |\n";
      continue;
    }
    found.push_back(path);
    row(model, corner_scene(path));
  }
  if (found.size() >= 3)
    row("three together", corner_scene({found[0], found[1], found[2]}, {{0.6f, 0.8f, 0.8f}, {0.6f, 2.2f, 0.8f}, {0.6f, 0.8f, 2.2f}}));
}

// The lookup options at equal memory (4226 x 32^2 and 1090 x 64^2 u8 tables, 4226 x 90^2 bits): inter-object error on
// the corner's rays, intra-object error on AO rays from the caster's own surface, and the time per
// query of each; the error x time product picks the defaults.
void lookups(const std::string& caster_path, SceneGeometry& corner, const std::vector<Ray>& corner_rays, std::ostream& out) {
  Scene alone;
  alone.meshes.push_back(load_mesh(caster_path).mesh);
  alone.meshes[0].occluder = MeshOccluder::field;
  alone.add_instance(0);
  SceneGeometry caster(alone);
  const Bvh bvh = Bvh::build(flatten(alone));
  const std::vector<Ray> own = make_ao_rays(bvh, alone, alone.camera_or_default(512, 512), 4,
                                            std::numeric_limits<float>::infinity(), 1);
  const Run corner_exact = run("bvh", corner, corner_rays), own_exact = run("bvh", caster, own);
  const auto disagreement = [&](const Run& r) {
    // run() keeps per-vertex AO for the corner; for the caster's own rays compare the answers.
    std::size_t differ = 0;
    for (std::size_t i = 0; i < r.occluded.size(); ++i) differ += r.occluded[i] != own_exact.occluded[i] ? 1 : 0;
    return static_cast<double>(differ) / static_cast<double>(r.occluded.size());
  };
  out << "Inter-object: " << corner_rays.size() << " rays from the corner's vertices, RMS (0-255) of the per-vertex AO. "
      << "Intra-object: " << own.size() << " AO rays (4 per pixel of a 512x512 view) from the caster's own surface, the "
      << "fraction of occlusion answers that differ from the exact ones. ns: wall time per ray over the threads.\n\n"
      << "| table | lookup | inter RMS | inter ns/ray | intra differ | intra ns/ray | RMS x ns | differ x ns |\n"
      << "|---|---|---:|---:|---:|---:|---:|---:|\n";
  for (const char* table : {"positions=4226,directions=32", "positions=1090,directions=64", "positions=4226,directions=90,storage=bit"})
    for (const char* lookup : {",through=0", ",through=0,bilinear=1", ",through=0,blend=1", ",through=0,bilinear=1,blend=1", ",through=1",
                               ",through=1,bilinear=1", ",through=1,blend=1", ",through=1,bilinear=1,blend=1", ",through=1,lines=1",
                               ",through=1,bilinear=1,lines=1"}) {
      const std::string spec = std::string("field:") + table + lookup;
      const Run inter = run(spec, corner, corner_rays), intra = run(spec, caster, own);
      const double inter_ns = inter.ao_s * 1e9 / static_cast<double>(corner_rays.size());
      const double intra_ns = intra.ao_s * 1e9 / static_cast<double>(own.size());
      const double inter_rms = rms_difference(inter.ao, corner_exact.ao), intra_differ = disagreement(intra);
      out << "| " << table << " | " << (std::string(lookup) == ",through=0" ? "through=0 (paper)" : lookup + 1) << " | " << formatted("%.3f", inter_rms) << " | "
          << formatted("%.2f", inter_ns) << " | " << formatted("%.4f", intra_differ) << " | " << formatted("%.2f", intra_ns) << " | "
          << formatted("%.2f", inter_rms * inter_ns) << " | " << formatted("%.4f", intra_differ * intra_ns) << " |\n";
    }
}

// The GPU paper's Figure 3: the caster on a ground plane, AO of the ground (inter-object; the caster
// itself is shaded flat, as the paper draws it with the fixed pipeline) from 256 rays per pixel of a
// 256x256 view, fields at {1090, 4226, 16642} x {32^2, 64^2, 128^2} against the exact image: RMS over
// all pixels on the 0-255 scale (the paper's measure), time of the AO rays, memory.
void gpu_figure3(const std::string& caster_path, std::ostream& out) {
  Scene scene;
  TriangleMesh caster = load_mesh(caster_path).mesh;
  const TriangleSet set = mesh_triangles(caster);
  if (set.size() == 0) throw Error(caster_path + ": no triangles of non-zero area");
  const field::BoundingSphere sphere = field::bounding_sphere_of(set);
  caster.occluder = MeshOccluder::field;
  scene.meshes.push_back(std::move(caster));
  scene.add_instance(0);
  // The ground: a square of 6 radii under the caster's lowest point, exact (the receiver).
  TriangleMesh ground;
  ground.name = "ground";
  ground.occluder = MeshOccluder::exact;
  const float y = set.bounds.lo.y, half = 3.0f * sphere.radius;
  const Vec3f c = sphere.centre;
  ground.positions = {{c.x - half, y, c.z - half}, {c.x + half, y, c.z - half}, {c.x + half, y, c.z + half}, {c.x - half, y, c.z + half}};
  ground.triangles = {{0, 2, 1}, {0, 3, 2}};
  scene.meshes.push_back(std::move(ground));
  const ObjectId ground_id = scene.add_instance(1);
  scene.name = "gpu-figure-3";
  Camera camera = scene.camera_or_default(256, 256);
  SceneGeometry geometry(scene);
  const Bvh bvh = Bvh::build(flatten(scene));
  const std::vector<Ray> primary = make_primary_rays(scene, camera);
  std::vector<Hit> hits(primary.size());
  intersect_batch(bvh, std::span<const Ray>(primary), std::span<Hit>(hits));
  // AO rays from the ground's pixels only.
  std::vector<Hit> ground_hits = hits;
  for (Hit& h : ground_hits)
    if (h.found && h.instance != ground_id) h = Hit{};
  constexpr int kRaysPerPixel = 256;
  const std::vector<Ray> rays = ao_rays_from_hits(scene, primary, ground_hits, kRaysPerPixel, std::numeric_limits<float>::infinity(), 1);
  const auto image = [&](const std::vector<double>& ao) {
    std::vector<double> pixels(hits.size());
    std::size_t next = 0;
    for (std::size_t p = 0; p < hits.size(); ++p)
      pixels[p] = !hits[p].found ? 255.0 : hits[p].instance == ground_id ? ao[next++] : 128.0;
    return pixels;
  };
  const auto per_pixel_ao = [&](const std::vector<std::uint8_t>& occluded) {
    std::vector<double> ao(occluded.size() / kRaysPerPixel);
    for (std::size_t v = 0; v < ao.size(); ++v) {
      std::size_t clear = 0;
      for (std::size_t k = 0; k < kRaysPerPixel; ++k) clear += occluded[v * kRaysPerPixel + k] ? 0 : 1;
      ao[v] = 255.0 * static_cast<double>(clear) / kRaysPerPixel;
    }
    return ao;
  };
  const auto measure = [&](const std::string& spec, double& build_s, double& ao_s, std::size_t& bytes) {
    BuiltBenchAccel built = build_bench_accel(spec, geometry, {rays.size()}, threads_in_force());
    const BenchAccel* accels[] = {&built.accel};
    const std::vector<QueryMeasurement> m = measure_queries(accels, rays, RayKind::ao, {1, 3});
    build_s = bench_accel_stats(built.accel).build_ms / 1000.0;
    bytes = bench_accel_stats(built.accel).memory_bytes;
    ao_s = m[0].timings.median_ms() / 1000.0;
    return image(per_pixel_ao(m[0].results.occluded));
  };
  double build_s = 0.0, exact_s = 0.0, embree_s = 0.0;
  std::size_t bytes = 0;
  const std::vector<double> exact = measure("bvh", build_s, exact_s, bytes);
  if (kHaveEmbree) measure(kEmbreeName, build_s, embree_s, bytes);
  out << rays.size() << " AO rays (" << kRaysPerPixel << " per ground pixel of a 256x256 view). Exact: our BVH "
      << formatted("%.3f s", exact_s) << (kHaveEmbree ? ", Embree " + formatted("%.3f s", embree_s) : std::string()) << ".\n\n"
      << "Each cell: AO time s / RMS (0-255, all pixels) / field memory; the GPU paper's draw time (on its 2010 GPU) and RMS below.\n\n"
      << "| positions | 32x32 | 64x64 | 128x128 |\n|---|---|---|---|\n";
  const char* const paper[3][3] = {{"81.2 ms / 0.596", "82.7 ms / 0.589", "82.9 ms / 0.586"},
                                   {"83.2 ms / 0.454", "83.3 ms / 0.424", "-"},
                                   {"84.2 ms / 0.421", "-", "-"}};
  const int positions[] = {1090, 4226, 16642};
  for (int p = 0; p < 3; ++p) {
    out << "| " << positions[p];
    for (const int n : {32, 64, 128}) {
      double field_build = 0.0, field_s = 0.0;
      std::size_t field_bytes = 0;
      const std::vector<double> field =
          measure("field:positions=" + std::to_string(positions[p]) + ",directions=" + std::to_string(n), field_build, field_s, field_bytes);
      out << " | " << formatted("%.4f s / %.3f / ", field_s, rms_difference(field, exact)) << format_bytes(static_cast<double>(field_bytes));
    }
    out << " |\n| paper | " << paper[p][0] << " | " << paper[p][1] << " | " << paper[p][2] << " |\n";
  }
}

}  // namespace

std::vector<std::string> field_figure_names() { return {"fig6", "fig5", "fig8", "lookups", "gpu3"}; }

void run_field_figure(const std::string& name, const std::string& caster_path, std::ostream& out) {
  // A timing-bound build's fields answer wrongly on purpose: its figures say so first.
  if (*field::ObjectField::timing_bound() != '\0')
    out << "TIMING BOUND: field query built " << field::ObjectField::timing_bound() << " (answers wrong)\n\n";
  if (name == "fig8") {
    const std::vector<Ray> rays = receiver_rays(corner_receiver());
    out << "## fig8: the models of " << caster_path << " in a corner of 3 x " << kCornerVertices << " x " << kCornerVertices
        << " receiver vertices, " << kRaysPerSide * kRaysPerSide << " concentric rays each, " << threads_in_force() << " threads\n\n";
    figure8(caster_path, rays, out);
    return;
  }
  if (name == "gpu3") {
    out << "## gpu3: the GPU paper's Figure 3 on the CPU: " << caster_path << " on a ground plane, inter-object AO, "
        << threads_in_force() << " threads\n\n";
    gpu_figure3(caster_path, out);
    return;
  }
  const Scene scene = corner_scene(caster_path);
  SceneGeometry geometry(scene);
  const std::vector<Ray> rays = receiver_rays(corner_receiver());
  out << "## " << name << ": " << caster_path << " (" << scene.meshes[0].triangles.size() << " triangles) in a corner of 3 x "
      << kCornerVertices << " x " << kCornerVertices << " receiver vertices, " << kRaysPerSide * kRaysPerSide
      << " concentric rays each, " << threads_in_force() << " threads\n\n";
  if (name == "fig6")
    figure6(geometry, rays, out);
  else if (name == "fig5")
    figure5(geometry, rays, out);
  else if (name == "lookups")
    lookups(caster_path, geometry, rays, out);
  else
    throw Error("--figure " + name + ": unknown figure");
}

}  // namespace vf::experiments
