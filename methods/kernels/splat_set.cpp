#include "methods/kernels/splat_set.hpp"

#include <algorithm>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <optional>

#include "core/morton.hpp"
#include "preprocess/point_attributes.hpp"
#include "structures/knn_index.hpp"

namespace pcrt {

const ParamList<NormalParams>& NormalParams::list() {
  using P = NormalParams;
  static const auto l =
      ParamList<P>()
          .add(&P::normal_k, {"normal_k", 16, 3, 256, "neighbours in the PCA normal fit"})
          .add(&P::estimate_normals,
               {"estimate_normals", 0, 0, 1, "1: estimate normals even if the cloud has them"});
  return l;
}

const ParamList<SplatParams>& SplatParams::list() {
  using P = SplatParams;
  static const auto l =
      ParamList<P>()
          .add(&P::normals, NormalParams::list())
          .add(&P::radius_k, {"radius_k", 8, 1, 256,
                              "splat radius = radius_scale * distance to the radius_k-th "
                              "neighbour"})
          .add(&P::radius_scale, {"radius_scale", 1.0, 0.01, 100,
                                  "factor on the neighbour distance for the splat radius"})
          .add(&P::estimate_radii,
               {"estimate_radii", 0, 0, 1, "1: estimate radii even if the cloud has them"});
  return l;
}

namespace {

// Hands freed heap memory back to the system. glibc keeps arrays below its (dynamic, up to 32 MiB)
// mmap threshold in the heap, where a freed one still counts as resident until reused; measured
// at 3x10^6 points, the freed box extents stayed resident without this.
void return_freed_memory() {
#ifdef __GLIBC__
  malloc_trim(0);
#endif
}

// Whether morton_order(positions) is the identity (a cloud sorted at load): consecutive points in
// its order (key, then x, y, z; the index breaks the remaining ties). O(N), no allocation.
bool in_morton_order(std::span<const Vec3> positions) {
  Aabb b;
  for (const Vec3& p : positions) b.extend(p);
  auto before = [&](const Vec3& p, uint64_t kp, const Vec3& q, uint64_t kq) {
    if (kp != kq) return kp < kq;
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    return p.z() < q.z();
  };
  uint64_t prev = 0;
  for (size_t i = 0; i < positions.size(); ++i) {
    const uint64_t key = morton_key(positions[i], b);
    if (i > 0 && before(positions[i], key, positions[i - 1], prev)) return false;
    prev = key;
  }
  return true;
}

template <class T>
std::vector<T> gathered(std::span<const T> from, std::span<const uint32_t> order) {
  std::vector<T> out(order.size());
  for (size_t k = 0; k < order.size(); ++k) out[k] = from[order[k]];
  return out;
}

// Item order = source order when the centres are already in Morton order (no copies: the spans
// stay the caller's, or the set's own arrays moved in); otherwise the Morton-ordered copies.
void lay_out(SplatSet& s, std::span<const Vec3> centres, std::span<const Vec3> normals,
             std::span<const float> radii) {
  if (!in_morton_order(centres)) {
    s.point = morton_order(centres);
    s.own_centres = gathered(centres, std::span<const uint32_t>(s.point));
    s.own_normals = gathered(normals, std::span<const uint32_t>(s.point));
    s.own_radii = gathered(radii, std::span<const uint32_t>(s.point));
    centres = s.own_centres, normals = s.own_normals, radii = s.own_radii;
  }
  s.centres = centres, s.normals = normals, s.radii = radii;
}

}  // namespace

SplatSet prepare_splats(const PointCloud& cloud, const SplatParams& params, PrepareContext& ctx,
                        float fixed_radius) {
  const bool need_normals = !cloud.has_normals() || params.normals.estimate_normals;
  const bool need_radii = fixed_radius <= 0 && (!cloud.has_radii() || params.estimate_radii);
  std::optional<KnnIndex> knn;
  if (need_normals || need_radii) {
    ScopedTimer t(ctx.timings, "prepare/knn_build");
    knn.emplace(cloud.positions);
  }
  SplatSet s;
  if (need_normals) {
    ScopedTimer t(ctx.timings, "prepare/normals");
    s.own_normals = estimate_normals(cloud.positions, *knn, params.normals.normal_k, ctx.counters);
  }
  if (need_radii) {
    ScopedTimer t(ctx.timings, "prepare/radii");
    s.own_radii =
        estimate_radii(cloud.positions, *knn, params.radius_k, params.radius_scale, ctx.counters);
  }
  knn.reset();  // build-only: freed before the layout's own peak
  if (fixed_radius > 0) s.own_radii.assign(cloud.size(), fixed_radius);
  const std::span<const Vec3> n_src = need_normals ? s.own_normals : cloud.normals;
  const std::span<const float> r_src = need_radii || fixed_radius > 0 ? s.own_radii : cloud.radii;

  ScopedTimer t(ctx.timings, "prepare/splat_layout");
  // (An unsorted cloud's estimated normals and radii are replaced by their ordered copies: each
  // copy is made from the old array before that is freed.)
  lay_out(s, cloud.positions, n_src, r_src);
  s.prim = s.point;       // the cloud's own indices (empty: the identity)
  return_freed_memory();  // the k-NN index's, before the structure build
  return s;
}

SplatSet make_splat_set(std::span<const Vec3> centres, std::span<const Vec3> normals,
                        std::span<const float> radii, std::span<const uint32_t> prim) {
  SplatSet s;
  s.own_centres.assign(centres.begin(), centres.end());
  s.own_normals.assign(normals.begin(), normals.end());
  s.own_radii.assign(radii.begin(), radii.end());
  lay_out(s, s.own_centres, s.own_normals, s.own_radii);
  s.prim.resize(s.size());
  for (uint32_t k = 0; k < s.size(); ++k) s.prim[k] = prim[s.point_of(k)];
  return s;
}

PointAttributes splat_attributes_by_point(const SplatSet& s) {
  PointAttributes a;
  if (s.point.empty()) {
    a.normals = s.normals, a.radii = s.radii;
    return a;
  }
  a.own_normals.resize(s.size());
  a.own_radii.resize(s.size());
  for (uint32_t k = 0; k < s.size(); ++k) {
    a.own_normals[s.point_of(k)] = s.normals[k];
    a.own_radii[s.point_of(k)] = s.radii[k];
  }
  a.normals = a.own_normals, a.radii = a.own_radii;
  return a;
}

void SplatSet::pack() {
  packed.resize(size());
  for (uint32_t k = 0; k < size(); ++k) packed[k] = splat(k);
}

void SplatSet::release_item_data() {
  centres = {}, normals = {}, radii = {};
  std::vector<uint32_t>().swap(point);
  std::vector<Vec3>().swap(own_centres);
  std::vector<Vec3>().swap(own_normals);
  std::vector<float>().swap(own_radii);
  return_freed_memory();
}

size_t SplatSet::memory_bytes() const {
  return point.capacity() * sizeof(uint32_t) + prim.capacity() * sizeof(uint32_t) +
         packed.capacity() * sizeof(PackedSplat) +
         (own_centres.capacity() + own_normals.capacity()) * sizeof(Vec3) +
         own_radii.capacity() * sizeof(float);
}

float prepare_spacing(const PointCloud& cloud, PrepareContext& ctx) {
  ScopedTimer t(ctx.timings, "prepare/spacing");
  return std::max(float(mean_spacing(cloud.positions, ctx.counters)), 1e-30f);
}

}  // namespace pcrt
