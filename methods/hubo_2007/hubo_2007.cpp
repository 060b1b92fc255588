// hubo_2007: Hubo, Mertens, Haber and Bekaert, "Self-similarity-based compression of point
// clouds, with application to ray tracing" (Symposium on Point-Based Graphics 2007), thesis [29]:
// the cloud is cut into small patches (octree cells of at most a few points); each patch is a
// Gaussian-weighted implicit surface over its own points, intersected with Algorithm 6 (Newton);
// the hits of the patches a ray meets in a leaf are blended by distance to the patch centres.
// With `compressed` 1 the patches are stored as instances of clustered representatives
// (self-similarity, patch_codebook.hpp) and decoded patch by patch as rays reach them.
#include <algorithm>
#include <numeric>
#include <vector>

#include "methods/hubo_2007/patch_codebook.hpp"
#include "methods/kernels/ball_runs.hpp"
#include "methods/kernels/implicit_newton.hpp"
#include "methods/kernels/leaf_implicit.hpp"
#include "methods/kernels/octree_partition.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"
#include "preprocess/point_attributes.hpp"

namespace pcrt {
namespace {

inline const Counter kPatches{"implicit_patches", "implicit patches precomputed"};
inline const Counter kPatchRuns{"patch_runs", "patches a ray was intersected with"};

struct Patch {
  uint32_t begin, end;  // its points in points_
  Vec3 centre, normal;
  float spread;  // largest distance of a point from the centre
};

struct Hubo2007Params {
  NormalParams normals;
  size_t patch_points = 32;
  GaussianParams gaussian;
  IterationParams iteration;
  float front_depth = 1;  // in h
  bool compressed = false;
  size_t codebook = 256;
};
const ParamList<Hubo2007Params>& hubo_2007_params() {
  using P = Hubo2007Params;
  static const auto l =
      ParamList<P>()
          .add(&P::normals, NormalParams::list())
          .add(&P::patch_points, {"patch_points", 32, 1, 4096, "most points in one patch"})
          .add(&P::gaussian, GaussianParams::list())
          .add(&P::iteration, IterationParams::list(0.001, 10, "h (|f|)", 10))
          .add(&P::front_depth, {"front_depth", 1.0, 0, 100,
                                 "blend the patch hits within this many h of the front-most"})
          .add(&P::compressed, {"compressed", 0, 0, 1,
                                "1: self-similarity compression (patches as instances of "
                                "clustered representatives)"})
          .add(&P::codebook,
               {"codebook", 256, 1, 65535, "compressed: representative patches (k-means)"});
  return l;
}

class Hubo2007 final : public Method {
 public:
  explicit Hubo2007(const Hubo2007Params& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    const float h = prepare_spacing(cloud, ctx);
    sigma_ = params_.gaussian.sigma * h;
    reach_ = sigma_ * params_.gaussian.cutoff;
    newton_ = newton_settings(params_.iteration, h);
    depth_ = params_.front_depth * h;
    SplatSet pts = prepare_splats(cloud, SplatParams{params_.normals}, ctx, reach_);
    pts.pack();
    ScopedTimer t(ctx.timings, "prepare/patches");
    std::vector<uint32_t> order(pts.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    const size_t max_points = params_.patch_points;
    octree_partition(
        pts.centres, std::span<uint32_t>(order),
        [&](const uint32_t* b, const uint32_t* e, int depth) {
          return size_t(e - b) <= max_points || depth >= 20;
        },
        [&](const uint32_t* b, const uint32_t* e) { add_patch(pts, b, e); }, ctx.counters);
    ctx.counters.add(kPatches, patches_.size());
    for (const Patch& p : patches_) centres_.push_back(p.centre);
    if (params_.compressed) compress(ctx);
    for (const Patch& p : patches_)
      radii_.push_back(p.spread + reach_);  // a patch's implicit surface reaches this far
    if (compressed_)
      ctx.counters.add(kCodebookBytes, codebook_.memory_bytes() + patches_.size() * sizeof(Patch) +
                                           centres_.size() * sizeof(Vec3) +
                                           radii_.size() * sizeof(float));
  }
  [[nodiscard]] ItemSet items() const override { return {centres_, radii_, {}}; }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    const GaussianWeight theta(sigma_, params_.gaussian.cutoff);
    // Pass 1: each patch's own hit; pass 2 blends those within depth_ of the front-most.
    float front = kInfinity;
    // (t, normal, weight) per patch hit; per-thread storage, so no allocation once warm.
    thread_local std::vector<std::pair<float, Vec3>> hits;
    thread_local std::vector<float> weights;
    hits.clear();
    weights.clear();
    thread_local std::vector<PackedSplat> decoded;
    thread_local std::vector<uint32_t> decoded_items;
    for (uint32_t k : leaf.items) {
      const Patch& p = patches_[k];
      float t0 = 0, t1 = 0;
      if (!ball_chord(ray, p.centre, radii_[k], hit.t, t0, t1)) continue;
      counters.add(kPatchRuns);
      std::span<const uint32_t> own(patch_items_.data() + p.begin, p.end - p.begin);
      std::span<const PackedSplat> pts = points_;
      if (compressed_) {  // random access: this patch only, from its instance and representative
        decoded.clear();
        codebook_.decode(k, p.centre, decoded, counters);
        decoded_items.resize(decoded.size());
        std::iota(decoded_items.begin(), decoded_items.end(), 0u);
        own = decoded_items, pts = decoded;
      }
      const float start = patch_start(ray, p, t0, t1);
      Vec3 n = Vec3::Zero();
      const float t = newton_on_weighted_plane(
          ray, start, t0, t1,
          [&](const Vec3& x) { return weighted_plane(x, own, pts, theta, counters); }, newton_, n,
          counters);
      if (t == kInfinity) continue;
      const float d2 = (ray.at(t) - p.centre).squaredNorm();
      const float spread = std::max(p.spread, sigma_);
      hits.emplace_back(t, n);
      weights.push_back(std::exp(-d2 / (2 * spread * spread)));  // nearer the centre: trusted
      front = std::min(front, t);
    }
    const size_t m = hits.size();
    if (m == 0) return false;
    float wsum = 0, tsum = 0;
    Vec3 nsum = Vec3::Zero();
    for (size_t i = 0; i < m; ++i) {
      if (hits[i].first > front + depth_) continue;
      const Vec3 n =
          hits[i].second.dot(hits[0].second) < 0 ? Vec3(-hits[i].second) : hits[i].second;
      wsum += weights[i], tsum += weights[i] * hits[i].first, nsum += weights[i] * n;
    }
    const float t = wsum > 0 ? tsum / wsum : front;
    const uint32_t prim = nearest_point(ray.at(t), leaf.items);
    if (t > leaf.t_exit || !closer(t, prim, hit)) return false;
    // The footprint covers the blend: the patch surfaces averaged lie up to depth_ apart, so a ray
    // leaving the hit (lifted by half the footprint) must clear depth_ beyond the Gaussian's
    // rounding, or it meets a neighbouring patch's surface (dark streaks on sparse scans).
    record_hit(ray, t, prim, nsum.norm() > 0 ? Vec3(nsum.normalized()) : hits[0].second,
               sigma_ + 2 * depth_, hit);
    return true;
  }

