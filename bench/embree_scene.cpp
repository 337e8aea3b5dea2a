#include "embree_scene.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <mutex>
#include <vector>

#include <embree3/rtcore.h>
#include <immintrin.h>
#include <tbb/blocked_range.h>

#include "visfield/accel/batch.hpp"
#include "visfield/core/error.hpp"
#include "visfield/core/stopwatch.hpp"
#include "visfield/core/interrupt.hpp"
#include "visfield/core/isa.hpp"
#include "visfield/core/parallel.hpp"
#include "visfield/core/row_transpose.hpp"

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

// Sums the signed sizes Embree announces for every device allocation and release.
bool count_bytes(void* user, ssize_t bytes, bool /*post*/) {
  static_cast<std::atomic<std::int64_t>*>(user)->fetch_add(bytes, std::memory_order_relaxed);
  return true;
}

}  // namespace

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
  bool high_quality = false;
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

EmbreeScene::EmbreeScene(std::shared_ptr<const EmbreeLayout> layout, EmbreeCall call) : layout_(std::move(layout)), call_(call) {}

EmbreeScene EmbreeScene::with_call(EmbreeCall call) const { return EmbreeScene(layout_, call); }

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

RTCBuildQuality build_quality(const EmbreeLayout& layout) {
  return layout.high_quality ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM;
}

// A committed Embree scene holding the triangles of `set` as one triangle geometry (primID = index).
RTCScene triangle_scene(EmbreeLayout& layout, const TriangleSet& set) {
  RTCScene scene = rtcNewScene(layout.device);
  rtcSetSceneBuildQuality(scene, build_quality(layout));
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
    rtcSetGeometryBuildQuality(geometry, build_quality(layout));
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

EmbreeScene EmbreeScene::build(const TriangleSet& set, int threads, EmbreeSettings settings) {
  auto layout = new_device(threads);
  layout->high_quality = settings.high_quality;
  const Stopwatch watch;
  layout->scene = triangle_scene(*layout, set);
  layout->check("building the scene");
  layout->prim = set.prim;
  layout->instance = set.instance;
  finish_stats(*layout, watch, layout->prim.size() + layout->instance.size());
  return EmbreeScene(std::move(layout), settings.call);
}

EmbreeScene EmbreeScene::build_instanced(const Scene& scene, int threads, EmbreeSettings settings) {
  auto layout = new_device(threads);
  layout->instanced = true;
  layout->high_quality = settings.high_quality;
  const Stopwatch watch;
  std::vector<std::int64_t> mesh_scene_index(scene.meshes.size(), -1);
  layout->scene = rtcNewScene(layout->device);
  rtcSetSceneBuildQuality(layout->scene, build_quality(*layout));
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
  return EmbreeScene(std::move(layout), settings.call);
}

namespace {

// Embree asks for flush-to-zero and denormals-are-zero on every thread that calls it; they are set
// around its calls only, so that visfield's own floats (and their bits) stay IEEE's.
class EmbreeFloatMode {
 public:
  EmbreeFloatMode() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | kFlushToZero | kDenormalsAreZero); }
  ~EmbreeFloatMode() { _mm_setcsr(saved_); }
  EmbreeFloatMode(const EmbreeFloatMode&) = delete;
  EmbreeFloatMode& operator=(const EmbreeFloatMode&) = delete;

 private:
  static constexpr unsigned kFlushToZero = 0x8000, kDenormalsAreZero = 0x0040;
  unsigned saved_;
};

