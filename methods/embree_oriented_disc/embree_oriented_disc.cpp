// embree_oriented_disc: the same splats (centre, normal, radius per point) as Embree 3's
// RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT in Embree's own BVH. Not a surveyed method: the industrial
// splat intersector that the surveyed methods' speed and accuracy are compared with.
#include <memory>

#include "core/error.hpp"
#include "methods/embree_oriented_disc/embree_discs.hpp"
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
    morton_ = params_.morton_order;
    embree_ = build_embree_discs(splats_, morton_, item_of_point_, "embree_oriented_disc");
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
