// Analytic scenes the path tracer must render to a known radiance (pbrt-v4's integrators_test
// design): inside a closed sphere of albedo 1/2 the radiance is 1 everywhere when the sphere is lit
// by a point light of intensity pi at its centre (direct 1/2, and each bounce halves what it
// carries), by four lights of pi/4, by a sphere light of the same power, or when the sphere emits
// 1/2 itself. A convex object of albedo 1 under a uniform environment of radiance 1 renders to 1
// (the white furnace). Run on an exact sphere and on a triangle mesh.
#include <catch2/catch.hpp>
#include <cmath>
#include <numeric>

#include "reconstruction/mesh_engine.hpp"
#include "render/furnace.hpp"
#include "render/renderer.hpp"
#include "render/surface_scene.hpp"

using namespace pcrt;

namespace {

// The exact unit sphere about the origin, normals outward.
class ExactSphere final : public SceneIntersector {
 public:
  bool closest_hit(const Ray& ray, Hit& hit, OpCounters& counters) const override {
    counters.add(kRaysCast);
    const float b = ray.o.dot(ray.d), c = ray.o.squaredNorm() - 1.0f;
    const float disc = b * b - c;
    if (disc < 0) return false;
    const float h = std::sqrt(disc);
    float t = -b - h;
    if (t < ray.tmin || t >= std::min(ray.tmax, hit.t)) t = -b + h;
    if (t < ray.tmin || t >= std::min(ray.tmax, hit.t)) return false;
    hit.t = t, hit.p = ray.at(t), hit.n = hit.p.normalized(), hit.prim = 0;
    return true;
  }
};

// An icosahedron subdivided `levels` times, its vertices on the unit sphere.
TriangleMesh icosphere(int levels) {
  const float g = (1.0f + std::sqrt(5.0f)) / 2.0f;
  TriangleMesh m;
  for (const Vec3& v : {Vec3(-1, g, 0), Vec3(1, g, 0), Vec3(-1, -g, 0), Vec3(1, -g, 0),
                        Vec3(0, -1, g), Vec3(0, 1, g), Vec3(0, -1, -g), Vec3(0, 1, -g),
                        Vec3(g, 0, -1), Vec3(g, 0, 1), Vec3(-g, 0, -1), Vec3(-g, 0, 1)})
    m.vertices.push_back(v.normalized());
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::vector<std::array<uint32_t, 3>> next;
    for (const auto& t : m.triangles) {
      uint32_t mid[3];
      for (int e = 0; e < 3; ++e) {
        m.vertices.push_back((m.vertices[t[e]] + m.vertices[t[(e + 1) % 3]]).normalized());
        mid[e] = uint32_t(m.vertices.size() - 1);
      }
      next.push_back({t[0], mid[0], mid[2]});
      next.push_back({mid[0], t[1], mid[1]});
      next.push_back({mid[2], mid[1], t[2]});
      next.push_back({mid[0], mid[1], mid[2]});
    }
    m.triangles = std::move(next);
  }
  return m;
}

Light point_light(float intensity) {
  Light l;
  l.power = Vec3::Constant(intensity);
  return l;
}

// The mean radiance of a small frame seen from inside the sphere, looking away from its centre
// (where the lights are): the wall's radiance does not depend on where it is seen from.
float mean_inside(const SceneIntersector& geometry, Material material, std::vector<Light> lights,
                  int spp = 16) {
  RenderScene scene;
  Aabb box;
  box.extend(Vec3::Constant(-1)), box.extend(Vec3::Constant(1));
  scene.objects.push_back(SceneObject{&geometry, nullptr, material, Transform{}, box, "sphere"});
  scene.lights = std::move(lights);
  RenderSettings s;
  s.width = s.height = 16;
  s.spp = spp;
  s.bounces = 24;  // 2^-25 of the series is left out
  s.ray_epsilon = 1e-4f;
  s.camera = Camera(Vec3(0.5f, 0.02f, 0.03f), Vec3(2, 0.3f, 0.2f), Vec3::UnitZ(), 90, 16, 16);
  const RenderResult r = render(scene, s);
  double sum = 0;
  for (const Vec3& p : r.image.pixels()) sum += p.mean();
  return float(sum / double(r.image.pixels().size()));
}

