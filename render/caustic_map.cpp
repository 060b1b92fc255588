#include "render/caustic_map.hpp"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>

#include "core/rng.hpp"
#include "render/renderer.hpp"
#include "render/sampling.hpp"

namespace pcrt {
namespace {

constexpr uint64_t kPhotonStream = 0x43534d;  // "CSM": apart from the camera samples' streams
constexpr uint32_t kLeafSize = 8;
constexpr int kMaxDepth = 24;

// A light that emits photons, its flux and the probability a photon is drawn from it.
struct Emitter {
  const Light* light;
  Vec3 flux;
  float p = 0, cdf = 0;
};

// Point lights: flux 4 pi I. Sphere lights: pi L times the sphere's area.
std::vector<Emitter> emitters(const RenderScene& scene) {
  std::vector<Emitter> out;
  for (const Light& l : scene.lights) {
    if (l.kind == LightKind::kPoint) out.push_back({&l, 4.0f * kPi * l.power});
    if (l.kind == LightKind::kSphere)
      out.push_back({&l, kPi * 4.0f * kPi * l.radius * l.radius * l.power});
  }
  float total = 0;
  for (const Emitter& e : out) total += e.flux.mean();
  float cdf = 0;
  for (Emitter& e : out) e.p = total > 0 ? e.flux.mean() / total : 0, e.cdf = cdf += e.p;
  return out;
}

enum class Fate : uint8_t { kStored, kDiffuseFirst, kEscaped, kCut };

struct PhotonSlot {
  CausticPhoton photon;
  Vec3 emitted = Vec3::Zero();
  Fate fate = Fate::kEscaped;
};

// The photon's first ray: from a point light in a uniform direction, from a uniform point of a
// sphere light in a cosine-weighted direction about its outward normal.
Ray emit(const Emitter& e, float epsilon, Rng& rng) {
  const Vec3 d = uniform_sphere(uniform2(rng));
  if (e.light->kind == LightKind::kPoint) return Ray{e.light->position, d, 0.0f, kInfinity};
  const Vec3 dir = Frame3(d).to_world(cosine_hemisphere(uniform2(rng))).normalized();
  return Ray{e.light->position + (e.light->radius + epsilon) * d, dir, 0.0f, kInfinity};
}

// Whether a sphere light lies in front of the hit at t: photons end on lights.
bool ends_on_light(const RenderScene& scene, const Ray& ray, float t) {
  for (const Light& l : scene.lights)
    if (intersect_light(l, ray) < t) return true;
  return false;
}

PhotonSlot trace_photon(const RenderScene& scene, std::span<const Emitter> lights,
                        const CausticMapSettings& s, float epsilon, uint64_t i,
                        OpCounters& counters) {
  Rng rng = Rng::for_sample(s.seed, i, kPhotonStream);
  const float u = rng.uniform();
  const Emitter* e = &lights.back();
  for (const Emitter& c : lights)
    if (u < c.cdf) {
      e = &c;
      break;
    }
  PhotonSlot slot;
  Vec3 power = e->flux / (float(s.spec.photons) * e->p);
  slot.emitted = power;
  Ray ray = emit(*e, epsilon, rng);
  counters.add(kCsmPhotons);
  for (int specular = 0;; ++specular) {
    Hit hit;
    uint32_t object = 0;
    counters.add(kCsmPhotonRays);
    const bool found = scene.closest_hit(ray, hit, object, counters);
    if (!found || ends_on_light(scene, ray, hit.t)) return slot;  // escaped
    const Material m = scene.material_at(object, hit.prim);
    if (!is_delta(m)) {
      slot.fate = specular == 0 ? Fate::kDiffuseFirst : Fate::kStored;
      slot.photon = CausticPhoton{hit.p, -ray.d, power};
      return slot;
    }
    if (specular == s.max_specular) {
      slot.fate = Fate::kCut;
      slot.photon.power = power;
      return slot;
    }
    const Vec3 n = shading_normal(hit, ray, m);
    const Frame3 frame(n);
    const Vec3 wo = frame.to_local(-ray.d);
    const Vec2 uv = uniform2(rng);
    const auto bs = bsdf_sample(m, wo, rng.uniform(), uv);
    if (!bs || bs->pdf <= 0) return slot;
    Vec3 weight = bs->f * (std::abs(bs->wi.z()) / bs->pdf);
    if (bs->transmitted) {  // flux, not radiance: undo the 1/eta^2 of radiance transport
      const float etap = wo.z() > 0 ? m.eta : 1.0f / m.eta;
      weight *= etap * etap;
    }
    power = power.cwiseProduct(weight);
    const Vec3 wi = frame.to_world(bs->wi).normalized();
    ray = Ray{spawn_point(hit, n, wi, epsilon), wi, 0.0f, kInfinity};
  }
}

// The stored photons in photon-index order, and the sums over all photons in that order.
CausticMapStats collect(std::span<const PhotonSlot> slots, std::vector<CausticPhoton>& stored) {
  CausticMapStats st;
  st.photons = slots.size();
  for (const PhotonSlot& slot : slots) {
    st.emitted_power += slot.emitted.cast<double>();
    switch (slot.fate) {
      case Fate::kStored:
        stored.push_back(slot.photon);
        st.stored_power += slot.photon.power.cast<double>();
        break;
      case Fate::kDiffuseFirst:
        ++st.diffuse_first;
        break;
      case Fate::kEscaped:
        ++st.escaped;
        break;
      case Fate::kCut:
        ++st.cut;
        st.cut_power += slot.photon.power.cast<double>();
        break;
    }
  }
  st.stored = stored.size();
  return st;
}

float box_distance2(const Vec3& q, const Vec3& lo, const Vec3& hi) {
  const Vec3 d = (lo - q).cwiseMax(q - hi).cwiseMax(Vec3::Zero());
  return d.squaredNorm();
}

}  // namespace

// The k nearest so far: a max-heap on the squared distance in fixed storage.
struct CausticMap::Heap {
  struct Entry {
    float d2;
    uint32_t index;
    bool operator<(const Entry& o) const { return d2 < o.d2; }
  };
  Heap(int k_, float max_d2_) : k(k_), max_d2(max_d2_) {}
  int k;
  float max_d2;
  int n = 0;
  uint64_t nodes = 0, entries = 0;
  std::array<Entry, kMaxK> e;  // uninitialised beyond n

