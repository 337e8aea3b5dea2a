// Fuzz target: the C API as a program embedding visfield calls it. The input is read as a sequence of
// calls — scenes created, loaded (built-in specs) and filled from the input's bytes (meshes, objects,
// transforms), structures built by any spec, objects removed, moved and inserted and committed,
// queries of AoS and SoA rays whose values come from the input (NaN, ±inf, zero directions,
// denormals, reversed intervals), fields, releases, and calls with released, forged and foreign
// handles, NULL pointers and counts whose arrays overflow. Each call must return VF_OK or an error
// code with a one-line message; a released, forged or foreign handle must be refused; and every
// answer of an exact structure must equal the brute-force oracle's over the objects the structure
// holds (committed edits applied, staged ones not), bit for bit. Anything else aborts.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "capi/handles.hpp"
#include "differential/harness.hpp"
#include "input_reader.hpp"
#include "visfield/accel/brute_force.hpp"
#include "visfield/core/triangle_set.hpp"
#include "visfield/io/scene_file.hpp"
#include "visfield/visfield.h"

namespace {

using namespace vf;

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "c_api: %s\n", what.c_str());
  std::abort();
}

// The input's reader, with the target's own kind of number: mostly small coordinates (eighths within
// ±16), sometimes any 32 bits (NaN, ±inf, denormals).
class Reader : public fuzz::InputReader {
 public:
  using InputReader::InputReader;
  float real() {
    const std::uint8_t kind = byte();
    if (kind < 200) return static_cast<float>(static_cast<std::int8_t>(byte())) / 8.0f;
    if (kind < 230) return 0.0f;
    return bits();
  }
};

// What the fuzzer holds of the objects of a scene or structure: meshes and placed objects in id order.
struct Objects {
  std::vector<TriangleMesh> meshes;
  std::vector<Instance> objects;

  Instance* find(ObjectId id) {
    for (Instance& o : objects)
      if (o.id == id) return &o;
    return nullptr;
  }
};

Objects objects_of(const Scene& scene) { return Objects{scene.meshes, scene.instances()}; }

struct SceneSlot {
  vf_scene handle = nullptr;
  Scene mirror;  // the same calls applied to a C++ scene
};

struct StructureSlot {
  vf_structure handle = nullptr;
  bool exact = false;
  bool two_level = false;
  bool known = true;  // false once an edit was accepted that the mirror cannot follow
  Objects committed, staged;
};

constexpr std::size_t kSlots = 3;
constexpr std::size_t kMaxRays = 48;
constexpr int kMaxCalls = 48;

struct State {
  int field_builds = 0;  // at most one an input: a field's precompute costs more than all the rest

  /// Whether a field (or an auto spec, which renders a probe) may be built now: the first asked
  /// for in an input, when the input's next byte is one value of 256 (a low value such as 0 is
  /// common in saved inputs). The smallest field's precompute (18,560 cells) costs some twenty
  /// times the rest of an input, and took four fifths of the target's time when allowed more often.
  bool may_build_field(Reader& in) { return field_builds++ == 0 && in.byte() == 0x9d; }
  std::array<SceneSlot, kSlots> scenes;
  std::array<StructureSlot, kSlots> structures;
  std::array<vf_field, kSlots> fields{};
  std::vector<std::uintptr_t> stale;  // handles released before
};

// Checks what a call returned: VF_OK, or an error code with a one-line message.
vf_error checked(vf_error code, const char* call) {
  if (code < VF_OK || code > VF_ERROR_INTERRUPTED) finding(std::string(call) + ": returned an unknown code " + std::to_string(code));
  if (code != VF_OK) {
    const std::string message = vf_last_error_message();
    if (message.empty() || message.find('\n') != std::string::npos) finding(std::string(call) + ": error without a one-line message");
  }
  return code;
}

void expect_refused(vf_error code, const char* call) {
  if (checked(code, call) != VF_ERROR_INVALID_ARGUMENT) finding(std::string(call) + ": a stale, forged or foreign handle was not refused");
}