Material diffuse(float albedo) {
  Material m;
  m.albedo = Vec3::Constant(albedo);
  return m;
}

void check_analytic_scenes(const SceneIntersector& sphere) {
  SECTION("one point light of intensity pi") {
    CHECK(mean_inside(sphere, diffuse(0.5f), {point_light(kPi)}) == Approx(1.0f).margin(0.025));
  }
  SECTION("four point lights of pi/4") {
    std::vector<Light> four(4, point_light(kPi / 4));
    CHECK(mean_inside(sphere, diffuse(0.5f), four) == Approx(1.0f).margin(0.025));
  }
  SECTION("a sphere light of the same power, sampled and hit (MIS)") {
    Light l;
    l.kind = LightKind::kSphere;
    l.radius = 0.1f;
    l.power = Vec3::Constant(1.0f / (l.radius * l.radius));  // irradiance pi L (r/d)^2 = pi
    l.position = Vec3::Zero();
    CHECK(mean_inside(sphere, diffuse(0.5f), {l}) == Approx(1.0f).margin(0.025));
  }
  SECTION("the sphere itself emitting 1/2") {
    Material m = diffuse(0.5f);
    m.emission = Vec3::Constant(0.5f);
    Light none;
    none.kind = LightKind::kEnvironment;
    none.power = Vec3::Zero();
    CHECK(mean_inside(sphere, m, {none}) == Approx(1.0f).margin(0.025));
  }
}

}  // namespace

TEST_CASE("analytic scenes render to radiance 1 on an exact sphere", "[light_transport]") {
  const ExactSphere sphere;
  check_analytic_scenes(sphere);
}

TEST_CASE("analytic scenes render to radiance 1 on a triangle mesh sphere", "[light_transport]") {
  const TriangleMesh mesh = icosphere(4);
  OpCounters counters;
  Timings timings;
  const MeshScene sphere(mesh, "bvh", counters, timings);
  check_analytic_scenes(sphere);
}

TEST_CASE("a white convex object under a uniform environment renders to 1 (furnace)",
          "[light_transport]") {
  const ExactSphere sphere;
  for (const bool sampled : {false, true}) {
    INFO("environment sampled by next event estimation: " << sampled);
    RenderScene scene;
    Aabb box;
    box.extend(Vec3::Constant(-1)), box.extend(Vec3::Constant(1));
    scene.objects.push_back(SceneObject{&sphere, nullptr, diffuse(1), Transform{}, box, "sphere"});
    Light env;
    env.kind = LightKind::kEnvironment;
    env.sampled = sampled;
    scene.lights = {env};
    RenderSettings s;
    s.width = s.height = 24;
    s.spp = 8;
    s.bounces = 3;
    const RenderResult r = render(scene, s);
    double sum = 0;
    for (const Vec3& p : r.image.pixels()) sum += p.mean();
    const double mean = sum / double(r.image.pixels().size());
    CHECK(mean == Approx(1.0).margin(sampled ? 0.02 : 1e-5));
    if (!sampled)  // every path escapes with weight exactly albedo = 1: no variance at all
      for (const Vec3& p : r.image.pixels()) REQUIRE(p.minCoeff() == Approx(1.0f).margin(1e-5));
  }
}

namespace {

// The unit sphere seen through its near side: rays from outside hit where they leave it, as a
// method's camera rays do when they pass between its splats.
class FarSideSphere final : public SceneIntersector {
 public:
  bool closest_hit(const Ray& ray, Hit& hit, OpCounters& counters) const override {
    if (ray.o.norm() <= 1.0f) return exact_.closest_hit(ray, hit, counters);
    const float b = ray.o.dot(ray.d), disc = b * b - (ray.o.squaredNorm() - 1.0f);
    if (disc < 0) return false;
    const float t = -b + std::sqrt(disc);
    hit.t = t, hit.p = ray.at(t), hit.n = hit.p.normalized(), hit.prim = 0;
    return true;
  }

