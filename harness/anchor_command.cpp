// `pcrt anchor`: our splat family against Embree's oriented discs on the same rays, in one process.
// Honest by construction: every splat-family method (splat_family(): kDisc, kSplatBlend) on every
// structure, Embree given both our Morton order and the cloud's order, passes alternated
// (candidate and references in turn, the order reversed every pass) and ratios taken pass by pass
// before the median, on primary, bounce and shadow rays.
#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "core/dataset.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "harness/command_helpers.hpp"
#include "harness/commands.hpp"
#include "methods/kernels/disc_lanes.hpp"
#include "reconstruction/mesh_engine.hpp"
#include "reconstruction/triangle_mesh.hpp"
#include "render/renderer.hpp"
#include "render/scene.hpp"
#include "structures/wide_node.hpp"

namespace pcrt {
namespace {

using json = nlohmann::json;

// Shadow rays ask whether anything blocks them; the others ask for the closest hit.
enum class Query { kClosest, kAny };

struct RaySet {
  const char* name;
  Query query;
  std::vector<Ray> rays;
};

// One timed pass of all rays; returns Mrays/s and counts hits and work into `hits`, `counters`.
double timed_pass(const SceneIntersector& scene, const RaySet& set, size_t& hits,
                  OpCounters& counters) {
  std::vector<char> found(set.rays.size());
  tbb::combinable<OpCounters> per_thread;
  const auto start = std::chrono::steady_clock::now();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, set.rays.size(), 1024),
                    [&](const tbb::blocked_range<size_t>& br) {
                      OpCounters& c = per_thread.local();
                      for (size_t i = br.begin(); i != br.end(); ++i) {
                        Hit h;
                        h.t = set.rays[i].tmax;
                        found[i] = set.query == Query::kAny ? scene.any_hit(set.rays[i], c)
                                                            : scene.closest_hit(set.rays[i], h, c);
                      }
                    });
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  hits = size_t(std::count(found.begin(), found.end(), 1));
  counters = OpCounters{};
  per_thread.combine_each([&](const OpCounters& c) { counters.merge(c); });
  return double(set.rays.size()) / s / 1e6;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The 1, 5 and 15 minute load averages (/proc/loadavg), or null where there are none: ratios
// are alternated against load, and a reader of the numbers needs to know what they ran beside.
json load_average() {
  std::FILE* f = std::fopen("/proc/loadavg", "r");
  if (!f) return nullptr;
  double a[3] = {0, 0, 0};
  const int read = std::fscanf(f, "%lf %lf %lf", &a[0], &a[1], &a[2]);
  std::fclose(f);
  return read == 3 ? json{a[0], a[1], a[2]} : json(nullptr);
}

// Whether `a` and `b` find the same hits (untimed): rays only one of them hits and, for closest
// hits, rays whose hit is on another point or triangle. Exact agreement is what tracing the same
// discs in the same frame should give; georeferenced coordinates once broke it.
json hit_agreement(const SceneIntersector& a, const SceneIntersector& b, const RaySet& set) {
  size_t both = 0, one_only = 0, other_prim = 0, other_t = 0;
  OpCounters c;
  for (const Ray& r : set.rays) {
    Hit ha, hb;
    ha.t = hb.t = r.tmax;
    const bool fa = set.query == Query::kAny ? a.any_hit(r, c) : a.closest_hit(r, ha, c);
    const bool fb = set.query == Query::kAny ? b.any_hit(r, c) : b.closest_hit(r, hb, c);
    one_only += size_t(fa != fb);
    if (!(fa && fb)) continue;
    ++both;
    if (set.query == Query::kAny || ha.prim == hb.prim) continue;
    ++other_prim;
    // Another point at the same distance is a tie between overlapping discs, not an error.
    other_t += size_t(std::abs(ha.t - hb.t) > 1e-5f * std::max(ha.t, hb.t));
  }
  return {{"both_hit", both},
          {"one_only", one_only},
          {"other_prim", other_prim},
          {"other_prim_other_t", other_t}};
}

// Scenes timed together: [0] the candidate, then the references. Pass 0 warms up; every later
// pass times all scenes, in reverse order on odd passes, so drift (turbo, other load) falls on
// both sides of each ratio alike.
json alternated(const std::vector<const SceneIntersector*>& scenes, const RaySet& set, int reps) {
  const size_t n = scenes.size();
  std::vector<std::vector<double>> rate(n);
  std::vector<size_t> hits(n);
  OpCounters work;
  for (int r = 0; r <= reps; ++r)
    for (size_t j = 0; j < n; ++j) {
      const size_t s = r % 2 ? n - 1 - j : j;
      OpCounters c;
      const double mr = timed_pass(*scenes[s], set, hits[s], c);
      if (r > 0) rate[s].push_back(mr);
      if (r == 0 && s == 0) work = c;
    }
  json out = {{"rays", set.rays.size()},
              {"query", set.query == Query::kAny ? "any_hit" : "closest_hit"},
              {"mrays_per_s", median(rate[0])},
              {"hits", hits[0]}};
  // Work per ray of the candidate (operation counts are exact, so one pass tells).
  json per_ray;
  for (const auto& [name, v] : work.to_map())
    per_ray[name] = double(v) / double(std::max<size_t>(set.rays.size(), 1));
  out["work_per_ray"] = per_ray;
  json refs = json::array();
  for (size_t s = 1; s < n; ++s) {
    std::vector<double> ratio;
    for (size_t k = 0; k < rate[0].size(); ++k) ratio.push_back(rate[0][k] / rate[s][k]);
    std::sort(ratio.begin(), ratio.end());
    refs.push_back({{"mrays_per_s", median(rate[s])},
                    {"hits", hits[s]},
                    {"agreement", hit_agreement(*scenes[0], *scenes[s], set)},
                    {"ratio", median(ratio)},
                    {"ratio_min", ratio.front()},
                    {"ratio_max", ratio.back()}});
  }
  out["references"] = refs;
  return out;
}

// Bounce and shadow rays from the reference's primary hits, as the renderer makes them: lifted
// off the surface, a cosine-sampled bounce and a ray to the renderer's point light.
void secondary_rays(const SceneIntersector& reference, const std::vector<Ray>& primary,
                    const Aabb& bounds, RaySet& bounce, RaySet& shadow) {
  const float diag = std::max(bounds.diagonal(), 1e-6f);
  const RenderSettings rs;
  const Vec3 up = rs.up.normalized(), view = rs.view.normalized();
  const Vec3 side = view.cross(up).normalized();
  const Vec3 light = bounds.center() + diag * (0.9f * view + 1.2f * up - 0.6f * side);
  OpCounters c;
  for (size_t i = 0; i < primary.size(); ++i) {
    Hit h;
    if (!reference.closest_hit(primary[i], h, c)) continue;
    const Vec3 n = h.n.dot(primary[i].d) > 0 ? Vec3(-h.n) : h.n;
    const Vec3 x = h.p + std::max(1e-3f * diag, 0.5f * h.footprint) * n;
    Rng rng = Rng::for_sample(1, i, 0);
    bounce.rays.push_back(Ray{x, cosine_direction(n, rng), 0.0f, kInfinity});
    const Vec3 to_light = light - x;
    const float dist = to_light.norm();
    if (n.dot(to_light) > 0) shadow.rays.push_back(Ray{x, to_light / dist, 0.0f, dist});
  }
}

// Our triangle BVH against Embree's triangles on the same mesh and rays (--mesh).
json mesh_anchor(const std::string& path, int w, int h, int reps) {
  const TriangleMesh mesh = read_mesh(path);
  PointCloud frame;
  frame.positions = mesh.vertices;
  const Aabb bounds = frame.bounds();
  const Camera cam = Camera::framing(bounds, w, h);
  RaySet primary{"primary", Query::kClosest, {}}, bounce{"bounce", Query::kClosest, {}},
      shadow{"shadow", Query::kAny, {}};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) primary.rays.push_back(cam.ray(float(x) + 0.5f, float(y) + 0.5f));
  OpCounters prep;
  Timings t;
  const MeshScene ours(mesh, "bvh", prep, t), embree(mesh, "embree", prep, t);
  secondary_rays(embree, primary.rays, bounds, bounce, shadow);
  json j = {{"mesh", path},
            {"triangles", mesh.triangles.size()},
            {"reps", reps},
            {"engine", "bvh"},
            {"node_simd", wide_nodes_use_avx2() ? "avx2x8" : "sse2x4"},
            {"reference", "embree"}};
  for (const RaySet* set : {&primary, &bounce, &shadow})
    j[set->name] = alternated({&ours, &embree}, *set, reps);
  return j;
}