// Our Ray (origin, direction, tmin, tmax: 8 floats) into an RTCRay with three 16-byte stores.
void put_ray(const Ray& ray, RTCRay& out) {
  static_assert(sizeof(Ray) == 8 * sizeof(float) && sizeof(RTCRay) == 12 * sizeof(float));
  const __m128 a = _mm_loadu_ps(&ray.org.x);  // ox oy oz dx
  const __m128 b = _mm_loadu_ps(&ray.dir.y);  // dy dz tmin tmax
  // ox oy oz tmin | dx dy dz time=0 | tfar mask=~0 id=0 flags=0
  _mm_storeu_ps(&out.org_x, _mm_blend_ps(a, _mm_shuffle_ps(b, b, _MM_SHUFFLE(2, 2, 2, 2)), 0x8));
  const __m128 d = _mm_shuffle_ps(a, b, _MM_SHUFFLE(1, 0, 3, 3));  // dx dx dy dz
  _mm_storeu_ps(&out.dir_x, _mm_blend_ps(_mm_shuffle_ps(d, d, _MM_SHUFFLE(0, 3, 2, 0)), _mm_setzero_ps(), 0x8));
  const __m128i tail = _mm_set_epi32(0, 0, -1, 0);
  _mm_storeu_ps(&out.tfar, _mm_blend_ps(_mm_castsi128_ps(tail), _mm_shuffle_ps(b, b, _MM_SHUFFLE(3, 3, 3, 3)), 0x1));
}

void put_ray_hit(const Ray& ray, RTCRayHit& out) {
  put_ray(ray, out.ray);
  out.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  out.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

// 16 consecutive rays (the last `count` < 16 repeated into the spare lanes) into a packet's columns:
// two 8 x 8 transposes of their floats, then vector stores.
template <class Packet>
void put_packet(const Ray* rays, std::size_t count, Packet& packet) {
  alignas(32) std::array<Ray, 16> padded;
  const Ray* from = rays;
  if (count < 16) {
    for (std::size_t l = 0; l < 16; ++l) padded[l] = rays[std::min(l, count - 1)];
    from = padded.data();
  }
  for (int half = 0; half < 2; ++half) {
    __m256 column[8];
    simd::rows_to_columns8(reinterpret_cast<const float*>(from + 8 * half), column);
    float* const out[8] = {packet.org_x, packet.org_y, packet.org_z, packet.dir_x, packet.dir_y, packet.dir_z, packet.tnear, packet.tfar};
    for (int c = 0; c < 8; ++c) _mm256_store_ps(out[c] + 8 * half, column[c]);
    _mm256_store_ps(packet.time + 8 * half, _mm256_setzero_ps());
    _mm256_store_si256(reinterpret_cast<__m256i*>(packet.mask + 8 * half), _mm256_set1_epi32(-1));
    _mm256_store_si256(reinterpret_cast<__m256i*>(packet.id + 8 * half), _mm256_setzero_si256());
    _mm256_store_si256(reinterpret_cast<__m256i*>(packet.flags + 8 * half), _mm256_setzero_si256());
  }
}

// The hit Embree found, in our terms (the triangle's ids mapped back to the TriangleSet's).
Hit hit_of(const EmbreeLayout& layout, float t, float u, float v, float nx, float ny, float nz, unsigned prim, unsigned geometry,
           unsigned instance) {
  if (geometry == RTC_INVALID_GEOMETRY_ID) return Hit{};
  const Vec3f normal{nx, ny, nz};
  if (!layout.instanced) return Hit::triangle(t, u, v, layout.prim[prim], layout.instance[prim], normal);
  return Hit::triangle(t, u, v, layout.mesh_prim[layout.instance_mesh[instance]][prim], layout.instance[instance], normal);
}

// Embree marks an occluded ray by setting tfar to -infinity.
bool blocked(float tfar) { return tfar == -std::numeric_limits<float>::infinity(); }

// Rays per task, and per Embree stream call.
constexpr std::size_t kChunk = 256;

// Runs run(first, count) over consecutive chunks of the rays in parallel, Embree's float mode on.
template <class Run>
void for_each_chunk(std::size_t rays, const Run& run) {
  vf::parallel_for(tbb::blocked_range<std::size_t>(0, (rays + kChunk - 1) / kChunk, 1), [&](const auto& range) {
    check_interrupt();
    const EmbreeFloatMode mode;
    for (std::size_t c = range.begin(); c != range.end(); ++c) run(c * kChunk, std::min(kChunk, rays - c * kChunk));
  });
}

RTCIntersectContext context_for(EmbreeCall call) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  // Packets are for coherent rays (camera rays, AO along one line); streams leave Embree to sort.
  context.flags = call == EmbreeCall::packet16 ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  return context;
}

}  // namespace