 private:
  SphereSurface surface_;
  SurfaceScene exact_{surface_};
};

}  // namespace

TEST_CASE("the furnace tells false camera-ray hits from paths lost after a true hit",
          "[light_transport]") {
  SphereSurface unit;
  PointCloud corners;
  corners.positions = {Vec3::Constant(-1), Vec3::Constant(1)};
  RenderSettings s;
  s.width = s.height = 24;
  s.spp = 1;
  s.bounces = 1;
  const FurnaceTruth truth{unit, 0.01};
  const SurfaceScene exact(unit);
  const FurnaceResult clean = white_furnace(exact, corners, s, truth);
  REQUIRE(clean.object_pixels > 100);
  CHECK(clean.dark_pixels == 0);
  REQUIRE(clean.causes);
  CHECK(clean.causes->primary == 0);
  CHECK(clean.causes->secondary == 0);
  // Every camera ray lands on the far wall, 2 units behind the surface it should hit; its bounce
  // ray then leaves inside the sphere and hits it again: every object pixel is dark, and each
  // is a false camera-ray hit.
  const FarSideSphere leaky;
  const FurnaceResult leaked = white_furnace(leaky, corners, s, truth);
  CHECK(leaked.dark_pixels == leaked.object_pixels);
  REQUIRE(leaked.causes);
  CHECK(leaked.causes->primary == leaked.dark_pixels);
  CHECK(leaked.causes->secondary == 0);
  CHECK_FALSE(white_furnace(leaky, corners, s).causes);  // without a truth, no split
}

namespace {

// A quad of side `size` about `centre` in a plane of constant z, as a mesh.
TriangleMesh quad_at(const Vec3& centre, float size) {
  const float h = 0.5f * size;
  TriangleMesh m;
  for (const Vec3& c : {Vec3(-h, -h, 0), Vec3(h, -h, 0), Vec3(h, h, 0), Vec3(-h, h, 0)})
    m.vertices.push_back(centre + c);
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

}  // namespace

TEST_CASE("a mirror shows the scene a mirrored camera sees, pixel for pixel", "[light_transport]") {
  // Two emitting quads above a mirror in z = 0; the frame of the mirror equals the frame of the
  // camera mirrored through z = 0, flipped left to right (a reflection reverses handedness).
  OpCounters counters;
  Timings timings;
  const TriangleMesh mirror_mesh = quad_at(Vec3::Zero(), 40), red = quad_at(Vec3(-1, 0.5f, 3), 2),
                     blue = quad_at(Vec3(1.5f, -0.7f, 4), 1.5f);
  const MeshScene mirror(mirror_mesh, "bvh", counters, timings), a(red, "bvh", counters, timings),
      b(blue, "bvh", counters, timings);
  auto emitter = [](const Vec3& c) {
    Material m;
    m.albedo = Vec3::Zero();
    m.emission = c;
    return m;
  };
  Material mirror_material;
  mirror_material.kind = MaterialKind::kMirror;
  mirror_material.albedo = Vec3::Ones();
  Light dark;
  dark.kind = LightKind::kEnvironment;
  dark.power = Vec3::Zero();
  const Aabb box;
  auto frame = [&](bool with_mirror, const Vec3& eye, const Vec3& target, const Vec3& up) {
    RenderScene scene;
    if (with_mirror) scene.objects.push_back({&mirror, nullptr, mirror_material, {}, box, "m"});
    scene.objects.push_back({&a, nullptr, emitter(Vec3(1, 0.2f, 0.1f)), {}, box, "red"});
    scene.objects.push_back({&b, nullptr, emitter(Vec3(0.1f, 0.3f, 1)), {}, box, "blue"});
    scene.lights = {dark};
    RenderSettings s;
    s.width = 64, s.height = 48, s.bounces = 1, s.ray_epsilon = 1e-4f;
    s.camera = Camera(eye, target, up, 50, s.width, s.height);
    return render(scene, s);
  };
  // Looking down at the mirror from above; and from the mirrored eye, up at the emitters.
  const RenderResult seen = frame(true, Vec3(0.3f, -9, 2.5f), Vec3(0.2f, 0, -3.1f), Vec3::UnitZ());
  const RenderResult reflected =
      frame(false, Vec3(0.3f, -9, -2.5f), Vec3(0.2f, 0, 3.1f), -Vec3::UnitZ());
  size_t lit = 0, differ = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) {
      const Vec3 m = seen.image.at(x, y), d = reflected.image.at(63 - x, y);
      lit += m.maxCoeff() > 0;
      differ += (m - d).cwiseAbs().maxCoeff() > 1e-5f;
    }
  CHECK(lit > 50);  // 83 here
  CHECK(differ == 0);
}

