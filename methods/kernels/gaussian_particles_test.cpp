// Gaussian particles and 3DGRT's k-buffer march (methods/grt_2024): the proxies bound the
// response they stand for, the maximum response is the maximum, and the march finds exactly the
// surface of blending every response in order, whatever k, proxy or structure; EVER's march
// (methods/ever_2024) finds exactly the surface of integrating every ellipsoid's entry and exit.
#include "methods/kernels/gaussian_particles.hpp"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <tuple>

#include "core/dataset.hpp"
#include "core/rng.hpp"
#include "render/scene.hpp"

namespace pcrt {
namespace {

ParticleSet one_particle(const Vec3& scale, const Vec4& q, float opacity, GaussianProxy proxy,
                         PointCloud& cloud) {
  cloud.positions = {Vec3(0.1f, -0.2f, 0.3f)};
  cloud.normals = {shortest_axis(scale, q)};
  cloud.gaussians.scales = {scale};
  cloud.gaussians.rotations = {q};
  cloud.gaussians.opacities = {opacity};
  OpCounters c;
  Timings t;
  PrepareContext ctx{c, t};
  return prepare_gaussians(cloud, ParticleParams::list().read({}, "test"), proxy, ctx);
}

Ray random_ray(Rng& rng, float spread) {
  Ray r;
  r.o = Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f) * 6.0f;
  const Vec3 aim = Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f) * spread;
  r.d = (aim - r.o).normalized();
  return r;
}

}  // namespace

TEST_CASE("the maximum response along a ray is the maximum", "[gaussians]") {
  PointCloud cloud;
  const Vec4 q = Vec4(0.9f, 0.3f, -0.2f, 0.1f).normalized();
  const ParticleSet g =
      one_particle(Vec3(0.5f, 0.2f, 0.05f), q, 0.8f, GaussianProxy::kEllipsoid, cloud);
  Rng rng(3, 0);
  for (int n = 0; n < 200; ++n) {
    const Ray ray = random_ray(rng, 1.0f);
    const ParticleResponse r = particle_response(g, 0, ray);
    auto response = [&](float t) {
      const Vec3 x = g.to_canonical[0] * (ray.at(t) - g.centres[0]);
      return g.opacities[0] * std::exp(-0.5f * x.squaredNorm());
    };
    REQUIRE(r.alpha == Approx(response(r.t)).margin(1e-6));
    for (float dt : {-1e-2f, 1e-2f}) REQUIRE(response(r.t + dt) <= r.alpha + 1e-6f);
  }
}

TEST_CASE("every proxy holds the cut-off ellipsoid, which holds every counted response",
          "[gaussians]") {
  const Vec4 q = Vec4(0.7f, -0.1f, 0.6f, 0.3f).normalized();
  for (const Vec3& scale : {Vec3(0.5f, 0.2f, 0.05f), Vec3(0.3f, 0.3f, 0.0003f)}) {
    PointCloud a, b, c;
    const ParticleSet ico = one_particle(scale, q, 0.9f, GaussianProxy::kIcosahedron, a);
    const ParticleSet box = one_particle(scale, q, 0.9f, GaussianProxy::kBox, b);
    const ParticleSet ell = one_particle(scale, q, 0.9f, GaussianProxy::kEllipsoid, c);
    Rng rng(5, 0);
    int responses = 0, ico_only = 0;
    for (int n = 0; n < 20000; ++n) {
      const Ray ray = random_ray(rng, 1.5f);
      // Counted: the response's maximum lies on the ray (t >= 0) and reaches min_response.
      const ParticleResponse r = particle_response(ell, 0, ray);
      const bool counted = r.alpha >= ell.min_response && r.t >= ray.tmin;
      const bool in_ell = proxy_hit(ell, GaussianProxy::kEllipsoid, 0, ray);
      const bool in_ico = proxy_hit(ico, GaussianProxy::kIcosahedron, 0, ray);
      if (counted) REQUIRE(in_ell);
      if (in_ell) REQUIRE(r.alpha >= ell.min_response * (1 - 1e-4f));
      if (in_ell) REQUIRE((in_ico && proxy_hit(box, GaussianProxy::kBox, 0, ray)));
      responses += counted;
      ico_only += in_ico && !in_ell;
    }
    REQUIRE(responses > 500);
    REQUIRE(ico_only > 0);  // the icosahedron is a looser fit: wasted tests exist
  }
}