// --mesh: our triangle BVH against Embree's triangles.
int anchor_mesh(const AnchorOptions& o) {
  if (o.data) input_error("pcrt anchor: --mesh and --data exclude each other");
  const json load_before = load_average();
  json j = mesh_anchor(*o.mesh, o.width, o.height, o.reps);
  j["load_average"] = {{"before", load_before}, {"after", load_average()}};
  if (o.json) {
    std::printf("%s\n", j.dump(2).c_str());
    return 0;
  }
  for (const char* k : {"primary", "bounce", "shadow"})
    std::printf("  %-8s bvh %6.2f Mrays/s, embree %6.2f Mrays/s: x%.3f\n", k,
                j[k]["mrays_per_s"].get<double>(),
                j[k]["references"][0]["mrays_per_s"].get<double>(),
                j[k]["references"][0]["ratio"].get<double>());
  return 0;
}

// --method and --structure checked to name a splat method and a structure.
void check_anchor_candidates(const AnchorOptions& o) {
  if (o.method && !splat_family(MethodRegistry::instance().get(*o.method, "method").family))
    input_error("pcrt anchor: --method {} is not of the splat family", *o.method);
  if (o.structure) (void)StructureRegistry::instance().get(*o.structure, "structure");  // known?
}

// What every candidate is timed against, on the same rays.
struct AnchorBench {
  const Dataset& data;
  ParamValues overrides;
  std::vector<const SceneIntersector*> references;  // Embree's discs in Morton and in cloud order
  std::vector<const RaySet*> sets;                  // primary, bounce, shadow
  int reps;
};

