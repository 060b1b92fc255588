// Embree 3 triangles (RTC_GEOMETRY_TYPE_TRIANGLE, high-quality BVH build): the industrial
// reference for triangle tracing. Embree's internal work is not counted, only its rays.
#include "core/embree_scene.hpp"
#include "core/error.hpp"
#include "reconstruction/mesh_engine.hpp"

namespace pcrt {
namespace {

inline const Counter kEmbreeTriangleRays{"embree_triangle_rays",
                                         "rays traced by Embree over triangles"};

class EmbreeTriangles final : public MeshEngine {
 public:
  explicit EmbreeTriangles(const TriangleMesh& mesh) : mesh_(mesh) {
    RTCGeometry geom = embree_.new_geometry(RTC_GEOMETRY_TYPE_TRIANGLE);
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
    embree_.build(geom);
  }

  bool closest_hit(const Ray& ray, Hit& hit, OpCounters& counters) const override {
    RTCRayHit rh;
    counters.add(kEmbreeTriangleRays);
    if (!embree_.closest_hit(ray, hit.t, rh)) return false;
    hit.t = rh.ray.tfar;
    hit.prim = rh.hit.primID;
    hit.p = ray.at(hit.t);
    hit.n = mesh_.normal(rh.hit.primID);
    hit.footprint = 0;
    return true;
  }
  bool any_hit(const Ray& ray, OpCounters& counters) const override {
    counters.add(kEmbreeTriangleRays);
    return embree_.occluded(ray);
  }
  [[nodiscard]] size_t memory_bytes() const override {
    return padded_.size() * sizeof(Float4) + embree_.bytes();
  }

 private:
  struct Float4 {
    float x, y, z, w;
  };
  const TriangleMesh& mesh_;
  std::vector<Float4> padded_;
  EmbreeScene embree_{"embree"};
};

}  // namespace

void register_embree_triangles(MeshEngineRegistry& registry) {
  registry.add(MeshEngineInfo{
      "embree", "Embree 3 triangles, high-quality BVH build (the industrial reference)",
      [](const TriangleMesh& mesh, OpCounters&, Timings& timings) {
        ScopedTimer t(timings, "build");
        return std::unique_ptr<MeshEngine>(std::make_unique<EmbreeTriangles>(mesh));
      }});
}

}  // namespace pcrt