std::array<float, 12> matrix(Reader& in) {
  std::array<float, 12> m{};
  if (in.byte() < 160) {  // a rotation about z times a scale, and a translation: mostly accepted
    const float angle = static_cast<float>(in.byte()) * 0.05f, scale = 0.25f + static_cast<float>(in.byte() % 16) * 0.25f;
    m = {std::cos(angle) * scale, -std::sin(angle) * scale, 0, in.real(), std::sin(angle) * scale, std::cos(angle) * scale, 0, in.real(),
         0, 0, scale, in.real()};
  } else {
    for (float& x : m) x = in.real();
  }
  return m;
}

std::vector<vf_ray> rays(Reader& in, std::size_t n) {
  std::vector<vf_ray> out(n);
  for (vf_ray& r : out) {
    r = vf_ray{in.real(), in.real(), in.real(), in.real(), in.real(), in.real(), 0.0f, INFINITY};
    const std::uint8_t range = in.byte();
    if (range > 200) r.tmin = in.real(), r.tmax = in.real();  // reversed, NaN, negative ...
  }
  return out;
}

// The oracle's closest hits for the structure's committed objects.
std::vector<Hit> oracle_hits(const StructureSlot& s, const std::vector<vf_ray>& in) {
  std::vector<Hit> out(in.size());
  const std::span<const Ray> rays(reinterpret_cast<const Ray*>(in.data()), in.size());
  if (s.two_level) {
    const test::InstancedOracle oracle(s.committed.objects, s.committed.meshes);
    for (std::size_t i = 0; i < rays.size(); ++i) out[i] = rays[i].is_valid() ? oracle.intersect(rays[i]) : Hit{};
    return out;
  }
  TriangleSet all;
  for (const Instance& o : s.committed.objects) {
    const TriangleSet part = object_triangles(s.committed.meshes[o.mesh], o.transform, o.id);
    all.triangles.insert(all.triangles.end(), part.triangles.begin(), part.triangles.end());
    all.prim.insert(all.prim.end(), part.prim.begin(), part.prim.end());
    all.instance.insert(all.instance.end(), part.instance.begin(), part.instance.end());
    all.degenerate_count += part.degenerate_count;
    all.bounds.extend(part.bounds);
  }
  const BruteForce oracle = BruteForce::build(all);
  for (std::size_t i = 0; i < rays.size(); ++i) out[i] = rays[i].is_valid() ? oracle.intersect(rays[i]) : Hit{};
  return out;
}

// A hit as the C API writes it.
vf_hit to_c(const Hit& h) { return vf_hit{h.t, h.u, h.v, h.prim, h.instance, h.normal.x, h.normal.y, h.normal.z}; }

std::string describe(const vf_hit& h) {
  char text[160];
  std::snprintf(text, sizeof text, "t=%a u=%a v=%a prim=%u instance=%u", h.t, h.u, h.v, h.prim, h.instance);
  return text;
}

void compare(const StructureSlot& s, const std::vector<vf_ray>& in, const std::vector<vf_hit>* hits, const std::uint8_t* occluded) {
  if (!s.exact || !s.known) return;
  const std::vector<Hit> expected = oracle_hits(s, in);
  const auto ray_of = [&](std::size_t i) {
    const vf_ray& r = in[i];
    char text[256];
    std::snprintf(text, sizeof text, "%s, ray %zu (org %a %a %a, dir %a %a %a, t %a %a)", vf_structure_spec(s.handle), i, r.org_x, r.org_y, r.org_z,
                  r.dir_x, r.dir_y, r.dir_z, r.tmin, r.tmax);
    return std::string(text);
  };
  for (std::size_t i = 0; i < in.size(); ++i) {
    const vf_hit want = to_c(expected[i]);
    if (hits && std::memcmp(&want, &(*hits)[i], sizeof want) != 0)
      finding(ray_of(i) + ": the closest hit differs from the oracle's (" + describe(want) + " expected, " + describe((*hits)[i]) + ")");
    if (occluded && (occluded[i] != 0) != expected[i].found)
      finding(ray_of(i) + ": occluded differs from the oracle's (" + (expected[i].found ? describe(want) : std::string("a miss")) + " expected)");
  }
}

