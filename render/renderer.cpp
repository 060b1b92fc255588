#include "render/renderer.hpp"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <vector>

#include "core/rng.hpp"
#include "render/caustic_map.hpp"
#include "render/sampling.hpp"

namespace pcrt {
namespace {

constexpr int kTile = 16;

// What every path of a frame shares.
struct PathContext {
  const RenderScene& scene;
  float epsilon;  // the smallest lift of a secondary ray's origin off the surface
  int bounces;
  const CausticMap* csm = nullptr;  // the frame's caustic sample map, if its scene declares one
};

// The previous vertex of a path: how the ray now traced was drawn, for the MIS weight of the
// light it may reach.
struct Bounce {
  Vec3 from = Vec3::Zero();
  float pdf = 0;
  bool specular = true;  // camera rays and delta lobes: no light strategy competes
};

// What a tile's paths add to their pixels, in the order the path tracer adds it, with each next
// event term waiting for its shadow ray. A shadow ray never steers its path (it only decides
// whether a term counts), so a tile draws its paths first (up to kSamplesAtOnce of them) and then
// traces their shadow rays together, sixteen at a time (SceneIntersector::any_hits: one walk of
// the tree for sixteen neighbouring samples' rays to the light), and sums each path as it would
// have, bit for bit.
class TileLedger {
 public:
  struct Pixel {
    int x, y;
    Vec3 sum;  // of its samples' radiance so far, in sample order
  };
  void clear() {
    pixels_.clear();
    forget_samples();
  }
  void add(const Vec3& v) { entries_.push_back({v, kPlain}); }
  // result += throughput * (the sum of the terms that follow whose shadow ray is free).
  void begin_direct(const Vec3& throughput) {
    direct_at_ = entries_.size();
    entries_.push_back({throughput, 0});
  }
  void light_term(const Vec3& term, const Ray& shadow, int depth) {
    ++entries_[direct_at_].terms;
    entries_.push_back({term, int32_t(rays_.size())});
    rays_.push_back(shadow);
    depth_.push_back(uint8_t(std::min(depth, 255)));
  }
  void end_sample() {
    sample_end_.push_back(uint32_t(entries_.size()));
    sample_pixel_.push_back(uint32_t(pixels_.size() - 1));
  }
  // The pixel whose samples follow.
  void begin_pixel(int x, int y) { pixels_.push_back({x, y, Vec3::Zero()}); }
  [[nodiscard]] const std::vector<Pixel>& pixels() const { return pixels_; }
  // Whether the samples recorded should be settled now: a tile of many samples per pixel is
  // settled in parts, so the ledger stays small (a packet's sixteen rays still neighbours).
  [[nodiscard]] bool full() const {
    return sample_end_.size() >= kSamplesAtOnce || entries_.size() >= kEntriesAtOnce;
  }
  // Traces the shadow rays of the samples recorded, adds each sample to its pixel's sum, and
  // forgets them.
  void settle(const RenderScene& scene, OpCounters& counters);

 private:
  static constexpr size_t kSamplesAtOnce = 1024, kEntriesAtOnce = size_t(1) << 16;
  static constexpr int32_t kPlain = -1;
  struct Entry {
    Vec3 value;
    int32_t terms;  // kPlain; or a direct-light header: its number of terms; or a term's ray
  };
  void forget_samples() {
    entries_.clear();
    sample_end_.clear();
    sample_pixel_.clear();
    rays_.clear();
    depth_.clear();
  }
  void trace_shadows(const RenderScene& scene, OpCounters& counters);
  // Sample k's radiance, summed in the order its path added it.
  [[nodiscard]] Vec3 radiance(size_t k) const;

