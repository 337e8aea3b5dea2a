#include "visfield/field/field_scene.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "block_lanes.hpp"
#include "core/isa_dispatch.hpp"
#include "visfield/accel/bvh.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/memory.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/field/closest_answer.hpp"
#include "visfield/field/field_file.hpp"
#include "visfield/field/field_params.hpp"

namespace vf::isa_avx512 {
void occluded_batch(const field::FieldScene& fields, std::span<const Ray> rays, std::span<std::uint8_t> occluded);
void occluded_block(const field::FieldScene& fields, std::span<const Ray> rays, std::span<std::uint8_t> occluded);
void intersect_batch(const field::FieldScene& fields, std::span<const Ray> rays, std::span<Hit> hits);
}  // namespace vf::isa_avx512

namespace vf::field {
namespace {

// Objects a leaf of the tree over them: a level fewer to go down, and a leaf's objects take its rays in
// one pass of sphere tests (measured where the leaves' objects are traced, occluded_by_tree).
constexpr int kObjectsPerLeaf = 4;

bool is_exact(const TriangleMesh& mesh, FieldMeshes meshes) {
  return mesh.occluder == MeshOccluder::exact || (meshes == FieldMeshes::marked && mesh.occluder != MeshOccluder::field);
}

/// Mesh indices some object uses, in increasing order, that get a field.
std::vector<std::uint32_t> field_meshes(const Scene& scene, FieldMeshes meshes) {
  std::vector<std::uint32_t> used;
  for (const Instance& object : scene.instances())
    if (!is_exact(scene.meshes[object.mesh], meshes)) used.push_back(object.mesh);
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  return used;
}

}  // namespace

ObjectFieldConfig FieldScene::mesh_config(const TriangleMesh& mesh, const ObjectFieldConfig& config) {
  return with_table_params(config, mesh.field_params, "mesh " + mesh.name + ": ");
}

double FieldScene::estimate_build_bytes(const Scene& scene, const ObjectFieldConfig& config, FieldMeshes meshes) {
  double tables = 0.0;
  std::size_t largest = 0;
  for (const std::uint32_t mesh : field_meshes(scene, meshes)) {
    tables += ObjectField::table_bytes(mesh_config(scene.meshes[mesh], config));
    largest = std::max(largest, scene.meshes[mesh].triangles.size());
  }
  std::size_t exact_triangles = 0;
  for (const Instance& object : scene.instances())
    if (is_exact(scene.meshes[object.mesh], meshes)) exact_triangles += scene.meshes[object.mesh].triangles.size();
  const double exact = exact_triangles > 0 ? 48.0 * static_cast<double>(exact_triangles) + Bvh::estimate_build_bytes(exact_triangles) : 0.0;
  return tables + std::max(Bvh::estimate_build_bytes(largest), exact) + 64.0 * static_cast<double>(scene.instances().size());
}

std::size_t FieldScene::progress_total(const Scene& scene, const ObjectFieldConfig& config, FieldMeshes meshes) {
  std::size_t total = 0;
  for (const std::uint32_t mesh : field_meshes(scene, meshes))
    total += static_cast<std::size_t>(mesh_config(scene.meshes[mesh], config).positions);
  return total;
}

namespace {

/// Where mesh `mesh`'s field is cached: its own field_file, else a file in `cache_folder` named by
/// the mesh and the parameters, else nowhere ("").
std::string cache_path(const TriangleMesh& mesh, std::uint64_t hash, const ObjectFieldConfig& config, const std::string& cache_folder) {
  if (!mesh.field_file.empty()) return mesh.field_file;
  if (cache_folder.empty()) return "";
  std::string name = mesh.name;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016llx", static_cast<unsigned long long>(hash));
  // Appended piece by piece: GCC 12 warns (-Wrestrict, falsely) on "literal" + a temporary string.
  std::string file = name;
  file.append("-").append(hex).append("-").append(std::to_string(config.positions)).append("x");
  file.append(std::to_string(config.directions)).append("-").append(mapping_name(config.mapping)).append("-");
  file.append(storage_name(config.storage));
  if (config.normals != NormalStorage::none) file.append("-").append(normals_name(config.normals));
  file.append(".vfield");
  return (std::filesystem::path(cache_folder) / file).string();
}

/// The field of `triangles` (mesh `mesh`): read from its cache file when there is one, else built
/// (and written to the cache file when it has one).
std::shared_ptr<const ObjectField> load_or_build_field(const TriangleMesh& mesh, const TriangleSet& triangles, const ObjectFieldConfig& config,
                                              const std::function<void(std::size_t)>& progress, const std::string& cache_folder) {
  const std::uint64_t hash = mesh_hash(triangles);
  const std::string path = cache_path(mesh, hash, config, cache_folder);
  if (!path.empty() && std::filesystem::exists(path)) {
    StoredField stored = load_field(path, hash, config);
    if (progress) progress(static_cast<std::size_t>(config.positions));
    return std::make_shared<const ObjectField>(std::move(stored.field));
  }
  auto field = std::make_shared<const ObjectField>(ObjectField::build(triangles, config, progress));
  if (!path.empty()) {
    if (mesh.field_file.empty()) std::filesystem::create_directories(cache_folder);
    save_field(*field, hash, path);
  }
  return field;
}

}  // namespace

FieldScene FieldScene::build(const Scene& scene, const ObjectFieldConfig& config, const std::function<void(std::size_t)>& progress,
                             const std::string& cache_folder, FieldMeshes meshes, ObjectCull cull) {
  config.validate();
  const std::vector<std::uint32_t> with_fields = field_meshes(scene, meshes);
  std::vector<ObjectFieldConfig> configs;
  for (const std::uint32_t mesh : with_fields) {
    configs.push_back(mesh_config(scene.meshes[mesh], config));
    configs.back().validate();
  }
  require_memory(estimate_build_bytes(scene, config, meshes),
                 "the object fields of " + std::to_string(with_fields.size()) + " meshes (" + std::to_string(config.positions) +
                     " positions x " + std::to_string(config.directions) + "^2 " + storage_name(config.storage) + " cells each)");
  const Stopwatch watch;
  FieldScene result;
  result.fields_.resize(scene.meshes.size());
  for (std::size_t k = 0; k < with_fields.size(); ++k) {
    const std::uint32_t mesh = with_fields[k];
    const TriangleSet triangles = mesh_triangles(scene.meshes[mesh]);
    if (triangles.size() == 0) throw Error("mesh " + scene.meshes[mesh].name + ": no triangles of non-zero area for its field");
    result.fields_[mesh] = load_or_build_field(scene.meshes[mesh], triangles, configs[k], progress, cache_folder);
    result.stats_.memory_bytes += result.fields_[mesh]->memory_bytes();
    result.stats_.reference_count += result.fields_[mesh]->position_count();
    ++result.stats_.node_count;
  }
  TriangleSet exact;
  for (const Instance& object : scene.instances()) {
    if (is_exact(scene.meshes[object.mesh], meshes)) {
      const TriangleSet part = object_triangles(scene.meshes[object.mesh], object.transform, object.id);
      exact.triangles.insert(exact.triangles.end(), part.triangles.begin(), part.triangles.end());
      exact.prim.insert(exact.prim.end(), part.prim.begin(), part.prim.end());
      exact.instance.insert(exact.instance.end(), part.instance.begin(), part.instance.end());
      exact.degenerate_count += part.degenerate_count;
      exact.bounds.extend(part.bounds);
      continue;
    }
    const ObjectField* field = result.fields_[object.mesh].get();
    const BoundingSphere& s = field->sphere();
    result.objects_.push_back({object.id, field, object.transform.inverse(), object.transform.rotation,
                               object.transform.apply_point(s.centre), s.radius * object.transform.scale});
  }
  if (exact.size() > 0) {
    if (exact.size() <= kSmallExactTriangles) result.small_exact_ = exact;
    result.exact_.emplace(Bvh::build(exact));
    result.stats_.memory_bytes += result.exact_->stats().memory_bytes;
  }
  result.cull_ = cull;
  if (result.uses_tree()) {
    const std::vector<Bounds3f> boxes = result.object_boxes();
    result.tree_ = BoxTree::build(boxes, kObjectsPerLeaf);
    result.stats_.memory_bytes += result.tree_.memory_bytes();
    std::vector<const ObjectField*> field_of;
    for (const Object& o : result.objects_) field_of.push_back(o.field);
    if (cull == ObjectCull::grid) result.grid_ = cell_grid_over(boxes, field_of, result.cell_first_, result.cell_objects_);
    result.stats_.memory_bytes += (result.cell_first_.capacity() + result.cell_objects_.capacity()) * sizeof(std::uint32_t);
  }
  result.stats_.leaf_count = result.objects_.size();
  result.stats_.memory_bytes += result.objects_.capacity() * sizeof(Object);
  result.stats_.max_depth = 1;
  result.stats_.build_ms = watch.elapsed_ms();
  return result;
}

std::vector<Bounds3f> FieldScene::object_boxes() const {
  // Each box holds its sphere grown by 1% of the radius and by 1e-5 of the scene's size: far more
  // than the rounding of may_meet (whose own widening is 0.1%) and of a tree's box test, so that a
  // tree never leaves out an object may_meet lets in, and the answers are those of testing every sphere.
  Bounds3f scene_box;
  for (const Object& o : objects_) scene_box.extend(Bounds3f{o.centre - Vec3f(o.radius), o.centre + Vec3f(o.radius)});
  const float scene_margin = 1e-5f * length(scene_box.hi - scene_box.lo);
  std::vector<Bounds3f> boxes;
  boxes.reserve(objects_.size());
  for (const Object& o : objects_) {
    const float r = o.radius * 1.01f + scene_margin;
    boxes.push_back({o.centre - Vec3f(r), o.centre + Vec3f(r)});
  }
  return boxes;
}

bool FieldScene::uses_tree() const { return cull_ != ObjectCull::each && objects_.size() > kFewObjects; }

std::size_t FieldScene::routed_by_grid(std::span<const Ray> rays) const {
  if (grid_.count() == 0) return 0;
  std::vector<std::int32_t> cell(rays.size());
  std::vector<std::uint32_t> in_cells(rays.size() + kColumnsSlack);
  cells_of_rays(grid_, rays, nullptr, cell.data(), in_cells.data());
  return static_cast<std::size_t>(std::count_if(cell.begin(), cell.end(), [](std::int32_t c) { return c != kManyCells; }));
}

void FieldScene::objects_met(const Ray& ray, std::vector<std::uint32_t>& out) const {
  out.clear();
  const auto count = static_cast<std::uint32_t>(objects_.size());
  if (count == 1) {
    out.push_back(0);
    return;
  }
  if (!uses_tree()) {
    for (std::uint32_t k = 0; k < count; ++k)
      if (may_meet(objects_[k], ray)) out.push_back(k);
    return;
  }
  tree_.items_met(ray, out);
  std::sort(out.begin(), out.end());
  out.erase(std::remove_if(out.begin(), out.end(), [&](std::uint32_t k) { return !may_meet(objects_[k], ray); }), out.end());
}

Hit FieldScene::field_hit(const Object& o, const FieldAnswer& a) {
  if (!a.has_normal) return Hit::surface(a.t, o.id);
  const Vec3f normal = o.rotation * Vec3f{a.normal.x, a.normal.y, a.normal.z};
  return Hit::surface(a.t, o.id, &normal);
}

Hit FieldScene::intersect(const Ray& ray) const {
  Hit best = exact_ ? exact_->intersect(ray) : Hit{};
  unsigned int best_object = kExactPart;
  thread_local std::vector<std::uint32_t> met;
  objects_met(ray, met);
  for (const std::uint32_t k : met) {
    const Object& o = objects_[k];
    const Ray local = o.to_object.apply(ray);
    const FieldAnswer a = o.field->trace(local.org, local.dir, ray.tmin, ray.tmax);
    if (a.hit && replaces_closest(a.t, k, best.found, best.t, best_object)) {
      best = field_hit(o, a);
      best_object = k;
    }
  }
  return best;
}

bool FieldScene::occluded(const Ray& ray) const {
  thread_local std::vector<std::uint32_t> met;
  objects_met(ray, met);
  for (const std::uint32_t k : met) {
    const Object& o = objects_[k];
    const Ray local = o.to_object.apply(ray);
    if (o.field->trace(local.org, local.dir, ray.tmin, ray.tmax).hit) return true;
  }
  return exact_ && exact_->occluded(ray);
}

ErrorBounds FieldScene::error_bounds() const {
  // Measured at the defaults (4226 x 32^2 u8) on builtin:sphere, boxes and cornell with their
  // receivers exact (tests/approximate/test_field_scene.cpp): worst occlusion disagreement 0.027,
  // distance RMS 0.041 of the diameter, AO image RMS 0.019; the bounds leave room above them.
  ErrorBounds b;
  b.occlusion_disagreement = 0.05;
  b.hit_disagreement = 0.05;
  b.distance_rms = 0.06;
  b.image_rms = 0.03;
  return b;
}

namespace {

// Rays per parallel task: enough to amortise its scheduling (1024 was 3% slower on one object). Among
// several objects a block's rays are shared out between them, and larger blocks fill the kernel's
// packets better: 16384 gained 5% on 9 bunnies and 10% on 1024, and lost 7% on a lone bunny. Through
// the tree, with each object's rays copied side by side, 16384 ran level with 32768 and 7% faster than
// 65536, whose 2 MiB of rays outgrow a core's L2 (1024 bunnies, 3 interleaved rounds).
constexpr std::size_t kBlock = 4096;
constexpr std::size_t kObjectsBlock = 16384;
// Occlusion through the tree: (ray, object) pairs traced in one stream once this many are pending.
// Between flushes the rays they settle leave the later leaves and the tree's walk. 1024 bunnies, AO, 4
// interleaved rounds: per-object streams 29.1-32.9 Mrays/s; 512 pairs 28.7-35.4, 1024 32.7-36.2, 2048
// 30.5-35.5; one flush at the block's end (no rays settled in between) was level with per-object
// streams. Leaves visited in the walk (5 rounds): 256 and 4096 level with 1024.
constexpr std::size_t kFlushPairs = 1024;

/// 0, 1, …, kObjectsBlock − 1: the candidate list of an object every ray of a block may meet.
const std::array<std::uint32_t, kObjectsBlock>& every_ray() {
  static const std::array<std::uint32_t, kObjectsBlock> all = [] {
    std::array<std::uint32_t, kObjectsBlock> a{};
    for (std::size_t i = 0; i < kObjectsBlock; ++i) a[i] = static_cast<std::uint32_t>(i);
    return a;
  }();
  return all;
}

}  // namespace

void FieldScene::trace_block(std::span<const Ray> rays, bool closest, Hit* best, std::uint8_t* occluded) const {
  const std::size_t n = rays.size();
  // The exact part first: its hit bounds every field's search (closest) or settles the ray (occlusion).
  if (small_exact_.size() > 0) {
    if (closest)
      closest_by_small_exact(small_exact_, *exact_, rays, best);
    else
      occluded_by_small_exact(small_exact_.triangles, rays, occluded);
  } else if (!exact_) {  // fields alone: every ray starts open (a loop testing exact_ a ray cost 7% of the corner's AO)
    if (closest)
      std::fill(best, best + n, Hit{});
    else
      std::fill(occluded, occluded + n, std::uint8_t{0});
  } else {
    for (std::size_t i = 0; i < n; ++i) {
      if (closest)
        best[i] = exact_->intersect(rays[i]);
      else
        occluded[i] = exact_->occluded(rays[i]) ? 1 : 0;
    }
  }
  if (objects_.empty()) return;
  // Among several objects, each takes the rays whose segment may meet its sphere: the test the
  // single-ray queries make, on the ray as given. (Not on the ray cut at its closest hit so far:
  // from far away, rounding in that test dropped rays whose field answer was nearer than the hit.)
  // A lone object takes every ray still open, and when nothing settled any (no exact part), the
  // block's rays in order.
  const bool cull = objects_.size() > 1;
  if (cull && uses_tree()) {
    if (closest)
      closest_by_tree(rays, best);
    else
      occluded_by_tree(rays, occluded);
    return;
  }
  if (cull && !closest) {
    // A few objects, occlusion: each object's open rays that may meet its sphere, mapped into object
    // space as its rows, all objects in one pass over the block (a packet read and transposed once,
    // not once an object: the corner's three models 6.9-7.1x -> 7.8-8.2x Embree, 9 bunnies 6.0x -> 7.2x),
    // then each object's rows traced in whole packets (as among many objects). A ray one object settles
    // is still traced for the later objects it may meet (every row is made before any is traced); the
    // answers are the same.
    thread_local std::vector<RayRows> rows;
    thread_local std::vector<SphereTarget> targets;
    thread_local std::vector<std::uint8_t> marks;
    rows.resize(objects_.size());
    targets.clear();
    for (std::size_t k = 0; k < objects_.size(); ++k)
      targets.push_back({objects_[k].centre, objects_[k].radius, &objects_[k].to_object, &rows[k]});
    append_meeting_spheres(targets, rays, every_ray().data(), occluded);
    for (std::size_t k = 0; k < objects_.size(); ++k) mark_rows(*objects_[k].field, rows[k], marks, occluded);
    return;
  }
  std::vector<std::uint32_t> index;
  std::vector<FieldAnswer> answers(closest ? n : 0);
  for (std::size_t object = 0; object < objects_.size(); ++object) {
    const Object& o = objects_[object];
    const std::uint32_t* candidates = every_ray().data();
    std::size_t m = n;
    if (cull) {  // a few objects, closest hits: every sphere against the block's rays, on lanes
      index.resize(n);
      m = rays_meeting_sphere(o.centre, o.radius, rays, index.data());
      candidates = index.data();
    } else if (!closest && exact_) {
      index.resize(n);
      m = 0;
      for (std::size_t i = 0; i < n; ++i)
        if (!occluded[i]) index[m++] = static_cast<std::uint32_t>(i);
      candidates = index.data();
    }
    if (m == 0) continue;
    if (!closest) {
      o.field->mark_occluded(rays.data(), candidates, m, o.to_object, occluded);
      continue;
    }
    // Each answer within its ray's own range; the objects come in index order, so that a nearer answer
    // replacing the hit so far is replaces_closest()'s rule.
    o.field->trace_rays(rays.data(), candidates, m, o.to_object, nullptr, answers.data());
    for (std::size_t k = 0; k < m; ++k) {
      if (!answers[k].hit) continue;
      const std::size_t i = candidates[k];
      if (!best[i].found || answers[k].t < best[i].t) best[i] = field_hit(o, answers[k]);
    }
  }
}

template <class Flush>
void FieldScene::pairs_by_tree(std::span<const Ray> rays, std::uint8_t* settled, RayRows& rows, std::vector<SphereTarget>& targets,
                               Flush&& flush) const {
  // The block's rays go down the tree together, their values with them, and each leaf takes its
  // rays as soon as it is reached, nearest first, from where the walk left them: read in order by
  // the sphere tests while still in cache. (Before: the rays grouped by object, the objects with the
  // most rays first, each leaf's open rays copied from the block: that copy was 13% of 1024 bunnies'
  // field time, mostly waiting on the block's rays, and writing the values beside each list for
  // later cost more than it saved.) The pairs of objects sharing a field are traced together, as one
  // stream of consecutive rays through the field's kernel: an object's own few rays would fill few
  // packets, gathered from its list and transformed per packet, with the pipeline restarting at
  // every object.
  static_assert(BoxTree::LeafRays::kSlack >= kColumnsSlack, "the sphere pass reads whole packets of a leaf's columns");
  static_assert(kObjectsPerLeaf <= 64, "a leaf's items as bits of one word");
  const ObjectField* pending = nullptr;
  const auto flush_pending = [&] {
    if (rows.count > 0) flush(*pending);
  };
  // First the grid's rays: those whose part within the objects' boxes lies in one cell, or in two
  // neighbouring cells an axis (cells_of_rays()), sorted by that list of cells and tested against its
  // objects' spheres as a leaf's rays are. They skip the walk, which sees them as settled (kRouted,
  // taken off after). Every box such a ray meets is on its list, and the same spheres let it in as
  // the walk's leaves would, so the answers are the tree's. The walk costs a ray ~3.5 nodes of 8 box
  // tests on 1024 bunnies; a list ~5-20 sphere tests (1024 bunnies: 88% of the open rays routed; ratio
  // to Embree's instancing, see docs/objectfield-measurements.md).
  const std::size_t n = rays.size(), cells = grid_.count();
  constexpr std::uint8_t kRouted = 2;
  thread_local std::vector<std::int32_t> cell;
  thread_local std::vector<std::uint32_t> in_cells, start, order;
  thread_local std::vector<std::uint8_t> own_skip;
  std::uint8_t* skip = settled;
  std::size_t routed = 0;
  if (cells > 0) {
    if (cell.size() < n) {
      cell.resize(n);
      in_cells.resize(n + kColumnsSlack);
      order.resize(n + kColumnsSlack);
    }
    const std::size_t placed = cells_of_rays(grid_, rays, settled, cell.data(), in_cells.data());
    if (!skip) {
      own_skip.assign(n, 0);
      skip = own_skip.data();
    }
    // Plain pointers: a store through `skip` (bytes) could alias the vectors' own.
    const std::int32_t* const where = cell.data();
    for (std::size_t i = 0; i < n; ++i) {
      const bool to_grid = where[i] != kManyCells;
      skip[i] |= static_cast<std::uint8_t>(to_grid ? kRouted : 0);
      routed += to_grid ? 1 : 0;
    }
    // The rays given a cell, sorted by cell (a counting sort): four counts a cell, by place mod 4, so
    // that a cell's rays, which come in runs, do not each wait on the count the one before updated.
    constexpr std::size_t kWays = 4;
    start.assign(kWays * kCellShapes * cells + 1, 0);
    std::uint32_t* const count = start.data();
    const std::uint32_t* const ids = in_cells.data();
    for (std::size_t k = 0; k < placed; ++k) ++count[kWays * static_cast<std::size_t>(where[ids[k]]) + k % kWays + 1];
    for (std::size_t b = 1; b < start.size(); ++b) count[b] += count[b - 1];
    thread_local std::vector<std::uint32_t> cursor;
    cursor.assign(start.begin(), start.end() - 1);
    std::uint32_t* const next = cursor.data();
    std::uint32_t* const sorted = order.data();
    for (std::size_t k = 0; k < placed; ++k) sorted[next[kWays * static_cast<std::size_t>(where[ids[k]]) + k % kWays]++] = ids[k];
    for (std::size_t k = placed; k < placed + kColumnsSlack; ++k) sorted[k] = 0;  // whole packets read valid ids
    for (std::size_t c = 0; c < kCellShapes * cells; ++c) {
      const std::size_t begin = count[kWays * c], rays_here = count[kWays * (c + 1)] - begin;
      if (rays_here == 0) continue;
      const std::uint32_t* list = cell_objects_.data() + cell_first_[c];
      const std::size_t objects = cell_first_[c + 1] - cell_first_[c];
      for (std::size_t k = 0; k < objects;) {
        const ObjectField* field = objects_[list[k]].field;
        if (field != pending || rows.count >= kFlushPairs) {
          flush_pending();
          pending = field;
        }
        targets.clear();
        for (; k < objects && objects_[list[k]].field == field; ++k) {
          const Object& o = objects_[list[k]];
          targets.push_back({o.centre, o.radius, &o.to_object, &rows, list[k]});
        }
        append_meeting_spheres(targets, rays.data(), sorted + begin, rays_here);
      }
    }
  }
  const std::uint8_t* const walk_settled = skip;
  tree_.visit_leaves(rays, walk_settled, [&](const BoxTree::LeafRays& leaf) {
    // The leaf's objects that share a field take its rays together, each packet tested against all
    // their spheres in one pass (1024 bunnies, leaves of 4 objects against 1, ratio to Embree's
    // instancing, 3 interleaved rounds: medians 4.16x -> 4.36x; busts 4.31x -> 4.96x): the rays still
    // open (an earlier flush may have settled some) that each sphere lets in (the test the single-ray
    // queries make, on the ray as given), mapped into object space and added to the pending pairs.
    std::uint64_t taken = 0;  // bit k: leaf.items[k] is in a group already
    for (std::size_t first = 0; first < leaf.items.size(); ++first) {
      if ((taken >> first) & 1u) continue;
      const ObjectField* field = objects_[leaf.items[first]].field;
      if (field != pending || rows.count >= kFlushPairs) {
        flush_pending();
        pending = field;
      }
      targets.clear();
      for (std::size_t k = first; k < leaf.items.size(); ++k) {
        const Object& o = objects_[leaf.items[k]];
        if (o.field != field) continue;
        taken |= std::uint64_t{1} << k;
        targets.push_back({o.centre, o.radius, &o.to_object, &rows, leaf.items[k]});
      }
      append_meeting_spheres(targets, leaf.columns, leaf.count, leaf.ids, walk_settled);
    }
  });
  flush_pending();
  if (settled && routed > 0)
    for (std::size_t i = 0; i < n; ++i) settled[i] &= static_cast<std::uint8_t>(~kRouted);
}

void FieldScene::closest_by_tree(std::span<const Ray> rays, Hit* best) const {
  struct Scratch {
    std::vector<SphereTarget> targets;
    RayRows local;  // the pending pairs' object-space rays: ids their rays' places in the block, tags their objects
    std::vector<FieldAnswer> answers;
    std::vector<std::uint32_t> best_object;  // the object of best[i] when a field answered it, else kExactPart
  };
  thread_local Scratch s;
  s.local.tagged = true;
  s.best_object.assign(rays.size(), kExactPart);
  // The objects come in the walk's order, not their index order: replaces_closest() makes the hit the
  // same. (Before: each object's rays listed, copied and traced on their own, in index order: on 1024
  // bunnies a few dozen rays an object, mostly partial packets.)
  pairs_by_tree(rays, nullptr, s.local, s.targets, [&](const ObjectField& field) {
    const std::size_t pairs = s.local.count;
    s.local.pad_to(static_cast<std::size_t>(ObjectField::batch_width()));  // whole packets
    if (s.answers.size() < s.local.count) s.answers.resize(s.local.count);
    field.trace_batch(s.local.view(), s.answers.data());
    for (std::size_t k = 0; k < pairs; ++k) {
      const FieldAnswer& a = s.answers[k];
      if (!a.hit) continue;
      const std::uint32_t i = s.local.id[k], object = s.local.tag[k];
      if (!replaces_closest(a.t, object, best[i].found, best[i].t, s.best_object[i])) continue;
      best[i] = field_hit(objects_[object], a);
      s.best_object[i] = object;
    }
    s.local.count = 0;
  });
}

void FieldScene::occluded_by_tree(std::span<const Ray> rays, std::uint8_t* occluded) const {
  struct Scratch {
    std::vector<std::uint8_t> marks;
    std::vector<SphereTarget> targets;
    RayRows local;  // the pending pairs' object-space rays, with their rays' places in the block as ids
  };
  thread_local Scratch s;
  // Rays a flush settles are left out of the later leaves and stop at the walk's next node.
  pairs_by_tree(rays, occluded, s.local, s.targets, [&](const ObjectField& field) { mark_rows(field, s.local, s.marks, occluded); });
}

std::size_t FieldScene::block_size() const { return objects_.size() > 1 ? kObjectsBlock : kBlock; }

void occluded_batch(const FieldScene& fields, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  VF_USE_WIDER(occluded_batch, fields, rays, occluded);
  const std::size_t size = fields.block_size();
  vf::parallel_for(std::size_t{0}, (rays.size() + size - 1) / size, [&](std::size_t block) {
    check_interrupt();
    const std::size_t begin = block * size, count = std::min(size, rays.size() - begin);
    fields.trace_block(rays.subspan(begin, count), false, nullptr, occluded.data() + begin);
  });
}

void occluded_block(const FieldScene& fields, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  VF_USE_WIDER(occluded_block, fields, rays, occluded);
  const std::size_t size = fields.block_size();
  for (std::size_t begin = 0; begin < rays.size(); begin += size) {
    const std::size_t count = std::min(size, rays.size() - begin);
    fields.trace_block(rays.subspan(begin, count), false, nullptr, occluded.data() + begin);
  }
}

void intersect_batch(const FieldScene& fields, std::span<const Ray> rays, std::span<Hit> hits) {
  VF_USE_WIDER(intersect_batch, fields, rays, hits);
  const std::size_t size = fields.block_size();
  vf::parallel_for(std::size_t{0}, (rays.size() + size - 1) / size, [&](std::size_t block) {
    check_interrupt();
    const std::size_t begin = block * size, count = std::min(size, rays.size() - begin);
    fields.trace_block(rays.subspan(begin, count), true, hits.data() + begin, nullptr);
  });
}

}  // namespace vf::field

#if VF_IN_WIDER_COPY
namespace vf::isa_avx512 {
VF_WIDER_ENTRY void occluded_batch(const field::FieldScene& fields, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  field::occluded_batch(fields, rays, occluded);
}
VF_WIDER_ENTRY void occluded_block(const field::FieldScene& fields, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  field::occluded_block(fields, rays, occluded);
}
VF_WIDER_ENTRY void intersect_batch(const field::FieldScene& fields, std::span<const Ray> rays, std::span<Hit> hits) {
  field::intersect_batch(fields, rays, hits);
}
}  // namespace vf::isa_avx512
#endif