void query(State& st, Reader& in) {
  StructureSlot& s = st.structures[in.byte() % kSlots];
  if (!s.handle) return;
  const std::size_t n = in.byte() % (kMaxRays + 1);
  const std::vector<vf_ray> r = rays(in, n);
  switch (in.byte() % 4) {
    case 0: {
      std::vector<vf_hit> out(n);
      if (checked(vf_intersect(s.handle, r.data(), n, out.data()), "vf_intersect") != VF_OK) finding("vf_intersect refused valid arrays");
      compare(s, r, &out, nullptr);
      break;
    }
    case 1: {
      std::vector<std::uint8_t> out(n);
      if (checked(vf_occluded(s.handle, r.data(), n, out.data()), "vf_occluded") != VF_OK) finding("vf_occluded refused valid arrays");
      compare(s, r, nullptr, out.data());
      break;
    }
    case 2: {
      std::vector<float> c[8];
      for (int k = 0; k < 8; ++k) c[k].resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        const float* f = &r[i].org_x;
        for (int k = 0; k < 8; ++k) c[k][i] = f[k];
      }
      const vf_rays_soa soa{c[0].data(), c[1].data(), c[2].data(), c[3].data(), c[4].data(), c[5].data(), c[6].data(), c[7].data()};
      std::vector<float> t(n), u(n), v(n), nx(n), ny(n), nz(n);
      std::vector<std::uint32_t> prim(n), instance(n);
      const vf_hits_soa out{t.data(), u.data(), v.data(), prim.data(), instance.data(), nx.data(), ny.data(), nz.data()};
      if (checked(vf_intersect_soa(s.handle, &soa, n, &out), "vf_intersect_soa") != VF_OK) finding("vf_intersect_soa refused valid arrays");
      std::vector<vf_hit> hits(n);
      for (std::size_t i = 0; i < n; ++i) hits[i] = vf_hit{t[i], u[i], v[i], prim[i], instance[i], nx[i], ny[i], nz[i]};
      compare(s, r, &hits, nullptr);
      break;
    }
    default: {
      // NULL arrays and counts whose arrays overflow: refused.
      vf_hit hit;
      std::uint8_t o = 0;
      if (checked(vf_intersect(s.handle, nullptr, n + 1, &hit), "vf_intersect") != VF_ERROR_INVALID_ARGUMENT) finding("NULL rays accepted");
      const std::size_t huge = SIZE_MAX - in.byte();
      if (checked(vf_occluded(s.handle, r.data(), huge, &o), "vf_occluded") != VF_ERROR_INVALID_ARGUMENT) finding("an overflowing count accepted");
      if (checked(vf_intersect(s.handle, r.data(), huge / 16, &hit), "vf_intersect") != VF_ERROR_INVALID_ARGUMENT)
        finding("an overflowing count accepted");
      break;
    }
  }
}

void add_mesh(SceneSlot& s, Reader& in) {
  const std::size_t vertices = in.byte() % 9, triangles = in.byte() % 7;
  std::vector<float> v(3 * vertices);
  for (float& x : v) x = in.real();
  std::vector<std::uint32_t> idx(3 * triangles);
  for (std::uint32_t& i : idx) i = in.byte() < 240 ? in.byte() % std::max<std::size_t>(vertices, 1) : in.u32();
  std::uint32_t mesh = 0;
  if (checked(vf_scene_add_mesh(s.handle, v.data(), vertices, idx.data(), triangles, &mesh), "vf_scene_add_mesh") != VF_OK) return;
  TriangleMesh m;
  m.name = "mesh " + std::to_string(s.mirror.meshes.size());
  for (std::size_t i = 0; i < vertices; ++i) m.positions.push_back(Vec3f{v[3 * i], v[3 * i + 1], v[3 * i + 2]});
  for (std::size_t i = 0; i < triangles; ++i) m.triangles.push_back({idx[3 * i], idx[3 * i + 1], idx[3 * i + 2]});
  s.mirror.meshes.push_back(std::move(m));
  if (mesh != s.mirror.meshes.size() - 1) finding("add_mesh: mesh index " + std::to_string(mesh));
}