  [[nodiscard]] float bound() const { return n == k ? e[0].d2 : max_d2; }
  void offer(float d2, uint32_t index) {
    if (d2 >= bound()) return;
    if (n == k) std::pop_heap(e.begin(), e.begin() + n--);
    e[size_t(n++)] = Entry{d2, index};
    std::push_heap(e.begin(), e.begin() + n);
  }
};

CausticMap::CausticMap(const RenderScene& scene, const CausticMapSettings& s, OpCounters& counters)
    : k_(std::clamp(s.spec.k, 1, kMaxK)) {
  const auto start = std::chrono::steady_clock::now();
  const float diag = positive_or(scene.bounds().diagonal(), 1e-6f);
  max_radius_ = s.spec.max_radius > 0 ? s.spec.max_radius * diag : kInfinity;
  const float epsilon = s.epsilon > 0 ? s.epsilon : 1e-3f * diag;
  const std::vector<Emitter> lights = emitters(scene);
  const size_t count = lights.empty() || s.spec.photons <= 0 ? 0 : size_t(s.spec.photons);
  std::vector<PhotonSlot> slots(count);
  tbb::combinable<OpCounters> per_thread;
  tbb::task_arena arena(s.threads > 0 ? s.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const auto& r) {
      OpCounters& c = per_thread.local();
      for (size_t i = r.begin(); i != r.end(); ++i)
        slots[i] = trace_photon(scene, lights, s, epsilon, i, c);
    });
  });
  per_thread.combine_each([&](const OpCounters& c) { counters.merge(c); });
  stats_ = collect(slots, photons_);
  counters.add(kCsmEntries, photons_.size());
  if (!photons_.empty()) {
    nodes_.emplace_back();
    build(0, 0, uint32_t(photons_.size()), 0);
  }
  counters.add(kCsmOctreeNodes, nodes_.size());
  stats_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Node `id` over entries [begin, end): a leaf when small, else split at its bounds' centre into
// the non-empty octants, in a stable order (the map does not depend on threads).
void CausticMap::build(uint32_t id, uint32_t begin, uint32_t end, int depth) {
  Vec3 lo = Vec3::Constant(kInfinity), hi = Vec3::Constant(-kInfinity);
  for (uint32_t i = begin; i < end; ++i)
    lo = lo.cwiseMin(photons_[i].p), hi = hi.cwiseMax(photons_[i].p);
  nodes_[id] = Node{lo, hi, begin, end - begin, true};
  if (end - begin <= kLeafSize || depth >= kMaxDepth || (hi - lo).maxCoeff() <= 0) return;
  const Vec3 mid = 0.5f * (lo + hi);
  auto octant = [&](const CausticPhoton& ph) {
    return int(ph.p.x() > mid.x()) | int(ph.p.y() > mid.y()) << 1 | int(ph.p.z() > mid.z()) << 2;
  };
  std::array<uint32_t, 9> offset{};
  for (uint32_t i = begin; i < end; ++i) ++offset[size_t(octant(photons_[i])) + 1];
  for (size_t o = 1; o < 9; ++o) offset[o] += offset[o - 1];
  const std::vector<CausticPhoton> part(photons_.begin() + begin, photons_.begin() + end);
  std::array<uint32_t, 9> at = offset;
  for (const CausticPhoton& ph : part) photons_[begin + at[size_t(octant(ph))]++] = ph;
  const uint32_t first = uint32_t(nodes_.size());
  uint32_t children = 0;
  for (size_t o = 0; o < 8; ++o) children += offset[o + 1] > offset[o];
  nodes_[id].leaf = false, nodes_[id].first = first, nodes_[id].count = children;
  nodes_.resize(nodes_.size() + children);
  uint32_t child = first;
  for (size_t o = 0; o < 8; ++o)
    if (offset[o + 1] > offset[o])
      build(child++, begin + offset[o], begin + offset[o + 1], depth + 1);
}

