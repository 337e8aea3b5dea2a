#include "embree_scene.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <mutex>
#include <vector>

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>

#include "visfield/accel/batch.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/isa.hpp"
#include "visfield/core/parallel.hpp"

namespace vf::bench {

static_assert(Accelerator<EmbreeScene>);

namespace {

const char* error_code_name(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_UNKNOWN: return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
  }
  return "unrecognised error code";
}

// Embree reports the message through a callback and the code through rtcGetDeviceError; the
// callback may run on Embree's worker threads, hence the mutex.
struct ErrorLog {
  std::mutex mutex;
  std::string first_message;

  static void record(void* user, RTCError, const char* message) {
    auto* log = static_cast<ErrorLog*>(user);
    const std::lock_guard lock(log->mutex);
    if (log->first_message.empty() && message != nullptr) log->first_message = message;
  }
};

// Sums the signed sizes Embree announces for every device allocation and release.
bool count_bytes(void* user, ssize_t bytes, bool /*post*/) {
  static_cast<std::atomic<std::int64_t>*>(user)->fetch_add(bytes, std::memory_order_relaxed);
  return true;
}

}  // namespace

/// The Embree objects and the tables that map Embree's ids back to ours.
struct EmbreeLayout {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<RTCScene> mesh_scenes;          // Instancing: one per mesh in use (released with the layout).
  // Flattened: indexed by primID. Instancing: prim[mesh] maps primID, instance_id[instID] the object.
  std::vector<std::uint32_t> prim;
  std::vector<ObjectId> instance;
  std::vector<std::vector<std::uint32_t>> mesh_prim;
  std::vector<std::uint32_t> instance_mesh;  // Instancing: mesh of each instance geometry.
  bool instanced = false;
  int packet = 1;  // occluded_batch's rays per Embree call
  std::atomic<std::int64_t> device_bytes{0};
  ErrorLog errors;
  AccelStats stats;

  EmbreeLayout() = default;
  EmbreeLayout(const EmbreeLayout&) = delete;
  EmbreeLayout& operator=(const EmbreeLayout&) = delete;
  ~EmbreeLayout() {
    if (scene != nullptr) rtcReleaseScene(scene);
    for (RTCScene s : mesh_scenes)
      if (s != nullptr) rtcReleaseScene(s);
    if (device != nullptr) rtcReleaseDevice(device);
  }

  /// Throws vf::Error when the device has recorded an error since the last call.
  void check(const char* during) {
    const RTCError code = rtcGetDeviceError(device);
    if (code == RTC_ERROR_NONE) return;
    const std::lock_guard lock(errors.mutex);
    std::string message = std::string("embree: ") + during + " failed: " + error_code_name(code);
    if (!errors.first_message.empty()) message += " (" + errors.first_message + ")";
    throw Error(message);
  }
};

EmbreeScene::EmbreeScene(std::unique_ptr<EmbreeLayout> layout) : layout_(std::move(layout)) {}
EmbreeScene::EmbreeScene(EmbreeScene&&) noexcept = default;
EmbreeScene& EmbreeScene::operator=(EmbreeScene&&) noexcept = default;
EmbreeScene::~EmbreeScene() = default;

namespace {

// Where VISFIELD_ISA lowers visfield's kernels below what the processor runs, Embree is held to the same
// instruction set, so that a comparison on the lower path is like for like.
bool embree_lowered() { return active_isa() != widest_isa(); }

std::unique_ptr<EmbreeLayout> new_device(int threads) {
  auto layout = std::make_unique<EmbreeLayout>();
  std::string config = threads > 0 ? "threads=" + std::to_string(threads) : std::string();
  if (embree_lowered()) config += std::string(config.empty() ? "" : ",") + "isa=" + isa_name(active_isa());
  layout->device = rtcNewDevice(config.c_str());
  if (layout->device == nullptr)
    throw Error(std::string("embree: rtcNewDevice failed: ") + error_code_name(rtcGetDeviceError(nullptr)));
  rtcSetDeviceErrorFunction(layout->device, &ErrorLog::record, &layout->errors);
  rtcSetDeviceMemoryMonitorFunction(layout->device, &count_bytes, &layout->device_bytes);
  return layout;
}

// A committed Embree scene holding the triangles of `set` as one triangle geometry (primID = index).
RTCScene triangle_scene(EmbreeLayout& layout, const TriangleSet& set) {
  RTCScene scene = rtcNewScene(layout.device);
  const std::size_t count = set.size();
  if (count > 0) {
    if (count > std::numeric_limits<std::uint32_t>::max() / 3) throw Error("embree: too many triangles for one geometry");
    RTCGeometry geometry = rtcNewGeometry(layout.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * count));
    auto* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), count));
    layout.check("allocating the triangle buffers");
    vf::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096), [&](const auto& range) {
      for (std::size_t i = range.begin(); i != range.end(); ++i) {
        for (std::size_t corner = 0; corner < 3; ++corner) {
          const Vec3f& p = set.triangles[i][corner];
          float* out = vertices + 3 * (3 * i + corner);
          out[0] = p.x;
          out[1] = p.y;
          out[2] = p.z;
          indices[3 * i + corner] = static_cast<std::uint32_t>(3 * i + corner);
        }
      }
    });
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(scene);
  return scene;
}