void scene_call(State& st, Reader& in) {
  SceneSlot& s = st.scenes[in.byte() % kSlots];
  const std::uint8_t op = in.byte() % 7;
  if (op == 0 || op == 1) {
    if (s.handle) return;
    static const char* const kSpecs[] = {"builtin:sphere:size=60", "builtin:boxes:size=3,seed=2", "builtin:soup:size=24,seed=1",
                                         "builtin:nothing", "builtin:soup:size=-1"};
    const char* spec = kSpecs[in.byte() % 5];
    if (op == 0 ? checked(vf_scene_create(&s.handle), "vf_scene_create") == VF_OK : checked(vf_scene_load(spec, &s.handle), "vf_scene_load") == VF_OK)
      s.mirror = op == 0 ? Scene{} : load_scene(spec);
    return;
  }
  if (!s.handle) return;
  if (op == 2) return add_mesh(s, in);
  if (op == 3) {
    const std::uint32_t mesh = in.byte() % 4;
    const std::array<float, 12> m = matrix(in);
    const bool identity = in.byte() < 64;
    std::uint32_t id = 0;
    if (checked(vf_scene_add_instance(s.handle, mesh, identity ? nullptr : m.data(), &id), "vf_scene_add_instance") == VF_OK &&
        s.mirror.add_instance(mesh, identity ? Transform{} : capi::transform_from_3x4(m.data())) != id)
      finding("add_instance: the id differs from the C++ scene's");
    return;
  }
  const ObjectId id = in.byte() % 8;
  if (op == 4) {
    const std::array<float, 12> m = matrix(in);
    if (checked(vf_scene_set_transform(s.handle, id, m.data()), "vf_scene_set_transform") == VF_OK)
      s.mirror.set_transform(id, capi::transform_from_3x4(m.data()));
  } else if (op == 5) {
    if (checked(vf_scene_remove_instance(s.handle, id), "vf_scene_remove_instance") == VF_OK) s.mirror.remove_instance(id);
  } else {
    std::size_t counts[3];
    float lo[3], hi[3];
    checked(vf_scene_counts(s.handle, &counts[0], &counts[1], &counts[2]), "vf_scene_counts");
    checked(vf_scene_bounds(s.handle, lo, hi), "vf_scene_bounds");
    if (counts[1] != s.mirror.instances().size()) finding("scene_counts: objects differ from the C++ scene's");
  }
}

void build(State& st, Reader& in) {
  SceneSlot& from = st.scenes[in.byte() % kSlots];
  StructureSlot& s = st.structures[in.byte() % kSlots];
  if (!from.handle || s.handle) return;
  // `auto` is left to the structure_spec target: its planner renders a probe image, too slow here.
  static const char* const kSpecs[] = {"bvh", "bvh:levels=2", "bvh:leaf=1", "grid", "kdtree", "median-bsp", "brute",
                                       "beam:dirs=33,n=4", "field:positions=290,directions=8", "grid:density=0", "octree", "bvh:leaf=0"};
  std::string spec = kSpecs[in.byte() % std::size(kSpecs)];
  if (in.byte() > 240) {  // any text
    spec.clear();
    for (std::size_t k = in.byte() % 24; k > 0; --k) spec.push_back(static_cast<char>(in.byte()));
  }
  // A text the mutator made a field or auto spec costs as much as a listed field.
  const std::string_view name = std::string_view(spec).substr(0, spec.find(':'));
  if ((name.find("field") != std::string_view::npos || name.find("auto") != std::string_view::npos) && !st.may_build_field(in)) return;
  if (checked(vf_structure_build(from.handle, spec.c_str(), &s.handle), "vf_structure_build") != VF_OK) {
    s.handle = nullptr;
    return;
  }
  vf_structure_stats stats;
  if (checked(vf_structure_get_stats(s.handle, &stats), "vf_structure_get_stats") != VF_OK) finding("stats of a live structure refused");
  s.exact = stats.exact == 1;
  s.two_level = std::string(vf_structure_spec(s.handle)).find("levels=2") != std::string::npos;
  s.known = true;
  s.committed = s.staged = objects_of(from.mirror);
}

