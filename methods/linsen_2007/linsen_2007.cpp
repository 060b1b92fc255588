// linsen_2007: Linsen, Mueller and Rosenthal, "Splat-based ray tracing of point clouds" (Journal
// of WSCG 2007), thesis [41]: splats sized by the local curvature (large where the surface is
// flat, small where it bends), fewer splats than points, and a linear normal field on each splat
// for smooth shading; weighted splat intersection in an octree. See README.md.
#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

#include "methods/kernels/splat_blend.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"
#include "preprocess/point_attributes.hpp"

namespace pcrt {
namespace {

// A linear normal field n(x) = n_i + M (x - c_i) fitted to the neighbours' normals, and the
// curvature it implies (the largest principal curvature of its shape operator).
struct NormalField {
  Eigen::Matrix3f m = Eigen::Matrix3f::Zero();
  float curvature = 0;
};

NormalField fit_normal_field(std::span<const Vec3> positions, std::span<const Vec3> normals,
                             uint32_t i, std::span<const uint32_t> nbrs) {
  Vec3 u, v;
  orthonormal_basis(normals[i], u, v);
  // The offsets in a unit of the neighbourhood's size: a's determinant is a fourth power of a
  // length, which overflows float at 10^10 and underflows at 10^-10.
  float reach = 0;
  for (uint32_t j : nbrs)
    reach = std::max(reach, (positions[j] - positions[i]).cwiseAbs().maxCoeff());
  const float inv_unit = 1.0f / length_unit(reach);
  Eigen::Matrix2f a = Eigen::Matrix2f::Zero();
  Eigen::Matrix<float, 3, 2> b = Eigen::Matrix<float, 3, 2>::Zero();
  for (uint32_t j : nbrs) {
    const Vec3 d = (positions[j] - positions[i]) * inv_unit;
    const Eigen::Vector2f q(d.dot(u), d.dot(v));
    const Vec3 nj = normals[j].dot(normals[i]) < 0 ? Vec3(-normals[j]) : normals[j];
    a += q * q.transpose();
    b += (nj - normals[i]) * q.transpose();
  }
  NormalField f;
  if (std::abs(a.determinant()) <= 1e-12f * a.squaredNorm()) return f;  // collinear neighbours
  const Eigen::Matrix<float, 3, 2> g = b * a.inverse() * inv_unit;      // dn per unit (u, v)
  Eigen::Matrix<float, 3, 2> uv;
  uv << u, v;
  f.m = g * uv.transpose();
  const Eigen::Matrix2f shape = uv.transpose() * g;
  const Eigen::Matrix2f sym = 0.5f * (shape + shape.transpose());
  const Eigen::Vector2f k = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2f>(sym).eigenvalues();
  f.curvature = std::max(std::abs(k[0]), std::abs(k[1]));
  if (!f.m.allFinite() || !std::isfinite(f.curvature)) f = NormalField{};
  return f;
}

inline const Counter kSplatsCutByCover{
    "splats_cut_by_cover",
    "splats whose curvature radius a point it would cover, off the splat's plane by more than the "
    "error tolerance, cut short"};

struct Linsen2007Params {
  SplatParams splat;
  size_t field_k = 16;
  float error_tolerance = 0.1f;  // in h
  float max_radius_scale = 4;
  bool reduce = true;
  float front_depth = 0.5f;
  DiscBlockParams blocks;
};
const ParamList<Linsen2007Params>& linsen_2007_params() {
  using P = Linsen2007Params;
  static const auto l =
      ParamList<P>()
          .add(&P::splat, SplatParams::list())
          .add(&P::field_k, {"field_k", 16, 4, 256, "neighbours in each splat's normal-field fit"})
          .add(&P::error_tolerance,
               {"error_tolerance", 0.1, 0.001, 10,
                "largest departure of a flat splat from the curved surface, in mean spacings "
                "h: sets the radius sqrt(2 eps / curvature)"})
          .add(&P::max_radius_scale,
               {"max_radius_scale", 4, 1, 100,
                "cap on a splat's radius, in multiples of its neighbour-distance radius"})
          .add(&P::reduce, {"reduce", 1, 0, 1, "1: drop the points a larger splat already covers"})
          .add(&P::front_depth, front_depth_spec())
          .add(&P::blocks, DiscBlockParams::list());
  return l;
}

class Linsen2007 final : public Method {
 public:
  explicit Linsen2007(const Linsen2007Params& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    const size_t n = cloud.size();
    const SplatSet base = prepare_splats(cloud, params_.splat, ctx);
    const PointAttributes by_point = splat_attributes_by_point(base);
    const std::span<const Vec3> normals = by_point.normals;
    const std::span<const float> cover = by_point.radii;
    std::optional<KnnIndex> knn;
    {
      ScopedTimer t(ctx.timings, "prepare/knn_build");
      knn.emplace(cloud.positions);
    }
    const float h = float(mean_spacing(cloud.positions, *knn, ctx.counters));
    std::vector<float> radii = curvature_radii(cloud.positions, normals, cover, h, *knn, ctx);
    cut_by_covered_points(cloud.positions, normals, cover, h, *knn, radii, ctx);
    std::vector<uint32_t> kept;
    {
      ScopedTimer t(ctx.timings, "prepare/splat_reduction");
      kept = params_.reduce ? reduce(cloud.positions, normals, radii, cover, *knn, ctx)
                            : all_points(n);
    }
    ctx.counters.add(kSplatsGenerated, kept.size());
    {
      ScopedTimer t(ctx.timings, "prepare/splat_layout");
      std::vector<Vec3> c(kept.size()), nn(kept.size());
      std::vector<float> r(kept.size());
      for (size_t s = 0; s < kept.size(); ++s)
        c[s] = cloud.positions[kept[s]], nn[s] = normals[kept[s]], r[s] = radii[kept[s]];
      splats_ = make_splat_set(c, nn, r, kept);
    }
    // The kept splats' fields fitted again (the same neighbours, so the same matrices) rather
    // than every point's kept from the first pass: 40 B per point (the matrix and
    // its curvature) less at the peak.
    ScopedTimer t(ctx.timings, "prepare/normal_field");
    fields_.resize(splats_.size());
    for_each_knn(
        splats_.size(), [&](size_t k) -> const Vec3& { return cloud.positions[source(kept, k)]; },
        *knn, params_.field_k, ctx.counters,
        [&](size_t k, auto nbrs, auto) {
          fields_[k] = fit_normal_field(cloud.positions, normals, source(kept, k), nbrs).m;
        });
    settings_ = splat_blend_settings(splats_.radii, params_.front_depth);
  }
  [[nodiscard]] ItemSet items() const override { return blend_items(splats_, settings_); }
  void bind_leaf_references(std::span<const uint32_t> refs) override {
    bind_splat_blocks(blocks_, splats_, refs, params_.blocks);
  }

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    auto field = [&](uint32_t k, const PackedSplat& s, const Vec3& x) {
      const Vec3 nx = s.n + fields_[k] * (x - s.c);
      return nx.squaredNorm() > 0 ? Vec3(nx.normalized()) : s.n;
    };
    return blend_splat_hits(ray, leaf, blocks_, splats_, settings_, field, hit, counters);
  }