  std::vector<Pixel> pixels_;
  std::vector<Entry> entries_;
  std::vector<uint32_t> sample_end_, sample_pixel_;
  size_t direct_at_ = 0;
  std::vector<Ray> rays_;
  std::vector<uint8_t> depth_;
  std::vector<uint32_t> order_, count_;
  std::vector<Ray> packed_;
  std::vector<char> blocked_, packed_blocked_;
};

// Shadow rays of one depth after another (at 1 spp and one light, a packet of the first depth holds
// a 4x4 block's rays where its pixels all hit; with more samples or lights, fewer pixels'), then
// their answers back in ledger order.
void TileLedger::trace_shadows(const RenderScene& scene, OpCounters& counters) {
  const size_t n = rays_.size();
  count_.assign(257, 0);
  for (const uint8_t d : depth_) ++count_[d + 1u];
  for (size_t d = 1; d < count_.size(); ++d) count_[d] += count_[d - 1];
  order_.resize(n);
  for (size_t i = 0; i < n; ++i) order_[count_[depth_[i]]++] = uint32_t(i);
  packed_.resize(n);
  for (size_t i = 0; i < n; ++i) packed_[i] = rays_[order_[i]];
  packed_blocked_.assign(n, 0);
  for (size_t i = 0; i < n; i += kShadowPacket)
    scene.any_hits(&packed_[i], int(std::min(kShadowPacket, n - i)), &packed_blocked_[i], counters);
  blocked_.resize(n);
  for (size_t i = 0; i < n; ++i) blocked_[order_[i]] = packed_blocked_[i];
}

void TileLedger::settle(const RenderScene& scene, OpCounters& counters) {
  trace_shadows(scene, counters);
  for (size_t k = 0; k < sample_end_.size(); ++k) pixels_[sample_pixel_[k]].sum += radiance(k);
  forget_samples();
}

Vec3 TileLedger::radiance(size_t k) const {
  Vec3 result = Vec3::Zero();
  size_t e = k == 0 ? 0 : sample_end_[k - 1];
  while (e < sample_end_[k]) {
    const Entry& head = entries_[e++];
    if (head.terms == kPlain) {
      result += head.value;
      continue;
    }
    Vec3 direct = Vec3::Zero();
    for (int32_t j = 0; j < head.terms; ++j, ++e)
      if (!blocked_[size_t(entries_[e].terms)]) direct += entries_[e].value;
    result += head.value.cwiseProduct(direct);
  }
  return result;
}

// The MIS weight of a BSDF-sampled ray that reached `light`.
float bsdf_weight(const Light& light, const Bounce& b, const Vec3& d) {
  if (b.specular || !light.sampled) return 1.0f;
  return power_heuristic(b.pdf, light_pdf(light, b.from, d));
}

// Radiance from a sphere light in front of the hit (closest_t), or from the environments when
// nothing was hit; true when the ray ended on a light (lights do not reflect). `mapped`: the
// caustic map holds what a sphere light gives this ray (environments emit no photons).
bool reach_lights(const PathContext& c, const Ray& ray, float closest_t, bool found,
                  const Bounce& b, const Vec3& throughput, bool mapped, TileLedger& result,
                  OpCounters& counters) {
  const Light* nearest = nullptr;
  float t = closest_t;
  for (const Light& l : c.scene.lights) {
    const float tl = intersect_light(l, ray);
    if (tl < t) t = tl, nearest = &l;
  }
  if (nearest) {
    counters.add(kLightHits);
    if (mapped) return true;
    result.add(bsdf_weight(*nearest, b, ray.d) * throughput.cwiseProduct(nearest->power));
    return true;
  }
  if (found) return false;
  for (const Light& l : c.scene.lights)
    if (is_environment(l))
      result.add(bsdf_weight(l, b, ray.d) * throughput.cwiseProduct(light_radiance(l, ray.d)));
  return true;
}

// The shadow ray from a hit to a sampled light point: it starts lifted off the surface (on the
// side the light lies) and ends at that point, or runs to infinity for an environment.
Ray shadow_ray(const PathContext& c, const Hit& hit, const Vec3& n, const LightSample& ls) {
  const Vec3 origin = spawn_point(hit, n, ls.wi, c.epsilon);
  if (!std::isfinite(ls.distance)) return Ray{origin, ls.wi, 0.0f, kInfinity};
  const Vec3 to = hit.p + ls.distance * ls.wi - origin;
  const float dist = to.norm();
  return Ray{origin, to / dist, 0.0f, dist};
}

// Whether another sphere light blocks a shadow ray towards `target`: a bounce ray in the same
// direction would end on it (lights do not pass light through them). Objects are asked later,
// for the whole tile (TileLedger::trace_shadows).
bool blocked_by_light(const PathContext& c, const Ray& shadow, const Light& target) {
  for (const Light& other : c.scene.lights)
    if (&other != &target && intersect_light(other, shadow) < shadow.tmax) return true;
  return false;
}

// Next event estimation at a non-specular vertex: one shadow ray per sampled light. The light is
// sampled from the hit itself, so that its distance and cosine are the shading point's (from the
// lifted origin a light at distance d would be brighter by (d / (d - lift))^2); only the shadow
// ray starts lifted. Point lights draw no random numbers (the default frame's random sequence is
// Algorithm 2's). Records throughput times the sum of the terms whose shadow ray is free.
void direct_light(const PathContext& c, const Hit& hit, const Vec3& n, const Frame3& frame,
                  const Material& m, const Vec3& wo, const Vec3& throughput, int depth, Rng& rng,
                  TileLedger& ledger, OpCounters& counters) {
  ledger.begin_direct(throughput);
  const bool transmits = m.kind == MaterialKind::kRoughDielectric;  // lit from both sides
  for (const Light& l : c.scene.lights) {
    if (!l.sampled) continue;
    const Vec2 u = l.kind == LightKind::kPoint ? Vec2::Zero() : uniform2(rng);
    const auto ls = sample_light(l, hit.p, u);
    if (!ls) continue;
    const Vec3 wi = frame.to_local(ls->wi);
    const float cos_i = std::abs(wi.z());
    if (cos_i <= 0 || (!transmits && wi.z() <= 0)) continue;  // the light is behind the surface
    const Vec3 f = bsdf_f(m, wo, wi);
    counters.add(kShadowRays);
    const Ray shadow = shadow_ray(c, hit, n, *ls);
    if (blocked_by_light(c, shadow, l)) continue;
    const float w = ls->delta ? 1.0f : power_heuristic(ls->pdf, bsdf_pdf(m, wo, wi));
    ledger.light_term(f.cwiseProduct(ls->radiance) * (w * cos_i / ls->pdf), shadow, depth);
  }
}

// Materials with a lobe choice draw its random number after the direction's two.
bool draws_lobe(const Material& m) {
  return m.kind == MaterialKind::kDielectric || m.kind == MaterialKind::kRoughDielectric;
}

// Where a path stands towards the caustic sample map: the map serves the first non-delta vertex
// reached through delta vertices only (the camera's, or behind mirrors and glass), and the paths
// it estimates (light, one or more delta vertices, that vertex) must not be counted again by a
// bounce from it that reaches a photon-emitting light through delta vertices.
struct CausticState {
  bool direct = true;           // every vertex so far was delta
  bool guard = false;           // the last non-delta vertex used the map
  bool specular_after = false;  // a delta vertex followed it
};

// The map's estimate at a vertex of material m, when the path may use it; updates the state.
Vec3 caustic_term(const PathContext& c, const Hit& hit, const Frame3& frame, const Material& m,
                  const Vec3& wo, CausticState& st, OpCounters& counters) {
  if (is_delta(m)) {
    st.specular_after = true;
    return Vec3::Zero();
  }
  const bool use = c.csm && st.direct;
  st = CausticState{false, use, false};
  return use ? c.csm->radiance(hit.p, frame, m, wo, counters) : Vec3::Zero();
}

// Algorithm 2, unrolled: radiance along `ray` whose closest hit (if `found`) is `hit` on
// `object`, recorded term by term in `result`.
void radiance(const PathContext& c, Ray ray, Hit hit, uint32_t object, bool found, Rng& rng,
              TileLedger& result, OpCounters& counters) {
  Vec3 throughput = Vec3::Ones();
  Bounce bounce;
  CausticState caustic;
  for (int depth = 0;; ++depth) {
    if (reach_lights(c, ray, found ? hit.t : kInfinity, found, bounce, throughput,
                     caustic.guard && caustic.specular_after, result, counters))
      break;
    const Material m = c.scene.material_at(object, hit.prim);
    result.add(throughput.cwiseProduct(m.emission));  // emitting surfaces: reached only by rays
    const Vec3 n = shading_normal(hit, ray, m);
    const Frame3 frame(n);
    const Vec3 wo = frame.to_local(-ray.d);
    if (!is_delta(m))
      direct_light(c, hit, n, frame, m, wo, throughput, depth, rng, result, counters);
    result.add(throughput.cwiseProduct(caustic_term(c, hit, frame, m, wo, caustic, counters)));
    if (depth == c.bounces) break;
    const Vec2 u = uniform2(rng);
    const float uc = draws_lobe(m) ? rng.uniform() : 0.5f;
    const auto bs = bsdf_sample(m, wo, uc, u);
    if (!bs) break;
    const Vec3 wi = frame.to_world(bs->wi).normalized();
    throughput = throughput.cwiseProduct(bs->f * (std::abs(bs->wi.z()) / bs->pdf));
    ray = Ray{spawn_point(hit, n, wi, c.epsilon), wi, 0.0f, kInfinity};
    // The light pdf of the point the ray starts from: from the hit, a ray that grazes a sphere
    // light's rim from the lifted origin may miss it, and would then weigh 1 (a firefly).
    bounce = Bounce{ray.o, bs->pdf, bs->delta};
    hit = Hit{};
    counters.add(kBounceRays);
    found = c.scene.closest_hit(ray, hit, object, counters);
  }
}

}  // namespace

Vec3 shading_normal(const Hit& hit, const Ray& ray, const Material& m) {
  if (m.kind == MaterialKind::kDielectric || m.kind == MaterialKind::kRoughDielectric) return hit.n;
  return hit.n.dot(ray.d) > 0 ? Vec3(-hit.n) : hit.n;
}

Vec3 cosine_direction(const Vec3& n, Rng& rng) {
  return Frame3(n).to_world(cosine_hemisphere(uniform2(rng))).normalized();
}

Vec3 spawn_point(const Hit& hit, const Vec3& n, const Vec3& dir, float epsilon) {
  const float lift = std::max(epsilon, 0.5f * hit.footprint);
  return dir.dot(n) >= 0 ? Vec3(hit.p + lift * n) : Vec3(hit.p - lift * n);
}

namespace {

// What every pixel of one frame shares, and the images it writes.
struct Frame {
  PathContext path;
  const RenderSettings& s;
  Camera camera;
  const PrimaryPass* primary;  // the method's own primary pass, or null: camera rays are traced
  RenderResult& out;
  std::vector<float>& depth;
};

// The closest hit of a camera ray: from the method's primary pass if it has one (counted like a
// traced ray, so that rays_cast stays comparable), else traced.
bool primary_hit(const Frame& f, const Ray& ray, float px, float py, Hit& hit, uint32_t& object,
                 OpCounters& counters) {
  counters.add(kPrimaryRays);
  if (!f.primary) return f.path.scene.closest_hit(ray, hit, object, counters);
  counters.add(kRaysCast);
  object = 0;
  const bool found = f.primary->closest_hit(ray, px, py, hit, counters);
  if (found) counters.add(kRayHits);
  return found;
}

// Algorithm 1 for one pixel: spp samples, the first through the pixel centre (it also feeds the
// depth and normal images), the others jittered over the pixel; their paths recorded in `ledger`.
void draw_pixel(const Frame& f, int x, int y, TileLedger& ledger, OpCounters& counters) {
  const RenderSettings& s = f.s;
  const uint64_t pixel = uint64_t(y) * uint64_t(s.width) + uint64_t(x);
  for (int i = 0; i < s.spp; ++i) {
    Rng rng = Rng::for_sample(s.seed, pixel, uint64_t(i));
    const float jx = i == 0 ? 0.5f : rng.uniform(), jy = i == 0 ? 0.5f : rng.uniform();
    const Ray ray = f.camera.ray(float(x) + jx, float(y) + jy);
    Hit hit;
    uint32_t object = 0;
    const bool found = primary_hit(f, ray, float(x) + jx, float(y) + jy, hit, object, counters);
    if (i == 0 && found) {
      f.depth[pixel] = hit.t;
      const Vec3 n = hit.n.dot(ray.d) > 0 ? Vec3(-hit.n) : hit.n;
      f.out.normals.at(x, y) = 0.5f * (n + Vec3::Ones());
      f.out.primary_n[pixel] = n;
    }
    radiance(f.path, ray, hit, object, found, rng, ledger, counters);
    ledger.end_sample();
    if (ledger.full()) ledger.settle(f.path.scene, counters);
  }
}

// A tile's pixels, in blocks of 4x4 (so that sixteen consecutive first shadow rays start from
// one block, as Embree's packets of 16 in the anchor): their paths drawn, then their shadow rays
// traced, then each pixel summed. False when the frame was stopped (the pixels drawn by then are
// written).
bool render_tile(const Frame& f, int x0, int y0, TileLedger& ledger, OpCounters& counters) {
  constexpr int kBlock = 4;
  const RenderSettings& s = f.s;
  const int x1 = std::min(x0 + kTile, s.width), y1 = std::min(y0 + kTile, s.height);
  ledger.clear();
  bool stopped = false;
  for (int by = y0; by < y1; by += kBlock)
    for (int bx = x0; bx < x1; bx += kBlock)
      for (int y = by; y < std::min(by + kBlock, y1); ++y)
        for (int x = bx; x < std::min(bx + kBlock, x1); ++x) {
          stopped = stopped || (s.stop && s.stop->load(std::memory_order_relaxed));
          if (stopped) break;
          ledger.begin_pixel(x, y);
          draw_pixel(f, x, y, ledger, counters);
        }
  ledger.settle(f.path.scene, counters);
  for (const TileLedger::Pixel& p : ledger.pixels())
    f.out.image.at(p.x, p.y) = p.sum / float(s.spp);
  return !stopped;
}

// Every pixel in 16x16 tiles on the threads the settings allow; counters per thread, summed.
void render_tiles(const Frame& f, OpCounters& total) {
  const RenderSettings& s = f.s;
  const int tiles_x = (s.width + kTile - 1) / kTile;
  const int tiles_y = (s.height + kTile - 1) / kTile;
  tbb::combinable<OpCounters> per_thread;
  tbb::task_arena arena(s.threads > 0 ? s.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y), [&](const auto& r) {
      OpCounters& counters = per_thread.local();
      TileLedger ledger;
      for (int tile = r.begin(); tile != r.end(); ++tile)
        if (!render_tile(f, (tile % tiles_x) * kTile, (tile / tiles_x) * kTile, ledger, counters))
          return;
    });
  });
  per_thread.combine_each([&](const OpCounters& c) { total.merge(c); });
}