void edit(State& st, Reader& in) {
  StructureSlot& s = st.structures[in.byte() % kSlots];
  if (!s.handle) return;
  const ObjectId id = in.byte() % 8;
  switch (in.byte() % 4) {
    case 0:
      if (checked(vf_structure_remove(s.handle, id), "vf_structure_remove") == VF_OK) {
        const auto at = std::find_if(s.staged.objects.begin(), s.staged.objects.end(), [&](const Instance& o) { return o.id == id; });
        if (at == s.staged.objects.end()) s.known = false;
        else s.staged.objects.erase(at);
      }
      break;
    case 1: {
      const std::array<float, 12> m = matrix(in);
      if (checked(vf_structure_move(s.handle, id, m.data()), "vf_structure_move") == VF_OK) {
        if (Instance* o = s.staged.find(id)) o->transform = capi::transform_from_3x4(m.data());
        else s.known = false;
      }
      break;
    }
    case 2: {
      SceneSlot& from = st.scenes[in.byte() % kSlots];
      if (!from.handle) break;
      if (checked(vf_structure_insert(s.handle, from.handle, id), "vf_structure_insert") == VF_OK) {
        const Instance* o = from.mirror.find_instance(id);
        if (!o || s.staged.find(id)) {
          s.known = false;
          break;
        }
        s.staged.meshes.push_back(from.mirror.meshes[o->mesh]);
        Instance added = *o;
        added.mesh = static_cast<std::uint32_t>(s.staged.meshes.size() - 1);
        s.staged.objects.insert(std::upper_bound(s.staged.objects.begin(), s.staged.objects.end(), added,
                                                 [](const Instance& a, const Instance& b) { return a.id < b.id; }),
                                added);
      }
      break;
    }
    default:
      if (checked(vf_structure_commit(s.handle), "vf_structure_commit") == VF_OK) s.committed = s.staged;
      else s.known = false;
  }
}

void fields(State& st, Reader& in) {
  vf_field& f = st.fields[in.byte() % kSlots];
  if (!f) {
    SceneSlot& from = st.scenes[in.byte() % kSlots];
    if (!from.handle || !st.may_build_field(in)) return;
    // The smallest fields (the defaults take 4226 x 32^2 rays to build: too slow for a fuzzer), and a refused one.
    static const char* const kParams[] = {"positions=290,directions=8", "positions=290,directions=8,normals=oct16", "directions=7",
                                          "positions=290,directions=8,storage=f32"};
    if (checked(vf_field_build(from.handle, in.byte() % 3, kParams[in.byte() % 4], &f), "vf_field_build") != VF_OK) f = nullptr;
    return;
  }
  const std::size_t n = in.byte() % (kMaxRays + 1);
  const std::vector<vf_ray> r = rays(in, n);
  std::vector<vf_hit> hits(n);
  std::vector<std::uint8_t> occluded(n);
  vf_field_info info;
  if (checked(vf_field_intersect(f, r.data(), n, hits.data()), "vf_field_intersect") != VF_OK ||
      checked(vf_field_occluded(f, r.data(), n, occluded.data()), "vf_field_occluded") != VF_OK ||
      checked(vf_field_get_info(f, &info), "vf_field_get_info") != VF_OK)
    finding("a live field refused valid arrays");
}

