#include "embree_scene.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <mutex>
#include <vector>

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "visfield/core/error.hpp"

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

struct EmbreeScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<std::uint32_t> prim, instance;  // Indexed by Embree's primID.
  std::atomic<std::int64_t> device_bytes{0};
  ErrorLog errors;
  AccelStats stats;

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    if (scene != nullptr) rtcReleaseScene(scene);
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

EmbreeScene::EmbreeScene(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
EmbreeScene::EmbreeScene(EmbreeScene&&) noexcept = default;
EmbreeScene& EmbreeScene::operator=(EmbreeScene&&) noexcept = default;
EmbreeScene::~EmbreeScene() = default;

EmbreeScene EmbreeScene::build(const TriangleSet& set, int threads) {
  auto impl = std::make_unique<Impl>();
  const std::string config = threads > 0 ? "threads=" + std::to_string(threads) : std::string();
  impl->device = rtcNewDevice(config.c_str());
  if (impl->device == nullptr) {
    throw Error(std::string("embree: rtcNewDevice failed: ") + error_code_name(rtcGetDeviceError(nullptr)));
  }
  rtcSetDeviceErrorFunction(impl->device, &ErrorLog::record, &impl->errors);
  rtcSetDeviceMemoryMonitorFunction(impl->device, &count_bytes, &impl->device_bytes);

  const auto start = std::chrono::steady_clock::now();
  impl->scene = rtcNewScene(impl->device);
  const std::size_t count = set.size();
  if (count > 0) {
    if (count > std::numeric_limits<std::uint32_t>::max() / 3)
      throw Error("embree: too many triangles for one geometry");
    RTCGeometry geometry = rtcNewGeometry(impl->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * count));
    auto* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), count));
    impl->check("allocating the triangle buffers");
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096), [&](const auto& range) {
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
    rtcAttachGeometry(impl->scene, geometry);
    rtcReleaseGeometry(geometry);
  }
  rtcCommitScene(impl->scene);
  impl->check("building the scene");
  impl->prim = set.prim;
  impl->instance = set.instance;
  impl->stats.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  const std::int64_t device_bytes = impl->device_bytes.load();
  impl->stats.memory_bytes = static_cast<std::size_t>(device_bytes > 0 ? device_bytes : 0) +
                             (impl->prim.size() + impl->instance.size()) * sizeof(std::uint32_t);
  return EmbreeScene(std::move(impl));
}

std::optional<Hit> EmbreeScene::intersect(const Ray& ray) const {
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
  rtcIntersect1(impl_->scene, &context, &query);
  if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  const std::uint32_t index = query.hit.primID;
  return Hit{query.ray.tfar, query.hit.u, query.hit.v, impl_->prim[index], impl_->instance[index]};
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
  rtcOccluded1(impl_->scene, &context, &query);
  // Embree marks an occluded ray by setting tfar to -infinity.
  return query.tfar == -std::numeric_limits<float>::infinity();
}

const AccelStats& EmbreeScene::stats() const { return impl_->stats; }

namespace {

// Mirrors Embree's CPU dispatch: the best ISA the library was compiled for (VISFIELD_EMBREE_ISA_*,
// taken from Embree's CMake package) that this CPU supports.
std::string dispatched_isa() {
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