void finish_stats(EmbreeLayout& layout, const Stopwatch& watch, std::size_t table_entries) {
  layout.stats.build_ms = watch.elapsed_ms();
  const std::int64_t device_bytes = layout.device_bytes.load();
  layout.stats.memory_bytes =
      static_cast<std::size_t>(device_bytes > 0 ? device_bytes : 0) + table_entries * sizeof(std::uint32_t);
}

}  // namespace

EmbreeScene EmbreeScene::build(const TriangleSet& set, int threads) {
  auto layout = new_device(threads);
  const Stopwatch watch;
  layout->scene = triangle_scene(*layout, set);
  layout->check("building the scene");
  layout->prim = set.prim;
  layout->instance = set.instance;
  finish_stats(*layout, watch, layout->prim.size() + layout->instance.size());
  return EmbreeScene(std::move(layout));
}

EmbreeScene EmbreeScene::build_instanced(const Scene& scene, int threads) {
  auto layout = new_device(threads);
  layout->instanced = true;
  const Stopwatch watch;
  std::vector<std::int64_t> mesh_scene_index(scene.meshes.size(), -1);
  layout->scene = rtcNewScene(layout->device);
  std::size_t table_entries = 0;
  for (const Instance& inst : scene.instances()) {
    if (mesh_scene_index[inst.mesh] < 0) {
      const TriangleSet set = mesh_triangles(scene.meshes[inst.mesh]);
      mesh_scene_index[inst.mesh] = static_cast<std::int64_t>(layout->mesh_scenes.size());
      layout->mesh_scenes.push_back(triangle_scene(*layout, set));
      layout->mesh_prim.push_back(set.prim);
      table_entries += set.prim.size();
    }
    RTCGeometry geometry = rtcNewGeometry(layout->device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(geometry, layout->mesh_scenes[static_cast<std::size_t>(mesh_scene_index[inst.mesh])]);
    // Column-major 3x4: the columns of scale * R, then the translation.
    const Transform& t = inst.transform;
    float xfm[12];
    for (int column = 0; column < 3; ++column)
      for (int row = 0; row < 3; ++row) xfm[3 * column + row] = t.rotation.rows[row][column] * t.scale;
    xfm[9] = t.translation.x;
    xfm[10] = t.translation.y;
    xfm[11] = t.translation.z;
    rtcSetGeometryTransform(geometry, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
    rtcCommitGeometry(geometry);
    const std::uint32_t id = rtcAttachGeometry(layout->scene, geometry);
    rtcReleaseGeometry(geometry);
    if (id >= layout->instance.size()) {
      layout->instance.resize(id + 1, kInvalidId);
      layout->instance_mesh.resize(id + 1, 0);
    }
    layout->instance[id] = inst.id;
    layout->instance_mesh[id] = static_cast<std::uint32_t>(mesh_scene_index[inst.mesh]);
  }
  rtcCommitScene(layout->scene);
  layout->check("building the instanced scene");
  finish_stats(*layout, watch, table_entries + 2 * layout->instance.size());
  return EmbreeScene(std::move(layout));
}

Hit EmbreeScene::intersect(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit query;
  query.ray.org_x = ray.org.x;
  query.ray.org_y = ray.org.y;
  query.ray.org_z = ray.org.z;
  query.ray.tnear = ray.tmin;
  query.ray.dir_x = ray.dir.x;
  query.ray.dir_y = ray.dir.y;
  query.ray.dir_z = ray.dir.z;
  query.ray.time = 0.0f;
  query.ray.tfar = ray.tmax;
  query.ray.mask = 0xffffffffu;
  query.ray.id = 0;
  query.ray.flags = 0;
  query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(layout_->scene, &context, &query);
  if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return Hit{};
  const Vec3f normal{query.hit.Ng_x, query.hit.Ng_y, query.hit.Ng_z};
  if (!layout_->instanced) {
    const std::uint32_t index = query.hit.primID;
    return Hit::triangle(query.ray.tfar, query.hit.u, query.hit.v, layout_->prim[index], layout_->instance[index], normal);
  }
  const std::uint32_t instance = query.hit.instID[0];
  return Hit::triangle(query.ray.tfar, query.hit.u, query.hit.v,
                       layout_->mesh_prim[layout_->instance_mesh[instance]][query.hit.primID], layout_->instance[instance],
                       normal);
}

bool EmbreeScene::occluded(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay query;
  query.org_x = ray.org.x;
  query.org_y = ray.org.y;
  query.org_z = ray.org.z;
  query.tnear = ray.tmin;
  query.dir_x = ray.dir.x;
  query.dir_y = ray.dir.y;
  query.dir_z = ray.dir.z;
  query.time = 0.0f;
  query.tfar = ray.tmax;
  query.mask = 0xffffffffu;
  query.id = 0;
  query.flags = 0;
  rtcOccluded1(layout_->scene, &context, &query);
  // Embree marks an occluded ray by setting tfar to -infinity.
  return query.tfar == -std::numeric_limits<float>::infinity();
}

const AccelStats& EmbreeScene::stats() const { return layout_->stats; }

void EmbreeScene::set_packet_size(int packet) {
  if (packet != 1 && packet != 16) throw Error("embree: packets=" + std::to_string(packet) + ": expected 1 or 16");
  if (packet == 16 && rtcGetDeviceProperty(layout_->device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) == 0 &&
      rtcGetDeviceProperty(layout_->device, RTC_DEVICE_PROPERTY_RAY_STREAM_SUPPORTED) == 0)
    throw Error("embree: packets=16: this Embree was built without 16-wide ray packets");
  layout_->packet = packet;
}

int EmbreeScene::packet_size() const { return layout_->packet; }

void occluded_batch(const EmbreeScene& embree, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  if (embree.packet_size() == 1) {
    vf::occluded_batch(embree, rays, occluded);  // the generic batch: rtcOccluded1 ray by ray
    return;
  }
  const RTCScene scene = embree.layout_->scene;
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, (rays.size() + 15) / 16, 16), [&](const auto& range) {
    check_interrupt();
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) RTCRay16 packet;
    alignas(64) int valid[16];
    for (std::size_t p = range.begin(); p != range.end(); ++p) {
      const std::size_t first = 16 * p, count = std::min<std::size_t>(16, rays.size() - first);
      for (std::size_t l = 0; l < 16; ++l) {
        valid[l] = l < count ? -1 : 0;
        const Ray& ray = rays[first + std::min(l, count - 1)];
        packet.org_x[l] = ray.org.x;
        packet.org_y[l] = ray.org.y;
        packet.org_z[l] = ray.org.z;
        packet.tnear[l] = ray.tmin;
        packet.dir_x[l] = ray.dir.x;
        packet.dir_y[l] = ray.dir.y;
        packet.dir_z[l] = ray.dir.z;
        packet.time[l] = 0.0f;
        packet.tfar[l] = ray.tmax;
        packet.mask[l] = 0xffffffffu;
        packet.id[l] = static_cast<unsigned>(l);
        packet.flags[l] = 0;
      }
      rtcOccluded16(valid, scene, &context, &packet);
      for (std::size_t l = 0; l < count; ++l) occluded[first + l] = packet.tfar[l] == -std::numeric_limits<float>::infinity() ? 1 : 0;
    }
  });
}