 private:
  // Newton's start: where the ray crosses the patch's mean plane, if that lies among the
  // patch's points; else (a plane tilted toward the ray, crossed at the chord's end, where no
  // point's weight reaches and the search would end at once) the ray's nearest approach to the
  // patch centre.
  static float patch_start(const Ray& ray, const Patch& p, float t0, float t1) {
    const float along = std::clamp((p.centre - ray.o).dot(ray.d), t0, t1);
    const float denom = p.normal.dot(ray.d);
    if (!(std::abs(denom) > 1e-6f)) return along;
    const float crossing = std::clamp(p.normal.dot(p.centre - ray.o) / denom, t0, t1);
    return (ray.at(crossing) - p.centre).norm() <= p.spread ? crossing : along;
  }

  void add_patch(const SplatSet& pts, const uint32_t* b, const uint32_t* e) {
    Patch p{uint32_t(points_.size()), 0, Vec3::Zero(), Vec3::Zero(), 0};
    for (const uint32_t* i = b; i != e; ++i)
      p.centre += pts.centres[*i], p.normal += pts.normals[*i];
    p.centre /= float(e - b);
    p.normal = p.normal.norm() > 0 ? Vec3(p.normal.normalized()) : pts.normals[*b];
    for (const uint32_t* i = b; i != e; ++i) {
      p.spread = std::max(p.spread, (pts.centres[*i] - p.centre).norm());
      patch_items_.push_back(uint32_t(points_.size()));
      points_.push_back(pts.packed[*i]);
    }
    p.end = uint32_t(points_.size());
    patches_.push_back(p);
  }