const char* embree_call_name(EmbreeCall call) {
  switch (call) {
    case EmbreeCall::one: return "1";
    case EmbreeCall::packet16: return "16";
    case EmbreeCall::stream: return "stream";
  }
  return "?";
}

Hit EmbreeScene::intersect(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit query;
  put_ray_hit(ray, query);
  rtcIntersect1(layout_->scene, &context, &query);
  return hit_of(*layout_, query.ray.tfar, query.hit.u, query.hit.v, query.hit.Ng_x, query.hit.Ng_y, query.hit.Ng_z, query.hit.primID,
                query.hit.geomID, query.hit.instID[0]);
}

bool EmbreeScene::occluded(const Ray& ray) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay query;
  put_ray(ray, query);
  rtcOccluded1(layout_->scene, &context, &query);
  return blocked(query.tfar);
}

const AccelStats& EmbreeScene::stats() const { return layout_->stats; }

EmbreeSettings EmbreeScene::settings() const { return {call_, layout_->high_quality}; }

bool EmbreeScene::instanced() const { return layout_->instanced; }

std::string embree_spec(bool instanced, const EmbreeSettings& settings) {
  std::string spec = std::string("embree:levels=") + (instanced ? "2" : "1");
  if (settings.call != EmbreeCall::one) spec += std::string(",call=") + embree_call_name(settings.call);
  if (settings.high_quality) spec += ",quality=high";
  return spec;
}