 private:
  // The cloud point that item k of the splat set was made from.
  [[nodiscard]] uint32_t source(std::span<const uint32_t> kept, size_t k) const {
    return kept[splats_.point_of(uint32_t(k))];
  }

  // Each point's splat radius from the curvature of its normal field: a flat disc of radius r
  // departs from a surface of curvature kappa by kappa r^2 / 2 at its rim, so r = sqrt(2 eps /
  // kappa) keeps that <= eps, clamped to [cover, max_radius_scale cover].
  std::vector<float> curvature_radii(std::span<const Vec3> positions, std::span<const Vec3> normals,
                                     std::span<const float> cover, float h, const KnnIndex& knn,
                                     PrepareContext& ctx) const {
    ScopedTimer t(ctx.timings, "prepare/curvature");
    std::vector<float> radii(positions.size());
    const float eps = params_.error_tolerance * h;
    const float max_scale = params_.max_radius_scale;
    for_each_point_knn(
        positions, knn, params_.field_k, ctx.counters, [&](size_t i, auto nbrs, auto) {
          const float kappa = fit_normal_field(positions, normals, uint32_t(i), nbrs).curvature;
          const float r = kappa > 0 ? std::sqrt(2 * eps / kappa) : kInfinity;
          radii[i] = std::clamp(r, cover[i], max_scale * cover[i]);
        });
    return radii;
  }