// The normalised depth image: near is bright, far is dark, background black.
void shade_depth(std::span<const float> depth, Image& image) {
  float dmin = kInfinity, dmax = 0;
  for (float d : depth)
    if (std::isfinite(d)) dmin = std::min(dmin, d), dmax = std::max(dmax, d);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) {
      const float d = depth[size_t(y) * size_t(image.width()) + size_t(x)];
      const float v =
          std::isfinite(d) ? 1.0f - 0.8f * (d - dmin) / std::max(dmax - dmin, 1e-30f) : 0.0f;
      image.at(x, y) = Vec3::Constant(v);
    }
}

// A method's own primary pass stands in for camera rays only where it sees the whole frame: one
// untransformed object.
std::unique_ptr<PrimaryPass> scene_primary_pass(const RenderScene& scene, const Camera& camera,
                                                OpCounters& counters) {
  if (scene.objects.size() != 1 || !scene.objects[0].transform.identity()) return nullptr;
  return scene.objects[0].geometry->primary_pass(camera, counters);
}

// The caustic sample map of the frame, when an object's method declares one and the scene can
// hold an entry (a delta object, a point or sphere light): photons bounded by B specular vertices.
std::unique_ptr<CausticMap> frame_caustic_map(const RenderScene& scene, const RenderSettings& s,
                                              float epsilon, OpCounters& counters) {
  const CausticMapSpec* spec = scene_caustic_map(scene);
  if (!spec || !caustic_map_possible(scene)) return nullptr;
  const CausticMapSettings settings{*spec, s.bounces, s.seed, s.threads, epsilon};
  return std::make_unique<CausticMap>(scene, settings, counters);
}

}  // namespace