void intersect_batch(const EmbreeScene& embree, std::span<const Ray> rays, std::span<Hit> hits) {
  const EmbreeLayout& layout = *embree.layout_;
  const EmbreeCall call = embree.call_;
  for_each_chunk(rays.size(), [&](std::size_t first, std::size_t count) {
    RTCIntersectContext context = context_for(call);
    if (call == EmbreeCall::packet16) {
      alignas(64) RTCRayHit16 packet;
      alignas(64) int valid[16];
      for (std::size_t p = 0; p < count; p += 16) {
        const std::size_t n = std::min<std::size_t>(16, count - p);
        put_packet(rays.data() + first + p, n, packet.ray);
        for (std::size_t l = 0; l < 16; ++l) {
          valid[l] = l < n ? -1 : 0;
          packet.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
          packet.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect16(valid, layout.scene, &context, &packet);
        for (std::size_t l = 0; l < n; ++l)
          std::construct_at(&hits[first + p + l], hit_of(layout, packet.ray.tfar[l], packet.hit.u[l], packet.hit.v[l], packet.hit.Ng_x[l],
                                                         packet.hit.Ng_y[l], packet.hit.Ng_z[l], packet.hit.primID[l], packet.hit.geomID[l],
                                                         packet.hit.instID[0][l]));
      }
    } else if (call == EmbreeCall::stream) {
      thread_local std::vector<RTCRayHit> stream(kChunk);
      for (std::size_t i = 0; i < count; ++i) put_ray_hit(rays[first + i], stream[i]);
      rtcIntersect1M(layout.scene, &context, stream.data(), static_cast<unsigned>(count), sizeof(RTCRayHit));
      for (std::size_t i = 0; i < count; ++i) {
        const RTCRayHit& q = stream[i];
        std::construct_at(&hits[first + i],
                          hit_of(layout, q.ray.tfar, q.hit.u, q.hit.v, q.hit.Ng_x, q.hit.Ng_y, q.hit.Ng_z, q.hit.primID, q.hit.geomID, q.hit.instID[0]));
      }
    } else {
      for (std::size_t i = first; i < first + count; ++i) {
        RTCRayHit q;
        put_ray_hit(rays[i], q);
        rtcIntersect1(layout.scene, &context, &q);
        std::construct_at(&hits[i], hit_of(layout, q.ray.tfar, q.hit.u, q.hit.v, q.hit.Ng_x, q.hit.Ng_y, q.hit.Ng_z, q.hit.primID, q.hit.geomID,
                                           q.hit.instID[0]));
      }
    }
  });
}

void occluded_batch(const EmbreeScene& embree, std::span<const Ray> rays, std::span<std::uint8_t> occluded) {
  const EmbreeLayout& layout = *embree.layout_;
  const EmbreeCall call = embree.call_;
  for_each_chunk(rays.size(), [&](std::size_t first, std::size_t count) {
    RTCIntersectContext context = context_for(call);
    if (call == EmbreeCall::packet16) {
      alignas(64) RTCRay16 packet;
      alignas(64) int valid[16];
      for (std::size_t p = 0; p < count; p += 16) {
        const std::size_t n = std::min<std::size_t>(16, count - p);
        put_packet(rays.data() + first + p, n, packet);
        for (std::size_t l = 0; l < 16; ++l) valid[l] = l < n ? -1 : 0;
        rtcOccluded16(valid, layout.scene, &context, &packet);
        for (std::size_t l = 0; l < n; ++l) occluded[first + p + l] = blocked(packet.tfar[l]) ? 1 : 0;
      }
    } else if (call == EmbreeCall::stream) {
      thread_local std::vector<RTCRay> stream(kChunk);
      for (std::size_t i = 0; i < count; ++i) put_ray(rays[first + i], stream[i]);
      rtcOccluded1M(layout.scene, &context, stream.data(), static_cast<unsigned>(count), sizeof(RTCRay));
      for (std::size_t i = 0; i < count; ++i) occluded[first + i] = blocked(stream[i].tfar) ? 1 : 0;
    } else {
      for (std::size_t i = first; i < first + count; ++i) {
        RTCRay q;
        put_ray(rays[i], q);
        rtcOccluded1(layout.scene, &context, &q);
        occluded[i] = blocked(q.tfar) ? 1 : 0;
      }
    }
  });
}

namespace {

// The instruction set Embree says it runs here: its verbose report (printed on stdout by a device made
// with verbose=1, read back through a temporary file) lists the targets this processor supports and
// those the library was compiled for; Embree runs the widest in both.
std::string reported_isa() {
  std::string config = "verbose=1";
  if (embree_lowered()) config += std::string(",isa=") + isa_name(active_isa());
  std::fflush(stdout);
  const int saved = dup(1);
  std::FILE* capture = std::tmpfile();
  if (saved < 0 || capture == nullptr) return "unknown";
  dup2(fileno(capture), 1);
  if (RTCDevice device = rtcNewDevice(config.c_str())) rtcReleaseDevice(device);
  std::fflush(stdout);
  dup2(saved, 1);
  close(saved);
  std::string report;
  std::rewind(capture);
  for (int c; (c = std::fgetc(capture)) != EOF;) report += static_cast<char>(c);
  std::fclose(capture);
  // In its Config section: "Targets : ... (supported)" then "... (compile time enabled)".
  const std::size_t config_at = report.find("Config");
  const std::size_t supported_end = report.find("(supported)", config_at);
  const std::size_t enabled_end = report.find("(compile time enabled)", supported_end);
  if (config_at == std::string::npos || supported_end == std::string::npos || enabled_end == std::string::npos) return "unknown";
  const std::size_t targets = report.find("Targets", config_at);
  const std::string supported = report.substr(targets, supported_end - targets);
  const std::string enabled = report.substr(supported_end, enabled_end - supported_end);
  const auto has = [](const std::string& list, const char* isa) { return (" " + list + " ").find(std::string(" ") + isa + " ") != std::string::npos; };
  for (const char* isa : {"AVX512", "AVX2", "AVX", "SSE4.2", "SSE2"})
    if (has(supported, isa) && has(enabled, isa)) return isa;
  return "unknown";
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
  static const std::string isa = reported_isa();
  return "Embree " + version + ", ISA " + isa + ", " + tasking + " tasking";
}

}  // namespace vf::bench
