// grt_2024: 3D Gaussian Ray Tracing (Moenne-Loccoz et al. 2024). Each point is a Gaussian
// particle inside a bounding proxy; a ray walks the structure over the proxies collecting the k
// nearest particle responses in a k-buffer, blends them front to back and re-traces from the
// last one until its accumulated opacity reaches the surface threshold. The surface is the
// particle where that happens, at its maximum response along the ray. See README.md.
#include <algorithm>
#include <array>

#include "methods/kernels/gaussian_particles.hpp"
#include "methods/kernels/kbuffer.hpp"
#include "methods/method.hpp"

namespace pcrt {
namespace {

constexpr int kMaxK = 64;

struct GrtParams {
  ParticleParams gaussians;
  GaussianProxy proxy = GaussianProxy::kIcosahedron;
  int k = 16;
  float surface_opacity = 0.5f;
};
const ParamList<GrtParams>& grt_params() {
  using P = GrtParams;
  static const auto l =
      ParamList<P>()
          .add(&P::gaussians, ParticleParams::list())
          .add(&P::proxy, {"proxy", 0, 0, 2,
                           "bounding proxy: 0 icosahedron (the paper's), 1 axis-aligned box, "
                           "2 the cut-off ellipsoid in closed form (RaySplats-style)"})
          .add(&P::k, {"k", 16, 1, kMaxK, "hits collected per walk (the k-buffer's size)"})
          .add(&P::surface_opacity,
               {"surface_opacity", 0.5, 0.01, 0.99,
                "accumulated opacity at which the ray has reached the surface"});
  return l;
}

// A response in the k-buffer, ordered by (t, particle) so that ties do not depend on the walk.
struct KEntry {
  float t;
  uint32_t prim;
  float alpha;
  [[nodiscard]] bool before(const KEntry& o) const {
    return t < o.t || (t == o.t && prim < o.prim);
  }
  [[nodiscard]] bool same(const KEntry& o) const { return prim == o.prim && t == o.t; }
};
using KBuffer = pcrt::KBuffer<KEntry, kMaxK>;

// The walk's leaf test: every proxy the ray meets before the buffer's bound is evaluated, and its
// response inserted if it reaches min_response.
class KBufferCollector final : public LeafIntersector {
 public:
  KBufferCollector(const ParticleSet& g, GaussianProxy proxy, KBuffer& buffer)
      : g_(g), proxy_(proxy), buffer_(buffer) {}

  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    counters.add(kProxyTests, leaf.items.size());
    Ray segment = ray;
    segment.tmax = hit.t;
    const Vec3 inv_d = ray.d.cwiseInverse();
    bool inserted = false;
    for (uint32_t i : leaf.items) {
      if (!proxy_hit(g_, proxy_, i, segment, inv_d)) continue;
      counters.add(kProxyHits);
      const ParticleResponse r = particle_response(g_, i, ray);
      if (r.alpha < g_.min_response || r.t < ray.tmin || r.t > hit.t) continue;
      if (!buffer_.insert({r.t, i, r.alpha})) continue;
      counters.add(kKBufferInserts);
      inserted = true;
      if (buffer_.full()) hit.t = segment.tmax = buffer_.last().t;
    }
    return inserted;
  }