TEST_CASE("a sphere light blocks the shadow rays of other lights, as it ends bounce rays",
          "[light_transport]") {
  // A dark sphere light around the whole scene: a bounce ray ends on it (radiance 0), so a
  // shadow ray to the environment beyond it must be blocked too, or NEE adds light that BSDF
  // sampling can never see.
  const ExactSphere sphere;
  RenderScene scene;
  Aabb box;
  box.extend(Vec3::Constant(-1)), box.extend(Vec3::Constant(1));
  scene.objects.push_back(SceneObject{&sphere, nullptr, diffuse(0.8f), Transform{}, box, "ball"});
  Light shell;
  shell.kind = LightKind::kSphere;
  shell.radius = 10;
  shell.power = Vec3::Zero();
  Light environment;
  environment.kind = LightKind::kEnvironment;
  scene.lights = {shell, environment};
  RenderSettings s;
  s.width = s.height = 16;
  s.spp = 4;
  s.bounces = 2;
  s.camera = Camera(Vec3(0, -3, 0), Vec3::Zero(), Vec3::UnitZ(), 40, 16, 16);
  const RenderResult r = render(scene, s);
  for (const Vec3& p : r.image.pixels()) REQUIRE(p.maxCoeff() == 0.0f);
}

TEST_CASE("a scene of several objects renders the same at 1 and 2 threads", "[light_transport]") {
  // Glass, a rough conductor and a diffuse floor, moved objects, a sphere light and a sampled
  // environment: every random number belongs to its (pixel, sample), so nothing may change.
  const ExactSphere ball;
  const TriangleMesh floor_mesh = quad_at(Vec3(0, 0, -1), 12);
  OpCounters prep;
  Timings timings;
  const MeshScene floor(floor_mesh, "bvh", prep, timings);
  Material glass, metal;
  glass.kind = MaterialKind::kDielectric;
  metal.kind = MaterialKind::kRoughConductor;
  metal.alpha = 0.3f;
  Transform moved;
  moved.translate = Vec3(2, 0.5f, -0.4f);
  moved.scale = 0.6f;
  const Aabb box;
  RenderScene scene;
  scene.objects = {{&ball, nullptr, glass, Transform{}, box, "glass"},
                   {&ball, nullptr, metal, moved, box, "metal"},
                   {&floor, nullptr, diffuse(0.7f), Transform{}, box, "floor"}};
  Light sphere_light, environment;
  sphere_light.kind = LightKind::kSphere;
  sphere_light.position = Vec3(-2, -3, 5);
  sphere_light.radius = 0.5f;
  sphere_light.power = Vec3::Constant(30);
  environment.kind = LightKind::kEnvironment;
  environment.power = Vec3::Constant(0.2f);
  scene.lights = {sphere_light, environment};
  RenderSettings s;
  s.width = 40, s.height = 30, s.spp = 3, s.bounces = 5;
  s.camera = Camera(Vec3(0, -7, 2), Vec3(0.5f, 0, -0.3f), Vec3::UnitZ(), 45, 40, 30);
  s.threads = 1;
  const RenderResult one = render(scene, s);
  s.threads = 2;
  const RenderResult two = render(scene, s);
  REQUIRE(one.image.pixels() == two.image.pixels());
  REQUIRE(one.counters.to_map() == two.counters.to_map());
  CHECK(one.counters.to_map().at("shadow_rays") > 0);
}
