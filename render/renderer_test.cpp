#include "render/renderer.hpp"

#include <tbb/global_control.h>

#include <catch2/catch.hpp>

#include "core/dataset.hpp"
#include "preprocess/point_attributes.hpp"
#include "render/scene.hpp"

using namespace pcrt;

namespace {

struct Frame {
  RenderResult result;
  OpCounters prepare;
};

Frame render_with_threads(const PointCloud& cloud, int threads,
                          const std::string& structure = "brute_force", ParamValues set = {}) {
  // Preparation (normals, radii) runs on TBB too: limit it the same way the CLI does.
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
  OpCounters prep;
  Timings t;
  set["estimate_normals"] = 1;
  const PointScene scene(cloud, SceneOptions{"reference_splat", structure, set}, prep, t);
  RenderSettings s;
  s.width = 40;
  s.height = 30;
  s.spp = 2;
  s.bounces = 2;
  s.threads = threads;
  return Frame{render(scene, cloud, s), prep};
}

// The scene `inner`, but asked for occlusion one ray at a time (SceneIntersector::any_hits'
// default), as frames were traced before a tile's shadow rays went sixteen at a time.
class OneShadowRayAtATime final : public SceneIntersector {
 public:
  explicit OneShadowRayAtATime(const SceneIntersector& inner) : inner_(inner) {}
  bool closest_hit(const Ray& ray, Hit& hit, OpCounters& counters) const override {
    return inner_.closest_hit(ray, hit, counters);
  }
  bool any_hit(const Ray& ray, OpCounters& counters) const override {
    return inner_.any_hit(ray, counters);
  }
  [[nodiscard]] std::unique_ptr<PrimaryPass> primary_pass(const Camera& camera,
                                                          OpCounters& counters) const override {
    return inner_.primary_pass(camera, counters);
  }
  [[nodiscard]] const CausticMapSpec* caustic_map() const override { return inner_.caustic_map(); }

 private:
  const SceneIntersector& inner_;
};

}  // namespace

TEST_CASE("shadow rays sixteen at a time give every method the image and counts of one at a time",
          "[renderer]") {
  const Dataset d = load_dataset("torus:n=20000,seed=9");
  RenderSettings s;
  s.width = 45;  // tiles and 4x4 blocks cut at the edges
  s.height = 30;
  s.spp = 2;
  s.bounces = 2;
  for (const MethodInfo& m : MethodRegistry::instance().all()) {
    // The bvh (whose walk takes sixteen rays together) wherever the method runs on structures.
    const std::string structure = m.own_structure.empty() ? "bvh" : "";
    INFO(m.id << " on " << (structure.empty() ? m.own_structure : structure));
    OpCounters prep;
    Timings t;
    const PointScene scene(d.cloud, SceneOptions{m.id, structure, {}}, prep, t);
    const RenderResult sixteen = render(scene, d.cloud, s);
    const RenderResult one = render(OneShadowRayAtATime(scene), d.cloud, s);
    CHECK(sixteen.image.pixels() == one.image.pixels());
    CHECK(sixteen.counters.to_map() == one.counters.to_map());
    CHECK(sixteen.counters.get(kShadowRays) > 0);
  }
}

TEST_CASE("images and counters do not depend on thread count", "[renderer]") {
  const Dataset d = load_dataset("torus:n=3000,seed=5");
  const Frame one = render_with_threads(d.cloud, 1);
  const Frame two = render_with_threads(d.cloud, 2);
  REQUIRE(one.result.image.pixels() == two.result.image.pixels());
  REQUIRE(one.result.counters.to_map() == two.result.counters.to_map());
  REQUIRE(one.prepare.to_map() == two.prepare.to_map());
  const auto c = one.result.counters.to_map();
  REQUIRE(c.at("primary_rays") == 40 * 30 * 2);
  // Every ray the renderer casts goes through the scene, and brute force tests every splat.
  REQUIRE(c.at("rays_cast") == c.at("primary_rays") + c.at("bounce_rays") + c.at("shadow_rays"));
  REQUIRE(c.at("splat_tests") == c.at("rays_cast") * 3000);
  REQUIRE(c.at("ray_hits") > 0);
}