  // Replaces the patches' points by instances of clustered representatives (then freed); a
  // patch's spread, normal and reach become its decoded points'.
  void compress(PrepareContext& ctx) {
    ScopedTimer t(ctx.timings, "prepare/self_similarity");
    std::vector<PatchInput> in;
    in.reserve(patches_.size());
    for (const Patch& p : patches_) in.push_back({p.begin, p.end, p.centre, p.normal});
    codebook_.build(points_, in, params_.codebook, 8, ctx.counters);
    std::vector<PackedSplat> decoded;
    OpCounters ignored;  // the decoding for the spheres below is build work, not tracing
    for (uint32_t k = 0; k < patches_.size(); ++k) {
      decoded.clear();
      codebook_.decode(k, patches_[k].centre, decoded, ignored);
      patches_[k].spread = 0;
      for (const PackedSplat& q : decoded)
        patches_[k].spread = std::max(patches_[k].spread, (q.c - patches_[k].centre).norm());
    }
    points_ = {}, patch_items_ = {};
    compressed_ = true;
  }

  uint32_t nearest_point(const Vec3& x, std::span<const uint32_t> items) const {
    if (compressed_) {  // the point nearest the centre of the patch nearest x
      uint32_t best = items[0];
      for (uint32_t k : items)
        if ((centres_[k] - x).squaredNorm() < (centres_[best] - x).squaredNorm()) best = k;
      return codebook_.prim(best);
    }
    uint32_t best = 0;
    float best_d2 = kInfinity;
    for (uint32_t k : items)
      for (uint32_t i = patches_[k].begin; i < patches_[k].end; ++i) {
        const float d2 = (points_[i].c - x).squaredNorm();
        if (d2 < best_d2) best_d2 = d2, best = points_[i].index;
      }
    return best;
  }

  Hubo2007Params params_;
  std::vector<PackedSplat> points_;    // grouped by patch
  std::vector<uint32_t> patch_items_;  // 0..n-1: the index span a patch hands the average
  std::vector<Patch> patches_;
  std::vector<Vec3> centres_;
  std::vector<float> radii_;
  PatchCodebook codebook_;
  bool compressed_ = false;
  float sigma_ = 0, reach_ = 0, depth_ = 0;
  NewtonSettings newton_;
};

}  // namespace

void register_hubo_2007(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "hubo_2007",
      .paper =
          "E. Hubo, T. Mertens, T. Haber and P. Bekaert, Self-similarity-based compression of "
          "point clouds, with application to ray tracing, Symposium on Point-Based Graphics 2007",
      .thesis_ref = "[29]",
      .description = "small patches (octree cells of a few points), each a Gaussian-weighted "
                     "implicit surface intersected by Newton steps (Algorithm 6); patch hits "
                     "blended by distance to the centres",
      .structure = "octree",
      .needs = {"point normals", "implicit patches"},
      .params = hubo_2007_params().specs(),
      .claims = {{"leaf intersection", "O(IK)", {"I", "K"}, "Table 5.5"},
                 {"frame", "O(SMB(log N + IK))", {"S", "M", "B", "N", "I", "K"}, "Table 6.1"}},
      .create = create_from<Hubo2007>(hubo_2007_params(), "hubo_2007"),
      .work = {&kWeightedPointTerms},
      .real_time_claim = "Table 5.1",
      .iterations = {&kNewtonSteps, &kNewtonRuns},
      .own_items = true,
      .cost = {.prepare_ns = 58, .ray_ns = 74},
      .designs = {{.experiment = "leaf_K_hubo_2007",
                   .variable = "K",
                   .param = "patch_points",
                   .values = {4, 8, 16, 32, 64, 128, 256},
                   .N = 20000,
                   .metric = {&kWeightedPointTerms},
                   .per = &kPatchRuns,
                   .x = "set_patch_points"},
                  {.experiment = "leaf_I_newton",
                   .variable = "I",
                   .param = "max_iterations",
                   .values = {1, 2, 3, 4, 6, 8, 12},
                   .metric = {&kNewtonSteps},
                   .per = &kNewtonRuns,
                   .x = "I_run",
                   .fixed = {{"tolerance", 0}},
                   .replicates = 1}}});
}

}  // namespace pcrt