RenderResult render(const RenderScene& scene, const RenderSettings& s) {
  const Aabb bounds = scene.bounds();
  const Camera camera =
      s.camera ? *s.camera : Camera::framing(bounds, s.width, s.height, s.view, s.up);
  RenderResult out{Image(s.width, s.height),
                   Image(s.width, s.height),
                   Image(s.width, s.height),
                   {},
                   0,
                   0,
                   {},
                   {}};
  std::vector<float> depth(size_t(s.width) * s.height, kInfinity);
  out.primary_n.assign(depth.size(), Vec3::Zero());
  const auto start = std::chrono::steady_clock::now();
  OpCounters frame_counters;
  const std::unique_ptr<PrimaryPass> primary = scene_primary_pass(scene, camera, frame_counters);
  const float diag = positive_or(bounds.diagonal(), 1e-6f);
  const float epsilon = s.ray_epsilon > 0 ? s.ray_epsilon : 1e-3f * diag;
  const std::unique_ptr<CausticMap> csm = frame_caustic_map(scene, s, epsilon, frame_counters);
  if (csm) out.csm_seconds = csm->stats().seconds;
  const PathContext path{scene, epsilon, s.bounces, csm.get()};
  const Frame frame{path, s, camera, primary.get(), out, depth};
  render_tiles(frame, out.counters);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.counters.merge(frame_counters);
  shade_depth(depth, out.depth);
  out.primary_t = std::move(depth);
  return out;
}

RenderResult render(const SceneIntersector& scene, const PointCloud& cloud,
                    const RenderSettings& s) {
  return render(single_object_scene(scene, cloud, s.view, s.up, s.point_light), s);
}

}  // namespace pcrt