void release(State& st, Reader& in) {
  const std::size_t k = in.byte() % kSlots;
  switch (in.byte() % 3) {
    case 0:
      if (!st.scenes[k].handle) return;
      checked(vf_scene_release(st.scenes[k].handle), "vf_scene_release");
      st.stale.push_back(reinterpret_cast<std::uintptr_t>(st.scenes[k].handle));
      st.scenes[k] = SceneSlot{};
      break;
    case 1:
      if (!st.structures[k].handle) return;
      checked(vf_structure_release(st.structures[k].handle), "vf_structure_release");
      st.stale.push_back(reinterpret_cast<std::uintptr_t>(st.structures[k].handle));
      st.structures[k] = StructureSlot{};
      break;
    default:
      if (!st.fields[k]) return;
      checked(vf_field_release(st.fields[k]), "vf_field_release");
      st.stale.push_back(reinterpret_cast<std::uintptr_t>(st.fields[k]));
      st.fields[k] = nullptr;
  }
}

// A call with a handle that is not live for its kind: released before, forged, or of another kind.
void bad_handle(State& st, Reader& in) {
  std::uintptr_t h = 0;
  const std::uint8_t source = in.byte() % 3;
  if (source == 0 && !st.stale.empty()) {
    h = st.stale[in.byte() % st.stale.size()];
    // A stale handle stays refused unless its slot came back with the same generation (2^24 releases).
  } else if (source == 1) {
    h = static_cast<std::uintptr_t>(in.u32()) | (static_cast<std::uintptr_t>(in.u32()) << 32);
  } else {
    h = reinterpret_cast<std::uintptr_t>(st.scenes[in.byte() % kSlots].handle);  // a scene as a structure or field
  }
  if (h == 0) return;
  for (const auto& s : st.structures)
    if (reinterpret_cast<std::uintptr_t>(s.handle) == h) return;  // forged into a live one: not a mistake to find
  for (const vf_field f : st.fields)
    if (reinterpret_cast<std::uintptr_t>(f) == h) return;
  const vf_ray ray{0, 0, 1, 0, 0, -1, 0, INFINITY};
  vf_hit hit;
  std::uint8_t o = 0;
  switch (in.byte() % 6) {
    case 0: expect_refused(vf_intersect(reinterpret_cast<vf_structure>(h), &ray, 1, &hit), "vf_intersect"); break;
    case 1: expect_refused(vf_occluded(reinterpret_cast<vf_structure>(h), &ray, 1, &o), "vf_occluded"); break;
    case 2: expect_refused(vf_structure_commit(reinterpret_cast<vf_structure>(h)), "vf_structure_commit"); break;
    case 3: expect_refused(vf_structure_release(reinterpret_cast<vf_structure>(h)), "vf_structure_release"); break;
    case 4: expect_refused(vf_field_occluded(reinterpret_cast<vf_field>(h), &ray, 1, &o), "vf_field_occluded"); break;
    default: {
      for (const auto& s : st.scenes)
        if (reinterpret_cast<std::uintptr_t>(s.handle) == h) return;
      expect_refused(vf_scene_release(reinterpret_cast<vf_scene>(h)), "vf_scene_release");
    }
  }
}

}  // namespace

// One thread: the calls are small, and the queries' thread pool would cost more than they do.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  vf_set_threads(1);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Reader in(data, size);
  State st;
  for (int call = 0; call < kMaxCalls && !in.done(); ++call) {
    switch (in.byte() % 8) {
      case 0:
      case 1: scene_call(st, in); break;
      case 2: build(st, in); break;
      case 3:
      case 4: query(st, in); break;
      case 5: edit(st, in); break;
      case 6: in.byte() % 2 ? fields(st, in) : release(st, in); break;
      default: bad_handle(st, in);
    }
  }
  // Everything still held is released (a leak is a finding under ASan).
  for (auto& s : st.structures)
    if (s.handle && checked(vf_structure_release(s.handle), "vf_structure_release") != VF_OK) finding("release of a live structure refused");
  for (vf_field f : st.fields)
    if (f && checked(vf_field_release(f), "vf_field_release") != VF_OK) finding("release of a live field refused");
  for (auto& s : st.scenes)
    if (s.handle && checked(vf_scene_release(s.handle), "vf_scene_release") != VF_OK) finding("release of a live scene refused");
  return 0;
}