TEST_CASE("every structure renders the same image with the same counters at 1 and 2 threads",
          "[renderer]") {
  const Dataset d = load_dataset("bumpy_sphere:n=20000,seed=5");
  const Frame reference = render_with_threads(d.cloud, 1);
  // Every structure with its defaults, and the variants whose build or walk differs.
  const std::vector<std::pair<std::string, ParamValues>> runs = {{"kd_tree", {}},
                                                                 {"kd_tree", {{"split", 1}}},
                                                                 {"octree", {}},
                                                                 {"octree", {{"child_bounds", 0}}},
                                                                 {"octree", {{"loose", 1}}},
                                                                 {"sphere_tree", {}},
                                                                 {"grid", {}},
                                                                 {"bvh", {}}};
  for (const auto& [id, set] : runs) {
    INFO(id << (set.empty() ? "" : " (a variant)"));
    const Frame one = render_with_threads(d.cloud, 1, id, set);
    const Frame two = render_with_threads(d.cloud, 2, id, set);
    REQUIRE(one.result.counters.to_map() == two.result.counters.to_map());
    REQUIRE(one.result.image.pixels() == two.result.image.pixels());
    // Exact closest hits: the image is brute force's, pixel for pixel.
    REQUIRE(one.result.image.pixels() == reference.result.image.pixels());
    REQUIRE(one.result.counters.get(kRayHits) == reference.result.counters.get(kRayHits));
  }
}

TEST_CASE("every method renders the same image with the same counters at 1 and 2 threads",
          "[renderer]") {
  const Dataset d = load_dataset("torus:n=20000,seed=9");
  // Every method with its defaults, and the compressed variants (their own walks and decoding).
  std::vector<std::pair<const MethodInfo*, ParamValues>> runs;
  for (const MethodInfo& m : MethodRegistry::instance().all()) runs.push_back({&m, {}});
  runs.push_back({&MethodRegistry::instance().get("hubo_2006", "method"), {{"quantized", 1}}});
  runs.push_back({&MethodRegistry::instance().get("hubo_2007", "method"), {{"compressed", 1}}});
  for (const auto& [method, set] : runs) {
    const MethodInfo& m = *method;
    INFO(m.id << (set.empty() ? "" : " (compressed variant)"));
    auto frame = [&, &set = set](int threads) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
      OpCounters prep;
      Timings t;
      const std::string structure = m.structure == "brute_force" ? "kd_tree" : "";
      const PointScene scene(d.cloud, SceneOptions{m.id, structure, set}, prep, t);
      RenderSettings s;
      s.width = 48;
      s.height = 32;
      s.spp = 2;
      s.bounces = 2;
      s.threads = threads;
      return std::make_pair(render(scene, d.cloud, s), prep);
    };
    const auto one = frame(1);
    const auto two = frame(2);
    REQUIRE(one.first.image.pixels() == two.first.image.pixels());
    REQUIRE(one.first.counters.to_map() == two.first.counters.to_map());
    REQUIRE(one.second.to_map() == two.second.to_map());
  }
}

TEST_CASE("a sphere renders where it should", "[renderer]") {
  const Dataset d = load_dataset("fibonacci_sphere:n=4000");
  OpCounters prep;
  Timings t;
  const PointScene scene(d.cloud, SceneOptions{"reference_splat", "", {}}, prep, t);
  RenderSettings s;
  s.width = s.height = 33;
  s.bounces = 0;
  const RenderResult r = render(scene, d.cloud, s);
  // Framing puts the sphere in the centre; the corners see sky.
  REQUIRE(r.depth.at(16, 16).x() > 0);
  REQUIRE(r.depth.at(0, 0).x() == 0);
  // With B = 0 there are no bounce rays: one shadow ray at most per lit primary hit.
  REQUIRE(r.counters.get(kBounceRays) == 0);
  REQUIRE(r.counters.get(kShadowRays) <= r.counters.get(kRayHits));
}

TEST_CASE("camera projection inverts camera rays", "[renderer]") {
  const Camera cam = Camera::framing(Aabb{Vec3(-1, -2, -1), Vec3(1, 2, 3)}, 320, 200);
  for (const auto& [px, py] : {std::pair{0.5f, 0.5f}, {319.0f, 10.0f}, {160.0f, 100.0f}}) {
    const Ray r = cam.ray(px, py);
    float qx = 0, qy = 0, depth = 0;
    REQUIRE(cam.project(r.at(7.0f), qx, qy, depth));
    REQUIRE(qx == Approx(px).margin(1e-3));
    REQUIRE(qy == Approx(py).margin(1e-3));
    REQUIRE(depth > 0);
  }
  float qx = 0, qy = 0, depth = 0;
  REQUIRE_FALSE(cam.project(cam.eye() - cam.ray(10, 10).d, qx, qy, depth));  // behind
}