  // The curvature at the centre bounds a splat's departure only where the surface keeps that
  // curvature out to the rim; a normal field fitted to field_k neighbours (about 2 h) sees none
  // across a flat patch whose edge bends 4 h away, and the splat then overhangs it (issue 30: 6.8%
  // phantoms on the elk, half of them on open surface). So each radius is also cut at the nearest
  // point it would cover lying further than eps from the splat's plane, as the paper derives a
  // splat from the points it covers; never below the cover radius, which keeps the surface closed.
  void cut_by_covered_points(std::span<const Vec3> positions, std::span<const Vec3> normals,
                             std::span<const float> cover, float h, const KnnIndex& knn,
                             std::vector<float>& radii, PrepareContext& ctx) const {
    ScopedTimer t(ctx.timings, "prepare/cover_check");
    const float eps = params_.error_tolerance * h;
    tbb::combinable<OpCounters> per_thread;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, positions.size(), 256), [&](const auto& r) {
      std::vector<std::pair<uint32_t, float>> found;
      OpCounters& local = per_thread.local();
      for (size_t i = r.begin(); i != r.end(); ++i) {
        if (radii[i] <= cover[i]) continue;
        knn.radius(positions[i], radii[i], found, local);
        for (const auto& [j, d2] : found)  // nearest first
          if (std::abs(normals[i].dot(positions[j] - positions[i])) > eps) {
            radii[i] = std::max(cover[i], std::sqrt(d2));
            local.add(kSplatsCutByCover);
            break;
          }
      }
    });
    per_thread.combine_each([&](const OpCounters& c) { ctx.counters.merge(c); });
  }

  static std::vector<uint32_t> all_points(size_t n) {
    std::vector<uint32_t> all(n);
    std::iota(all.begin(), all.end(), 0u);
    return all;
  }

  // Greedy cover, largest splats first: a point whose own (cover-radius) disc lies inside a kept
  // splat on the same sheet needs no splat of its own.
  std::vector<uint32_t> reduce(std::span<const Vec3> positions, std::span<const Vec3> normals,
                               std::span<const float> radii, std::span<const float> cover,
                               const KnnIndex& knn, PrepareContext& ctx) const {
    std::vector<uint32_t> order = all_points(positions.size());
    std::stable_sort(order.begin(), order.end(),
                     [&](uint32_t a, uint32_t b) { return radii[a] > radii[b]; });
    std::vector<uint8_t> covered(positions.size(), 0);
    std::vector<uint32_t> kept;
    std::vector<std::pair<uint32_t, float>> found;
    for (uint32_t i : order) {
      if (covered[i]) continue;
      kept.push_back(i);
      knn.radius(positions[i], radii[i], found, ctx.counters);
      for (const auto& [j, d2] : found)
        if (std::sqrt(d2) + cover[j] <= radii[i] && normals[i].dot(normals[j]) > 0.9f)
          covered[j] = 1;
    }
    std::sort(kept.begin(), kept.end());
    return kept;
  }

  Linsen2007Params params_;
  SplatSet splats_;
  SplatLeafBlocks blocks_;
  std::vector<Eigen::Matrix3f> fields_;  // item order
  SplatBlendSettings settings_;
};

}  // namespace

void register_linsen_2007(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "linsen_2007",
      .paper = "L. Linsen, K. Mueller and P. Rosenthal, Splat-based ray tracing of point clouds, "
               "Journal of WSCG 15 (2007)",
      .thesis_ref = "[41]",
      .description =
          "splats sized by local curvature and reduced by a greedy cover; a linear normal field "
          "per splat; the splats hit in a leaf are blended by distance from their centres",
      .structure = "octree",
      .needs = {"point normals", "splat radii", "normal field"},
      .params = linsen_2007_params().specs(),
      .claims = {{"leaf intersection", "O(K)", {"K"}, "Table 5.5"},
                 {"frame", "O(SMB(log N + K))", {"S", "M", "B", "N", "K"}, "Table 6.1"}},
      .create = create_from<Linsen2007>(linsen_2007_params(), "linsen_2007"),
      .work = {&kProjectionTests, &kSplatTests},
      .family = LeafFamily::kSplatBlend,
      // Per splat: its normal field, its own centre, normal and radius, and its point index.
      .own_data_bytes_per_point =
          sizeof(Eigen::Matrix3f) + 2 * sizeof(Vec3) + sizeof(float) + sizeof(uint32_t),
      .own_items = true,
      .cost = {.prepare_ns = 345, .ray_ns = 48},
      .designs = {{.experiment = "leaf_K_octree",
                   .variable = "K",
                   .param = "leaf_size",
                   .values = {2, 4, 8, 16, 32, 64, 128},
                   .N = 20000,
                   .metric = {&kSplatTests},
                   .per = &kLeavesVisited}}});
}

}  // namespace pcrt