void print_candidate(const json& e, const std::vector<const RaySet*>& sets) {
  std::printf("  %-20s %-12s", e["method"].get<std::string>().c_str(),
              e["structure"].get<std::string>().c_str());
  for (const RaySet* set : sets) {
    const json& r = e[set->name];
    std::printf("  %s %6.2f Mrays/s x%.2f", set->name, r["mrays_per_s"].get<double>(),
                r["references"][0]["ratio"].get<double>());
  }
  std::printf("\n");
}

// One splat-family method on one structure, timed pass by pass against the references.
json time_candidate(const AnchorBench& b, const MethodInfo& m, const StructureInfo& s) {
  Timings ct;
  OpCounters cp;
  const PointScene scene(b.data.cloud, SceneOptions{m.id, s.id, b.overrides}, cp, ct);
  json e = {{"method", m.id},
            {"same_discs", m.family == LeafFamily::kDisc},
            {"structure", s.id},
            {"build_s", ct["build"]},
            {"refs_per_item", double(cp.get(kBuildItemRefs)) / double(b.data.cloud.size())},
            {"structure_bytes", scene.structure_bytes()}};
  std::vector<const SceneIntersector*> scenes = {&scene};
  scenes.insert(scenes.end(), b.references.begin(), b.references.end());
  for (const RaySet* set : b.sets) e[set->name] = alternated(scenes, *set, b.reps);
  return e;
}

json time_candidates(const AnchorOptions& o, const AnchorBench& b) {
  json candidates = json::array();
  for (const MethodInfo& m : MethodRegistry::instance().all()) {
    if (!splat_family(m.family) || !m.own_structure.empty()) continue;
    if (o.method && *o.method != m.id) continue;
    for (const StructureInfo& s : StructureRegistry::instance().all()) {
      if (s.id == "brute_force" || (o.structure && *o.structure != s.id)) continue;
      candidates.push_back(time_candidate(b, m, s));
      if (!o.json) print_candidate(candidates.back(), b.sets);
    }
  }
  return candidates;
}

