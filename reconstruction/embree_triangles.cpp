// Embree 3 triangles (RTC_GEOMETRY_TYPE_TRIANGLE, high-quality BVH build): the industrial
// reference for triangle tracing. Embree's internal work is not counted, only its rays.
#include <embree3/rtcore.h>

#include <atomic>

#include "core/embree_ray.hpp"
#include "core/error.hpp"
#include "reconstruction/mesh_engine.hpp"

namespace pcrt {
namespace {

inline const Counter kEmbreeTriangleRays{"embree_triangle_rays",
                                         "rays traced by Embree over triangles"};

class EmbreeTriangles final : public MeshEngine {
 public:
  explicit EmbreeTriangles(const TriangleMesh& mesh) : mesh_(mesh) {
    device_ = rtcNewDevice(nullptr);
    if (!device_)
      input_error("embree: Embree could not start (error {})", int(rtcGetDeviceError(nullptr)));
    // Embree's own allocations (its BVH above all) are counted through its memory monitor.
    rtcSetDeviceMemoryMonitorFunction(
        device_,
        [](void* user, ssize_t bytes, bool) {
          static_cast<std::atomic<int64_t>*>(user)->fetch_add(bytes);
          return true;
        },
        &bytes_);
    scene_ = rtcNewScene(device_);
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    // Embree reads vertices and indices from our arrays (shared buffers): no copy. It may read
    // up to 16 bytes past a vertex, so the vertex array gets a padded copy instead.
    padded_.resize(mesh.vertices.size() + 1);
    for (size_t i = 0; i < mesh.vertices.size(); ++i)
      padded_[i] = {mesh.vertices[i].x(), mesh.vertices[i].y(), mesh.vertices[i].z(), 0};
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, padded_.data(),
                               0, 4 * sizeof(float), mesh.vertices.size());
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                               mesh.triangles.data(), 0, 3 * sizeof(uint32_t),
                               mesh.triangles.size());
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    rtcCommitScene(scene_);
  }
  ~EmbreeTriangles() override {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
  }
  EmbreeTriangles(const EmbreeTriangles&) = delete;
  EmbreeTriangles& operator=(const EmbreeTriangles&) = delete;

  bool closest_hit(const Ray& ray, Hit& hit, OpCounters& counters) const override {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh = embree_ray(ray, hit.t);
    rtcIntersect1(scene_, &context, &rh);
    counters.add(kEmbreeTriangleRays);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit.t = rh.ray.tfar;
    hit.prim = rh.hit.primID;
    hit.p = ray.at(hit.t);
    hit.n = mesh_.normal(rh.hit.primID);
    hit.footprint = 0;
    return true;
  }
  [[nodiscard]] size_t memory_bytes() const override {
    return padded_.size() * sizeof(Float4) + size_t(std::max<int64_t>(bytes_.load(), 0));
  }

 private:
  struct Float4 {
    float x, y, z, w;
  };
  const TriangleMesh& mesh_;
  std::vector<Float4> padded_;
  std::atomic<int64_t> bytes_{0};
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

const RegisterMeshEngine kRegister{MeshEngineInfo{
    "embree", "Embree 3 triangles, high-quality BVH build (the industrial reference)",
    [](const TriangleMesh& mesh, OpCounters&, Timings& timings) {
      ScopedTimer t(timings, "build");
      return std::unique_ptr<MeshEngine>(std::make_unique<EmbreeTriangles>(mesh));
    }}};

}  // namespace
}  // namespace pcrt