namespace {

// Mirrors Embree's CPU dispatch: the best ISA the library was compiled for (VISFIELD_EMBREE_ISA_*,
// taken from Embree's CMake package) that this CPU supports.
std::string dispatched_isa() {
  if (embree_lowered()) return isa_name(active_isa());
  __builtin_cpu_init();
#if VISFIELD_EMBREE_ISA_AVX512
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512dq") &&
      __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl")) {
    return "avx512";
  }
#endif
#if VISFIELD_EMBREE_ISA_AVX2
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
      __builtin_cpu_supports("bmi2")) {
    return "avx2";
  }
#endif
#if VISFIELD_EMBREE_ISA_AVX
  if (__builtin_cpu_supports("avx")) return "avx";
#endif
#if VISFIELD_EMBREE_ISA_SSE42
  if (__builtin_cpu_supports("sse4.2")) return "sse4.2";
#endif
  return "sse2";
}

}  // namespace

std::string embree_description() {
  RTCDevice device = rtcNewDevice(nullptr);
  std::string version = "3";
  std::string tasking = "unknown";
  if (device != nullptr) {
    version = std::to_string(rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION_MAJOR)) + "." +
              std::to_string(rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION_MINOR)) + "." +
              std::to_string(rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_VERSION_PATCH));
    switch (rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_TASKING_SYSTEM)) {
      case 0: tasking = "internal"; break;
      case 1: tasking = "TBB"; break;
      case 2: tasking = "PPL"; break;
      default: break;
    }
    rtcReleaseDevice(device);
  }
  return "Embree " + version + ", ISA " + dispatched_isa() + ", " + tasking +
         " tasking, build quality medium (default), rtcIntersect1/rtcOccluded1";
}

}  // namespace vf::bench