// The surface by definition: every particle's response, sorted by (t, index), blended until the
// accumulated opacity reaches one half.
struct Oracle {
  bool found = false;
  uint32_t prim = kNoPrim;
  float t = 0;
};
Oracle blend_all(const ParticleSet& g, const Ray& ray) {
  std::vector<std::pair<ParticleResponse, uint32_t>> all;
  for (uint32_t i = 0; i < g.size(); ++i) {
    const ParticleResponse r = particle_response(g, i, ray);
    if (r.alpha >= g.min_response && r.t >= ray.tmin && r.t <= ray.tmax) all.push_back({r, i});
  }
  std::sort(all.begin(), all.end(), [](const auto& x, const auto& y) {
    return x.first.t < y.first.t || (x.first.t == y.first.t && x.second < y.second);
  });
  float transmittance = 1;
  for (const auto& [r, i] : all) {
    transmittance *= 1 - r.alpha;
    if (transmittance <= 0.5f) return {true, i, r.t};
  }
  return {};
}

// The marches' test bed: a sphere's default particles and 400 rays crossing it.
struct MarchBed {
  Dataset d = load_dataset("sphere:n=3000,seed=2");
  std::vector<Ray> rays = std::vector<Ray>(400);
  ParticleSet g;
  explicit MarchBed(uint64_t seed) {
    Rng rng(seed, 0);
    for (Ray& r : rays) r = random_ray(rng, 1.2f);
    OpCounters c;
    Timings t;
    PrepareContext ctx{c, t};
    g = prepare_gaussians(d.cloud, ParticleParams::list().read({}, "test"),
                          GaussianProxy::kEllipsoid, ctx);
  }
};

TEST_CASE("the k-buffer march finds the blended surface for every k, proxy and structure",
          "[gaussians][methods]") {
  const MarchBed bed(9);
  const Dataset& d = bed.d;
  const std::vector<Ray>& rays = bed.rays;
  const ParticleSet& g = bed.g;
  std::vector<Oracle> truth;
  for (const Ray& r : rays) truth.push_back(blend_all(g, r));
  REQUIRE(std::count_if(truth.begin(), truth.end(), [](const Oracle& o) { return o.found; }) > 100);
  uint64_t blended_k1 = 0, retraces_k1 = 0;
  for (double proxy : {0.0, 1.0, 2.0})
    for (const char* structure : {"brute_force", "bvh", "kd_tree", "octree"})
      for (double k : {1.0, 3.0, 16.0, 64.0}) {
        OpCounters c;
        Timings t;
        const ParamValues set{{"k", k}, {"proxy", proxy}};
        const PointScene scene(d.cloud, SceneOptions{"grt_2024", structure, set}, c, t);
        OpCounters frame;
        for (size_t i = 0; i < rays.size(); ++i) {
          Hit h;
          const bool found = scene.closest_hit(rays[i], h, frame);
          INFO(structure << " k=" << k << " proxy " << proxy << " ray " << i);
          REQUIRE(found == truth[i].found);
          if (found) REQUIRE((h.prim == truth[i].prim && h.t == truth[i].t));
          OpCounters shadow;
          REQUIRE(scene.any_hit(rays[i], shadow) == found);
        }
        // Blending stops at the surface whatever k: the same responses are blended.
        if (blended_k1 == 0) {
          blended_k1 = frame.get(kParticlesBlended), retraces_k1 = frame.get(kRetraces);
          REQUIRE(retraces_k1 > rays.size());
        }
        REQUIRE(frame.get(kParticlesBlended) == blended_k1);
        if (k == 1.0) REQUIRE(frame.get(kRetraces) == retraces_k1);
        if (k == 64.0) REQUIRE(frame.get(kRetraces) * 8 < retraces_k1);
      }
}