// The best candidate by its primary-ray ratio against Embree in Morton order: of all, or of those
// tracing exactly Embree's surface (one disc per point; the blending methods trace splats of
// their own making, often fewer than the points).
json best_candidate(const json& candidates, bool same_discs_only) {
  json best;
  for (const json& c : candidates)
    if ((!same_discs_only || c["same_discs"].get<bool>()) &&
        (best.is_null() || c["primary"]["references"][0]["ratio"].get<double>() >
                               best["primary"]["references"][0]["ratio"].get<double>()))
      best = c;
  if (best.is_null()) return best;
  return {{"method", best["method"]},
          {"structure", best["structure"]},
          {"primary", best["primary"]},
          {"bounce", best["bounce"]},
          {"shadow", best["shadow"]}};
}

void print_best(const json& best, const json& best_same) {
  for (const auto& [label, b] : {std::pair{"best", best}, std::pair{"best, same discs", best_same}})
    if (!b.is_null())
      std::printf("%s: %s on %s, primary rays x%.3f Embree (Morton order), x%.3f (cloud order)\n",
                  label, b["method"].get<std::string>().c_str(),
                  b["structure"].get<std::string>().c_str(),
                  b["primary"]["references"][0]["ratio"].get<double>(),
                  b["primary"]["references"][1]["ratio"].get<double>());
}

}  // namespace

int command_anchor(const AnchorOptions& o) {
  auto limit = limit_threads(o.threads);
  if (o.mesh) return anchor_mesh(o);
  const std::string& data = required(o.data, "--data", AnchorOptions::usage);
  const Dataset d = load_dataset(data);
  const Aabb bounds = d.cloud.bounds();
  check_anchor_candidates(o);
  const json load_before = load_average();
  const int w = o.width, hgt = o.height;
  const Camera cam = Camera::framing(bounds, w, hgt);
  RaySet primary{"primary", Query::kClosest, {}}, bounce{"bounce", Query::kClosest, {}},
      shadow{"shadow", Query::kAny, {}};
  for (int y = 0; y < hgt; ++y)
    for (int x = 0; x < w; ++x) primary.rays.push_back(cam.ray(float(x) + 0.5f, float(y) + 0.5f));
  // The references: Embree's discs in our Morton order (the headline) and in the cloud's order.
  Timings t;
  OpCounters prep;
  const PointScene embree_morton(
      d.cloud, SceneOptions{"embree_oriented_disc", "", {{"morton_order", 1}}}, prep, t);
  const PointScene embree_cloud(
      d.cloud, SceneOptions{"embree_oriented_disc", "", {{"morton_order", 0}}}, prep, t);
  secondary_rays(embree_morton, primary.rays, bounds, bounce, shadow);
  const AnchorBench bench{
      d, o.set, {&embree_morton, &embree_cloud}, {&primary, &bounce, &shadow}, o.reps};
  const json candidates = time_candidates(o, bench);
  const json best = best_candidate(candidates, false), best_same = best_candidate(candidates, true);
  const json j = {{"dataset", data},
                  {"N", d.cloud.size()},
                  {"width", w},
                  {"height", hgt},
                  {"reps", o.reps},
                  {"set", o.set},
                  {"leaf_simd", disc_lanes_name()},
                  {"node_simd", wide_nodes_use_avx2() ? "avx2x8" : "sse2x4"},
                  {"references",
                   {"embree_oriented_disc morton_order=1", "embree_oriented_disc morton_order=0"}},
                  {"best", best},
                  {"best_same_discs", best_same},
                  {"load_average", {{"before", load_before}, {"after", load_average()}}},
                  {"candidates", candidates}};
  if (o.json)
    std::printf("%s\n", j.dump(2).c_str());
  else
    print_best(best, best_same);
  return 0;
}

}  // namespace pcrt
