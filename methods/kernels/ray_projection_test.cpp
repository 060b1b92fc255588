#include "methods/kernels/ray_projection.hpp"

#include <bit>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <vector>

#include "core/rng.hpp"

using namespace pcrt;

namespace {

Vec3 random_unit(Rng& rng) {
  return Vec3(rng.uniform() * 2 - 1, rng.uniform() * 2 - 1, rng.uniform() * 2 - 1).normalized();
}

// Points on the unit sphere with their normals (a surface, as the methods see it), radius r.
std::vector<PackedSplat> sphere_points(size_t n, float r, Rng& rng) {
  std::vector<PackedSplat> s(n);
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3 c = random_unit(rng);
    s[i] = PackedSplat{c, r, c, i};
  }
  return s;
}

// A ray from outside the unit sphere towards a random point near it.
Ray ray_at_sphere(Rng& rng) {
  const Vec3 o = 3.0f * random_unit(rng);
  return Ray{o, (0.9f * random_unit(rng) - o).normalized()};
}

// The exact test the methods' weights share: the crossing lies within the radius (weight 1).
float rim_weight(const Ray& ray, const PackedSplat& p, float t, const Vec3& /*lateral*/) {
  return (ray.at(t) - p.c).squaredNorm() < p.r * p.r ? 1.0f : 0.0f;
}

}  // namespace

TEST_CASE("projection lanes read PackedSplat records field by field", "[kernels]") {
  const PackedSplat p{Vec3(1, 2, 3), 4, Vec3(5, 6, 7), 8};
  float f[kRecordFloats];
  std::memcpy(f, &p, sizeof(f));
  REQUIRE((f[kCx] == 1 && f[kCy] == 2 && f[kCz] == 3 && f[kR] == 4));
  REQUIRE((f[kNx] == 5 && f[kNy] == 6 && f[kNz] == 7));
}

TEST_CASE("projection lanes sum num and den as the exact projection does", "[kernels]") {
  // Eigen's 3-vector dot is x + (y + z); summed (x + y) + z, a third of these would differ.
  Rng rng(3);
  for (int i = 0; i < 10000; ++i) {
    const PackedSplat p{Vec3(rng.uniform() * 4 - 2, rng.uniform() * 4 - 2, rng.uniform() * 4 - 2),
                        1, random_unit(rng), 0};
    const Ray ray{Vec3(rng.uniform() * 6 - 3, rng.uniform(), rng.uniform()), random_unit(rng)};
    const ProjectionQuery q = projection_query(ray);
    const Vec3 v = p.c - ray.o;
    Lane1 num, den;
    plane_crossing<Lane1>(q, Lane1(v.x()), Lane1(v.y()), Lane1(v.z()), Lane1(p.n.x()),
                          Lane1(p.n.y()), Lane1(p.n.z()), num, den);
    REQUIRE(std::bit_cast<uint32_t>(num.v) == std::bit_cast<uint32_t>(p.n.dot(v)));
    REQUIRE(std::bit_cast<uint32_t>(den.v) == std::bit_cast<uint32_t>(p.n.dot(ray.d)));
  }
}

TEST_CASE("projection lanes: the widest kernel keeps exactly the scalar kernel's points",
          "[kernels]") {
  Rng rng(11);
  const auto points = sphere_points(2000, 0.3f, rng);
  const float* records = reinterpret_cast<const float*>(points.data());
  const ProjectionKernel best = best_projection_kernel();
  size_t candidates = 0;
  for (int r = 0; r < 3000; ++r) {
    const ProjectionQuery q = projection_query(ray_at_sphere(rng));
    // Leaves of every length up to 64, items in any order, repeated or not.
    const uint32_t count = 1 + rng.below(64);
    std::vector<uint32_t> items(count);
    for (uint32_t& k : items) k = rng.below(uint32_t(points.size()));
    uint64_t wide = 0, narrow = 0;
    best(records, items.data(), count, q, &wide);
    projection_candidates<Lane1>(records, items.data(), count, q, &narrow);
    REQUIRE(wide == narrow);
    REQUIRE((count == 64 || (wide >> count) == 0));
    candidates += size_t(std::popcount(wide));
  }
  INFO("lanes: " << disc_lanes_name());
  REQUIRE(candidates > 1000);  // the rays do meet points
}

TEST_CASE("the projection prefilter keeps every point the exact projection accepts", "[kernels]") {
  // Rays aimed at points 0.9 to 1.0 radii from the centre in the tangent plane, where the lanes'
  // radius test and the exact one round apart; half of them grazing the plane (n.d down to
  // 1e-6), where t = num / den magnifies any difference in num. Fails with r^2 unwidened, or
  // with num summed in another order than the exact projection's.
  Rng rng(29);
  size_t kept = 0, grazing = 0;
  for (int i = 0; i < 40000; ++i) {
    const Vec3 c = random_unit(rng), n = random_unit(rng);
    const PackedSplat p{c, 0.005f + 0.05f * rng.uniform(), n, 0};
    Vec3 u, v;
    orthonormal_basis(n, u, v);
    const float a = 6.2831853f * rng.uniform();
    const Vec3 side = std::cos(a) * u + std::sin(a) * v;
    const Vec3 target = c + (0.9f + 0.1f * rng.uniform()) * p.r * side;
    const bool graze = i % 2 == 0;
    const float tilt = graze ? std::pow(10.0f, -6 + 4 * rng.uniform()) : rng.uniform();
    const Vec3 along = std::cos(2 * a) * u + std::sin(2 * a) * v;
    const Vec3 d = (along + tilt * (rng.uniform() < 0.5f ? n : Vec3(-n))).normalized();
    const Ray ray{target - (0.5f + 4.5f * rng.uniform()) * d, d};
    float t = 0, w = 0;
    if (!project_point(ray, p, rim_weight, t, w)) continue;
    ++kept, grazing += graze;
    uint64_t bit = 0;
    const uint32_t item = 0;
    projection_candidates<Lane1>(reinterpret_cast<const float*>(&p), &item, 1,
                                 projection_query(ray), &bit);
    REQUIRE(bit == 1);
  }
  REQUIRE(kept > 20000);
  REQUIRE(grazing > 5000);
}

