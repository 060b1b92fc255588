// kashyap_2010_splat: Kashyap, Goradia, Chaudhuri and Chandran, "Real time ray tracing of
// point-based models" (I3D 2010), thesis [34]: a splat octree. The octree is refined until the
// points of each leaf lie within a tolerance of one plane; each leaf's points are then replaced by
// one splat fitted to them (centroid, PCA normal, radius covering them), so the splats are a
// level of detail coarser than the points. Rays blend the splats they hit in a leaf (thesis 5.5.2,
// "Splat intersection"). See README.md.
#include <algorithm>
#include <cmath>

#include "methods/kernels/octree_partition.hpp"
#include "methods/kernels/splat_blend.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"
#include "preprocess/point_attributes.hpp"

namespace pcrt {
namespace {

struct LeafSplats {
  std::vector<Vec3> centres, normals;
  std::vector<float> radii;
  std::vector<uint32_t> prim;
};

class SplatOctreeBuilder {
 public:
  SplatOctreeBuilder(std::span<const Vec3> p, std::span<const Vec3> n, std::span<const float> cover,
                     float tolerance, size_t max_points, float min_cos)
      : p_(p),
        n_(n),
        cover_(cover),
        tolerance_(tolerance),
        max_points_(max_points),
        min_cos_(min_cos) {}

  LeafSplats build(OpCounters& counters) {
    std::vector<uint32_t> idx(p_.size());
    for (uint32_t i = 0; i < idx.size(); ++i) idx[i] = i;
    // Depth 20 and cells of 1-2 points always stop; fit() records the splat when it accepts.
    octree_partition(
        p_, std::span<uint32_t>(idx),
        [&](const uint32_t* b, const uint32_t* e, int depth) {
          return fit(b, e, e - b <= 2 || depth >= 20);
        },
        [](const uint32_t*, const uint32_t*) {}, counters);
    return std::move(out_);
  }

 private:
  // Fits one splat to the points [begin, end); false if they are not flat enough for one.
  bool fit(const uint32_t* begin, const uint32_t* end, bool force) {
    const std::span<const uint32_t> pts(begin, end);
    Vec3 c = Vec3::Zero(), mean_n = Vec3::Zero();
    float mean_cover = 0;
    for (uint32_t i : pts) c += p_[i], mean_n += n_[i], mean_cover += cover_[i];
    c /= float(pts.size());
    mean_cover /= float(pts.size());
    Vec3 n = pts.size() >= 3 ? pca_normal(p_, pts) : mean_n.normalized();
    if (!n.allFinite()) n = n_[pts[0]];
    if (n.dot(mean_n) < 0) n = -n;
    float height = 0, spread = 0, min_cos = 1;
    for (uint32_t i : pts) {
      const Vec3 d = p_[i] - c;
      const float along = n.dot(d);
      height = std::max(height, std::abs(along));
      spread = std::max(spread, (d - along * n).norm());
      min_cos = std::min(min_cos, n.dot(n_[i]));
    }
    if (!force && (pts.size() > max_points_ || height > tolerance_ || min_cos < min_cos_))
      return false;
    uint32_t nearest = pts[0];
    for (uint32_t i : pts)
      if ((p_[i] - c).squaredNorm() < (p_[nearest] - c).squaredNorm()) nearest = i;
    out_.centres.push_back(c);
    out_.normals.push_back(n);
    // Covers the farthest point's own disc, so neighbouring leaves' splats overlap.
    out_.radii.push_back(spread + mean_cover);
    out_.prim.push_back(nearest);
    return true;
  }

