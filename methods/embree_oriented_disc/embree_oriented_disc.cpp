// embree_oriented_disc: the same splats (centre, normal, radius per point) as Embree 3's
// RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT in Embree's own BVH. Not a surveyed method: the industrial
// splat intersector that the surveyed methods' speed and accuracy are compared with.
#include <memory>

#include "core/embree_scene.hpp"
#include "core/error.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"

namespace pcrt {
namespace {

struct EmbreeDiscParams {
  SplatParams splat;
  bool morton_order = false;
};
const ParamList<EmbreeDiscParams>& embree_disc_params() {
  using P = EmbreeDiscParams;
  static const auto l =
      ParamList<P>()
          .add(&P::splat, SplatParams::list())
          .add(&P::morton_order,
               {"morton_order", 0, 0, 1,
                "1: hand Embree the points in Morton order (as our splat methods store them)"});
  return l;
}

class EmbreeOrientedDisc final : public Method {
 public:
  explicit EmbreeOrientedDisc(const EmbreeDiscParams& params) : params_(params) {}
  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    splats_ = prepare_splats(cloud, params_.splat, ctx);
    ScopedTimer t(ctx.timings, "prepare/embree_build");
    embree_ = std::make_unique<EmbreeScene>("embree_oriented_disc");
    RTCGeometry geom = embree_->new_geometry(RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT);
    // Embree wants x, y, z, radius per point and its own copy of the normals.
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), cloud.size()));
    auto* n = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), cloud.size()));
    // Embree gets the points in the cloud's own order unless morton_order=1 asks for ours.
    morton_ = params_.morton_order;
    for (size_t k = 0; k < splats_.size(); ++k) {
      const size_t i = morton_ ? k : splats_.point_of(uint32_t(k));
      for (int a = 0; a < 3; ++a) v[4 * i + size_t(a)] = splats_.centres[k][a];
      v[4 * i + 3] = splats_.radii[k];
      for (int a = 0; a < 3; ++a) n[3 * i + size_t(a)] = splats_.normals[k][a];
    }
    if (!morton_) {
      item_of_point_.resize(splats_.size());
      for (uint32_t k = 0; k < splats_.size(); ++k) item_of_point_[splats_.point_of(k)] = k;
    }
    embree_->build(geom);
  }

  [[nodiscard]] ItemSet items() const override { return splats_.items(); }

  bool intersect_leaf(const Ray&, const LeafVisit&, Hit&, OpCounters&) const override {
    return false;  // never called: own_structure is set, rays go through own_closest_hit
  }

  bool own_closest_hit(const Ray& ray, Hit& hit, OpCounters& counters) const override {
    RTCRayHit rh;
    counters.add(kEmbreeRays);
    if (!embree_->closest_hit(ray, hit.t, rh)) return false;
    const uint32_t k = morton_ ? rh.hit.primID : item_of_point_[rh.hit.primID];
    hit.t = rh.ray.tfar;
    hit.prim = splats_.point_of(k);
    hit.p = ray.at(hit.t);
    hit.n = splats_.normals[k];
    hit.footprint = splats_.radii[k];
    return true;
  }

  bool own_any_hit(const Ray& ray, OpCounters& counters) const override {
    counters.add(kEmbreeRays);
    return embree_->occluded(ray);
  }

 private:
  static inline const Counter kEmbreeRays{
      "embree_rays", "rays traced by Embree (its internal work is not counted)"};
  EmbreeDiscParams params_;
  SplatSet splats_;
  bool morton_ = false;
  std::vector<uint32_t> item_of_point_;
  std::unique_ptr<EmbreeScene> embree_;
};

}  // namespace

void register_embree_oriented_disc(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "embree_oriented_disc",
      .paper = "Embree 3 (Wald et al. 2014), RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT",
      .thesis_ref = "-",
      .description = "industrial reference: Embree's oriented discs (radius and normal per point) "
                     "in Embree's BVH",
      .structure = "embree_bvh",
      .needs = {"point normals", "point radii"},
      .params = embree_disc_params().specs(),
      .claims = {},
      .create = create_from<EmbreeOrientedDisc>(embree_disc_params(), "embree_oriented_disc"),
      .own_structure = "embree_bvh",
      .family = LeafFamily::kDisc,
      // The same flat discs as reference_splat: the torus's normal median.
      .accuracy_misses = {{"torus", "normal median"}}});
}

}  // namespace pcrt