void CausticMap::visit(uint32_t id, const Vec3& q, Heap& heap) const {
  const Node& node = nodes_[id];
  ++heap.nodes;
  if (node.leaf) {
    heap.entries += node.count;
    for (uint32_t i = node.first; i < node.first + node.count; ++i)
      heap.offer((photons_[i].p - q).squaredNorm(), i);
    return;
  }
  std::array<std::pair<float, uint32_t>, 8> order;  // children nearest first (insertion sort)
  for (uint32_t c = 0; c < node.count && c < 8; ++c) {
    const Node& child = nodes_[node.first + c];
    const std::pair<float, uint32_t> item{box_distance2(q, child.lo, child.hi), node.first + c};
    uint32_t j = c;
    for (; j > 0 && item < order[j - 1]; --j) order[j] = order[j - 1];
    order[j] = item;
  }
  for (uint32_t c = 0; c < node.count; ++c) {
    if (order[c].first >= heap.bound()) break;
    visit(order[c].second, q, heap);
  }
}

size_t CausticMap::nearest(const Vec3& q, int k, float max_d2, uint32_t* index, float* d2,
                           OpCounters& counters) const {
  Heap heap{std::clamp(k, 1, kMaxK), max_d2};
  if (!nodes_.empty() && box_distance2(q, nodes_[0].lo, nodes_[0].hi) < max_d2) visit(0, q, heap);
  counters.add(kCsmNodesVisited, heap.nodes);
  counters.add(kCsmEntriesVisited, heap.entries);
  for (int i = 0; i < heap.n; ++i) index[i] = heap.e[size_t(i)].index, d2[i] = heap.e[size_t(i)].d2;
  return size_t(heap.n);
}

Vec3 CausticMap::radiance(const Vec3& p, const Frame3& frame, const Material& m, const Vec3& wo,
                          OpCounters& counters) const {
  counters.add(kCsmLookups);
  std::array<uint32_t, kMaxK> index;
  std::array<float, kMaxK> d2;
  const float max_d2 = max_radius_ * max_radius_;
  const size_t n = nearest(p, k_, max_d2, index.data(), d2.data(), counters);
  if (n == 0) return Vec3::Zero();
  // Fewer than k within the bound: the bound is the estimate's radius.
  const float r2 = n == size_t(k_) ? *std::max_element(d2.begin(), d2.begin() + n) : max_d2;
  if (!(r2 > 0) || !std::isfinite(r2)) return Vec3::Zero();
  const float inv_r2 = 1.0f / r2;  // one division per lookup, none per photon
  Vec3 sum = Vec3::Zero();
  for (size_t i = 0; i < n; ++i) {
    const CausticPhoton& ph = photons_[index[i]];
    const float w = 1.0f - d2[i] * inv_r2;
    if (w > 0) sum += w * bsdf_f(m, wo, frame.to_local(ph.wi)).cwiseProduct(ph.power);
  }
  return sum * (2.0f / (kPi * r2));
}

const CausticMapSpec* scene_caustic_map(const RenderScene& scene) {
  for (const SceneObject& o : scene.objects)
    if (const CausticMapSpec* spec = o.geometry->caustic_map()) return spec;
  return nullptr;
}

bool caustic_map_possible(const RenderScene& scene) {
  const auto delta = [](const SceneObject& o) { return is_delta(o.material); };
  const bool specular = std::any_of(scene.objects.begin(), scene.objects.end(), delta);
  // A photon is stored only where it lands on a non-delta surface: a scene of mirrors alone
  // (the closed mirror sphere of configs/bounces.json) would trace every photon to its cut.
  const bool receives = !std::all_of(scene.objects.begin(), scene.objects.end(), delta);
  const bool emits = std::any_of(scene.lights.begin(), scene.lights.end(), [](const Light& l) {
    return l.kind == LightKind::kPoint || l.kind == LightKind::kSphere;
  });
  return specular && receives && emits;
}

}  // namespace pcrt