  std::span<const Vec3> p_, n_;
  std::span<const float> cover_;
  float tolerance_;
  size_t max_points_;
  float min_cos_;
  LeafSplats out_;
};

struct Kashyap2010SplatParams {
  SplatParams splat;
  float error_tolerance = 0.05f;  // in h
  size_t max_leaf_points = 64;
  double max_normal_angle = 25;  // degrees
  float front_depth = 0.5f;
  DiscBlockParams blocks;
};
const ParamList<Kashyap2010SplatParams>& kashyap_2010_splat_params() {
  using P = Kashyap2010SplatParams;
  static const auto l =
      ParamList<P>()
          .add(&P::splat, SplatParams::list())
          .add(&P::error_tolerance,
               {"error_tolerance", 0.05, 0.001, 10,
                "largest distance of a leaf's points from its splat plane, in mean spacings h"})
          .add(&P::max_leaf_points,
               {"max_leaf_points", 64, 1, 100000, "most points one splat may replace"})
          .add(&P::max_normal_angle,
               {"max_normal_angle", 25, 1, 180,
                "largest angle between a leaf's splat normal and its points' normals (deg)"})
          .add(&P::front_depth, front_depth_spec())
          .add(&P::blocks, DiscBlockParams::list());
  return l;
}

class Kashyap2010Splat final : public Method {
 public:
  explicit Kashyap2010Splat(const Kashyap2010SplatParams& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    const SplatSet base = prepare_splats(cloud, params_.splat, ctx);
    const PointAttributes by_point = splat_attributes_by_point(base);
    const std::span<const Vec3> normals = by_point.normals;
    const std::span<const float> cover = by_point.radii;
    const float h = prepare_spacing(cloud, ctx);
    ScopedTimer t(ctx.timings, "prepare/splat_octree");
    SplatOctreeBuilder builder(cloud.positions, normals, cover, params_.error_tolerance * h,
                               params_.max_leaf_points,
                               float(std::cos(params_.max_normal_angle * M_PI / 180)));
    const LeafSplats leaves = builder.build(ctx.counters);
    ctx.counters.add(kSplatsGenerated, leaves.prim.size());
    splats_ = make_splat_set(leaves.centres, leaves.normals, leaves.radii, leaves.prim);
    settings_ = splat_blend_settings(splats_.radii, params_.front_depth);
  }
  [[nodiscard]] ItemSet items() const override { return blend_items(splats_, settings_); }
  void bind_leaf_references(std::span<const uint32_t> refs) override {
    bind_splat_blocks(blocks_, splats_, refs, params_.blocks);
  }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    return blend_splat_hits(ray, leaf, blocks_, splats_, settings_, hit, counters);
  }

 private:
  Kashyap2010SplatParams params_;
  SplatSet splats_;
  SplatLeafBlocks blocks_;
  SplatBlendSettings settings_;
};

}  // namespace

void register_kashyap_2010_splat(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "kashyap_2010_splat",
      .paper = "S. Kashyap, R. Goradia, P. Chaudhuri and S. Chandran, Real time ray tracing of "
               "point-based models, I3D 2010",
      .thesis_ref = "[34]",
      .description =
          "splat octree: cells refined until their points fit one plane, one fitted splat per "
          "leaf; the splats hit in a leaf are blended by distance from their centres",
      .structure = "octree",
      .needs = {"point normals", "splat radii", "splat octree"},
      .params = kashyap_2010_splat_params().specs(),
      .claims = {{"leaf intersection", "O(K)", {"K"}, "Table 5.5"},
                 {"frame", "O(SMB(log N + K))", {"S", "M", "B", "N", "K"}, "Table 6.1"}},
      .create = create_from<Kashyap2010Splat>(kashyap_2010_splat_params(), "kashyap_2010_splat"),
      .work = {&kProjectionTests, &kSplatTests},
      .family = LeafFamily::kSplatBlend,
      .real_time_claim = "Table 5.1",
      .own_items = true,
      .cost = {.prepare_ns = 157, .ray_ns = 38},
      .designs = {{.experiment = "leaf_K_octree",
                   .variable = "K",
                   .param = "leaf_size",
                   .values = {2, 4, 8, 16, 32, 64, 128},
                   .N = 20000,
                   .metric = {&kSplatTests},
                   .per = &kLeavesVisited}}});
}

}  // namespace pcrt