// EVER's surface by definition: every ellipsoid's entry (clamped to the ray's start) and exit,
// sorted, integrated until the optical depth reaches ln 2 (opacity one half).
Oracle integrate_all(const ParticleSet& g, const std::vector<float>& density, const Ray& ray) {
  struct Event {
    float t;
    uint32_t prim;
    bool exit;
  };
  std::vector<Event> all;
  for (uint32_t i = 0; i < g.size(); ++i) {
    float t0 = 0, t1 = 0;
    if (!ellipsoid_chord(g, i, ray, g.reach[i], t0, t1) || t1 < ray.tmin) continue;
    all.push_back({std::max(t0, ray.tmin), i, false});
    all.push_back({t1, i, true});
  }
  std::sort(all.begin(), all.end(), [](const Event& a, const Event& b) {
    return std::tie(a.t, a.prim, a.exit) < std::tie(b.t, b.prim, b.exit);
  });
  const double target = -std::log1p(-0.5);
  OpticalDepth depth;
  depth.t = ray.tmin;
  float t = 0;
  for (const Event& e : all) {
    if (e.t > ray.tmax) break;
    if (depth.advance(e.t, target, ray.d.norm(), t)) return {true, depth.front, t};
    if (e.exit)
      depth.exit(density[e.prim]);
    else
      depth.enter(e.prim, density[e.prim]);
  }
  if (depth.advance(ray.tmax, target, ray.d.norm(), t)) return {true, depth.front, t};
  return {};
}

TEST_CASE("constant-density ellipsoids: a chord through the centre gives the peak opacity",
          "[gaussians]") {
  PointCloud cloud;
  const Vec4 q = Vec4(0.9f, 0.3f, -0.2f, 0.1f).normalized();
  ParticleSet g = one_particle(Vec3(0.5f, 0.2f, 0.05f), q, 0.8f, GaussianProxy::kEllipsoid, cloud);
  const std::vector<float> density = constant_density_ellipsoids(g);
  Ray ray;
  ray.d = rotation_matrix(q).col(2);  // the shortest axis, through the centre
  ray.o = g.centres[0] - 3.0f * ray.d;
  float t0 = 0, t1 = 0;
  REQUIRE(ellipsoid_chord(g, 0, ray, g.reach[0], t0, t1));
  REQUIRE(t1 - t0 == Approx(2 * kHalfMaximumRadius * 0.05f).epsilon(1e-4));
  REQUIRE(1 - std::exp(-density[0] * (t1 - t0)) == Approx(0.8).epsilon(1e-4));
  // The proxy box holds the ellipsoid: its extreme points along each world axis.
  const Mat3 rs = g.to_canonical[0].inverse();
  for (int a = 0; a < 3; ++a)
    REQUIRE(g.half_extents[0][a] == Approx(kHalfMaximumRadius * rs.row(a).norm()).epsilon(1e-5));
}

TEST_CASE("EVER's march integrates exactly what every event does, for every k and structure",
          "[gaussians][methods]") {
  MarchBed bed(11);
  const Dataset& d = bed.d;
  const std::vector<Ray>& rays = bed.rays;
  ParticleSet& g = bed.g;
  const std::vector<float> density = constant_density_ellipsoids(g);
  std::vector<Oracle> truth;
  for (const Ray& r : rays) truth.push_back(integrate_all(g, density, r));
  REQUIRE(std::count_if(truth.begin(), truth.end(), [](const Oracle& o) { return o.found; }) > 100);
  uint64_t integrated_k1 = 0;
  for (const char* structure : {"brute_force", "bvh", "kd_tree", "octree"})
    for (double k : {1.0, 2.0, 16.0, 64.0}) {
      OpCounters c;
      Timings t;
      const PointScene scene(d.cloud, SceneOptions{"ever_2024", structure, {{"k", k}}}, c, t);
      OpCounters frame;
      for (size_t i = 0; i < rays.size(); ++i) {
        Hit h;
        const bool found = scene.closest_hit(rays[i], h, frame);
        INFO(structure << " k=" << k << " ray " << i);
        REQUIRE(found == truth[i].found);
        if (found) REQUIRE((h.prim == truth[i].prim && h.t == truth[i].t));
        OpCounters shadow;
        REQUIRE(scene.any_hit(rays[i], shadow) == found);
      }
      const uint64_t integrated = frame.to_map().at("ellipsoid_events");
      if (integrated_k1 == 0) integrated_k1 = integrated;
      REQUIRE(integrated == integrated_k1);  // the same events, whatever k
    }
}

}  // namespace pcrt