 private:
  const ParticleSet& g_;
  GaussianProxy proxy_;
  KBuffer& buffer_;
};

class Grt2024 final : public Method {
 public:
  explicit Grt2024(const GrtParams& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override {
    particles_ = prepare_gaussians(cloud, params_.gaussians, params_.proxy, ctx);
  }
  [[nodiscard]] ItemSet items() const override { return particles_.items(); }

  bool intersect_leaf(const Ray&, const LeafVisit&, Hit&, OpCounters&) const override {
    return false;  // never called: the walks go through closest_hit_through's k-buffer
  }

  bool closest_hit_through(const Structure& s, const Ray& ray, Hit& hit,
                           OpCounters& counters) const override {
    const KEntry* surface = nullptr;
    KBuffer buffer;
    if (!march(s, ray, std::min(ray.tmax, hit.t), buffer, surface, counters)) return false;
    const uint32_t i = surface->prim;
    record_hit(ray, surface->t, i, particles_.normals[i], particles_.footprints[i], hit);
    return true;
  }
  void any_hits_through(const Structure& s, const Ray* rays, int n, char* blocked,
                        OpCounters& counters) const override {
    for (int i = 0; i < n; ++i) blocked[i] = char(any_hit_through(s, rays[i], counters));
  }
  bool any_hit_through(const Structure& s, const Ray& ray, OpCounters& counters) const override {
    const KEntry* surface = nullptr;
    KBuffer buffer;
    return march(s, ray, ray.tmax, buffer, surface, counters);
  }

 private:
  // Walks until the accumulated opacity reaches surface_opacity (true, `surface` the particle
  // that made it) or a walk ends with the buffer not full (no more responses before tmax).
  bool march(const Structure& s, const Ray& ray, float tmax, KBuffer& buffer,
             const KEntry*& surface, OpCounters& counters) const {
    const float stop = 1.0f - params_.surface_opacity;
    float transmittance = 1;
    buffer.k = params_.k;
    for (bool first = true;; first = false) {
      if (!first) counters.add(kRetraces);
      buffer.n = 0;
      // A re-trace starts at the last entry blended, as the paper's does (that entry's key is
      // inside its proxy, so every later one is met again), not at the ray's origin.
      Ray walk = ray;
      if (buffer.has_after) walk.tmin = buffer.after.t;
      walk.tmax = tmax;
      Hit bound;
      bound.t = tmax;
      s.closest_hit(walk, KBufferCollector(particles_, params_.proxy, buffer), bound, counters);
      for (int j = 0; j < buffer.n; ++j) {
        counters.add(kParticlesBlended);
        transmittance *= 1.0f - buffer.entries[size_t(j)].alpha;
        if (transmittance <= stop) {
          surface = &buffer.entries[size_t(j)];
          counters.add(kKBufferWasted, uint64_t(buffer.n - j - 1));
          return true;
        }
      }
      if (!buffer.full()) return false;
      buffer.restart();
    }
  }

  GrtParams params_;
  ParticleSet particles_;
};

// The paper's statements about its cost (that it follows the hits, not the particles; a BVH
// build close to linear; k = 16 as the compromise between re-traversals and wasted hits), as
// claims the sweeps judge. H is the proxy hits per ray (the any-hit calls of its OptiX walk).
std::vector<MethodInfo::OtherClaim> grt_claims() {
  const std::string paper = "Moenne-Loccoz et al. 2024";
  return {
      {"hits", "time per ray grows linearly in the hits per ray at fixed N", "O(H)", {"H"}, paper},
      {"hits_traversal",
       "traversal work per ray (nodes entered, proxies tested) grows linearly in the hits per ray "
       "at fixed N",
       "O(H)",
       {"H"},
       paper},
      {"in_N",
       "at fixed hits per ray, time per ray grows in the number of particles no faster than the "
       "BVH's depth (the cost follows the hits, not the particles)",
       "O(log N)",
       {"N"},
       paper},
      {"in_N_traversal", "the same of the traversal work per ray", "O(log N)", {"N"}, paper},
      {"build",
       "the BVH over the particles' proxies builds in close to linear time",
       "O(N)",
       {"N"},
       paper},
      {"k_traversal",
       "traversal work per ray is bounded in k: fewer re-traversals at a large k are not paid for "
       "by walks that reach farther",
       "O(1)",
       {"k"},
       paper},
  };
}

std::vector<MethodInfo::ClaimDesign> grt_designs() {
  // Hits per ray at fixed N through the particles' size: radius_k 2..64 moves H about 40x.
  const MethodInfo::ClaimDesign hits{.claim = "hits",
                                     .experiment = "grt_hits",
                                     .variable = "H",
                                     .param = "radius_k",
                                     .values = {2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64},
                                     .N = 20000,
                                     .M = 4096,
                                     .timed = true};
  MethodInfo::ClaimDesign hits_traversal = hits;
  hits_traversal.claim = "hits_traversal";
  hits_traversal.timed = false;
  hits_traversal.metric = {&kNodesVisited, &kProxyTests};
  hits_traversal.per = &kRaysCast;
  // N at fixed H: flat particles are sized by the point spacing, so H is held by design (and
  // checked: it is a held variable). From 16000: below it the sphere's curvature at the
  // particles' scale still moves the traversal work (5% from 4000 to 16000).
  MethodInfo::ClaimDesign in_n{
      .claim = "in_N",
      .experiment = "grt_in_N",
      .variable = "N",
      .M = 4096,
      .Ns = {16000, 32000, 64000, 128000, 256000, 512000, 1024000, 1600000},
      .timed = true};
  MethodInfo::ClaimDesign in_n_traversal = in_n;
  in_n_traversal.claim = "in_N_traversal";
  in_n_traversal.timed = false;
  in_n_traversal.metric = hits_traversal.metric;
  in_n_traversal.per = &kRaysCast;
  const MethodInfo::ClaimDesign build{
      .claim = "build",
      .experiment = "grt_build",
      .variable = "N",
      // 3 decades: over 2.4 a class-up violation of O(N) in time at 5% noise is called only
      // 70% of the time (harness/fit_test.cpp's power test asks 90%).
      .Ns = {2000, 4000, 8000, 16000, 32000, 64000, 128000, 256000, 512000, 1024000, 2048000},
      .build = true,
      .timed = true};
  // The k sweep judges the re-traversal side only: the wasted side (kbuffer_wasted) is at most
  // k - 1 per ray by construction, a bound no data could exceed, so it is measured
  // (results/gaussians/tradeoffs.md), not claimed.
  const MethodInfo::ClaimDesign k_traversal{.claim = "k_traversal",
                                            .experiment = "grt_k",
                                            .variable = "k",
                                            .param = "k",
                                            .values = {2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64},
                                            .N = 20000,
                                            .M = 4096,
                                            .free = {"H"},
                                            .metric = hits_traversal.metric,
                                            .per = &kRaysCast};
  return {hits, hits_traversal, in_n, in_n_traversal, build, k_traversal};
}

}  // namespace

void register_grt_2024(MethodRegistry& registry) {
  registry.add(MethodInfo{
      .id = "grt_2024",
      .paper = "Moenne-Loccoz, Mirzaei, Perel, de Lutio, Martinez Esturo, State, Fidler, Sharp, "
               "Gojcic: 3D Gaussian Ray Tracing: Fast Tracing of Particle Scenes, ACM TOG 43(6) "
               "(SIGGRAPH Asia) 2024",
      .thesis_ref = "-",
      .description = "Gaussian particles in bounding proxies; a k-buffer of the nearest responses "
                     "per walk, blended front to back and re-traced until the accumulated opacity "
                     "reaches the surface threshold",
      .structure = "bvh",
      .needs = {"Gaussian particles (from the file, or made from normals and splat radii)"},
      .params = grt_params().specs(),
      .claims = {},
      .create = create_from<Grt2024>(grt_params(), "grt_2024"),
      .work = {&kProxyTests, &kProxyHits, &kKBufferInserts, &kParticlesBlended},
      .family = LeafFamily::kOther,
      .own_data_bytes_per_point = sizeof(Mat3) + 4 * sizeof(float) + 2 * sizeof(Vec3),
      .hits = &kProxyHits,
      // The surface is where blended opacity reaches one half: on a convex surface the particles
      // in front are the outer tangent planes of points up to 2.9 splat radii away (where a flat
      // particle's alpha falls to 1/255), so the crossing lies farther out than the nearest
      // disc's, and on the torus's tube (radius 0.25) their normals tilt (README: accuracy).
      .accuracy_misses = {{"sphere", "distance median"},
                          {"torus", "distance median"},
                          {"torus", "normal median"}},
      .other_claims = grt_claims(),
      .designs = grt_designs(),
  });
}

}  // namespace pcrt