namespace {

struct BlendResult {
  bool found;
  uint32_t t_bits, prim, nx, ny, nz;
  uint64_t tests, candidates;
  bool operator==(const BlendResult&) const = default;
};

BlendResult result_of(bool found, const Hit& h, const OpCounters& c) {
  return {found,
          std::bit_cast<uint32_t>(h.t),
          h.prim,
          std::bit_cast<uint32_t>(h.n.x()),
          std::bit_cast<uint32_t>(h.n.y()),
          std::bit_cast<uint32_t>(h.n.z()),
          c.get(kProjectionTests),
          c.get(kProjectionCandidates)};
}

// The blend as it was before the lanes: every item projected exactly, twice per group tried.
template <typename Weight>
BlendResult scalar_blend(const Ray& ray, const LeafVisit& leaf,
                         const std::vector<PackedSplat>& points, const ProjectionSettings& s,
                         Weight&& weight) {
  auto every_item = [&](auto&& g) {
    for (uint32_t k : leaf.items) {
      float t = 0, w = 0;
      if (project_point(ray, points[k], weight, t, w)) g(k, points[k], t, w);
    }
  };
  auto own_normal = [](uint32_t, const PackedSplat& p, const Vec3&) { return p.n; };
  Hit hit;
  OpCounters counters;
  const bool found = blend_groups(ray, leaf, every_item, s, own_normal, hit, counters);
  return result_of(found, hit, counters);
}

template <typename Weight>
BlendResult lanes_blend(const Ray& ray, const LeafVisit& leaf,
                        const std::vector<PackedSplat>& points, ProjectionKernel kernel,
                        const ProjectionSettings& s, Weight&& weight) {
  Hit hit;
  OpCounters counters;
  const bool found = blend_projected_points(ray, leaf, points, kernel, s, weight, hit, counters);
  return result_of(found, hit, counters);
}

}  // namespace

TEST_CASE("the projection blend over the lanes gives the scalar blend's hits and counts",
          "[kernels]") {
  // A noisy sphere (normals perturbed, so that tangent planes cross the ray early and the blend
  // tries several groups), leaves of 1 to 300 items: past 64 kept points a leaf is blended
  // without the cache. A cylinder (Schaufler and Jensen) and a Gaussian cone-like weight (Wand
  // and Strasser) with a coverage threshold.
  Rng rng(41);
  const float d = 0.08f;
  auto points = sphere_points(4000, d, rng);
  for (PackedSplat& p : points) p.n = (p.n + 0.3f * random_unit(rng)).normalized();
  auto cylinder = [&](const Ray& r, const PackedSplat& p, float t, const Vec3& lateral) {
    const float dist2 = lateral.squaredNorm();
    if (dist2 >= d * d || (r.at(t) - p.c).squaredNorm() >= d * d) return 0.0f;
    return 1.0f - std::sqrt(dist2) / d;
  };
  auto gaussian = [&](const Ray& r, const PackedSplat& p, float t, const Vec3& lateral) {
    const float sigma = d / 3, q = lateral.squaredNorm() / (sigma * sigma);
    if (q >= 9 || (r.at(t) - p.c).squaredNorm() >= d * d) return 0.0f;
    return std::exp(-0.5f * q);
  };
  const ProjectionSettings linear{d, 0.0f, d, d}, covered{0.5f * d, 2.0f, d, d};
  size_t found = 0, multi_group = 0, uncached = 0;
  for (int r = 0; r < 3000; ++r) {
    Ray ray = ray_at_sphere(rng);
    std::vector<uint32_t> items(1 + rng.below(300));
    for (uint32_t& k : items) k = rng.below(uint32_t(points.size()));
    if (r % 10 == 0) {
      // Many copies of a point the ray is aimed at: leaves that keep more than the cache holds.
      const uint32_t k0 = rng.below(uint32_t(points.size()));
      ray = Ray{3.0f * points[k0].c, (points[k0].c - 3.0f * points[k0].c).normalized()};
      for (uint32_t& k : items) k = rng.below(4) == 0 ? k : k0;
    }
    const LeafVisit leaf{items, 0.0f, kInfinity};
    for (const ProjectionKernel kernel :
         {best_projection_kernel(), &projection_candidates<Lane1>}) {
      const BlendResult a = scalar_blend(ray, leaf, points, linear, cylinder);
      REQUIRE(lanes_blend(ray, leaf, points, kernel, linear, cylinder) == a);
      const BlendResult b = scalar_blend(ray, leaf, points, covered, gaussian);
      REQUIRE(lanes_blend(ray, leaf, points, kernel, covered, gaussian) == b);
      found += a.found + b.found;
      multi_group += b.tests > 2 * items.size();
      uncached += a.candidates > ProjectedPoints::kCapacity;
    }
  }
  REQUIRE(found > 500);
  REQUIRE(multi_group > 50);
  REQUIRE(uncached > 50);
}
