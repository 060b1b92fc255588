// The accuracy bounds of the method issues, checked for every registered method on the default
// sphere and torus of 10^5 points. A method that cannot meet a bound as its paper describes it is
// listed below with the bound it misses and why; the test checks that it still misses exactly
// that one (so a fix shows up, and nothing else slips).
#include "render/accuracy.hpp"

#include <catch2/catch.hpp>
#include <map>
#include <set>

#include "core/dataset.hpp"
#include "core/rng.hpp"
#include "preprocess/point_attributes.hpp"
#include "render/scene.hpp"

using namespace pcrt;

namespace {

// The exact surface as an intersector: the evaluator must find it perfect.
struct ExactScene final : SceneIntersector {
  const Surface& s;
  explicit ExactScene(const Surface& surface) : s(surface) {}
  bool closest_hit(const Ray& ray, Hit& hit, OpCounters&) const override {
    float t = 0;
    Vec3 n;
    if (!s.intersect(ray, t, n) || t >= hit.t) return false;
    hit = Hit{t, ray.at(t), n, 0, 0};
    return true;
  }
};

std::set<std::string> missed_bounds(const AccuracyReport& r) {
  const AccuracyBounds b;
  std::set<std::string> m;
  if (r.hole_rate > b.max_hole_rate) m.insert("holes");
  if (r.false_hit_rate > b.max_false_hit_rate) m.insert("false hits");
  if (!(r.distance_median_h <= b.max_distance_median_h)) m.insert("distance median");
  if (!(r.distance_p95_h <= b.max_distance_p95_h)) m.insert("distance p95");
  if (!(r.normal_median_deg <= b.max_normal_median_deg)) m.insert("normal median");
  return m;
}

// The bounds a method declares it misses on a shape (MethodInfo::accuracy_misses).
std::set<std::string> declared_misses(const MethodInfo& m, const std::string& dataset) {
  std::set<std::string> out;
  for (const auto& miss : m.accuracy_misses)
    if (miss.dataset == dataset) out.insert(miss.bound);
  return out;
}

}  // namespace

TEST_CASE("the accuracy evaluator finds the exact surface perfect", "[accuracy]") {
  for (const char* spec : {"sphere:n=100000", "torus:n=100000"}) {
    const Dataset d = load_dataset(spec);
    const double h = 0.005;
    const auto rays = accuracy_rays(*d.truth, h, 4000, 1);
    OpCounters c;
    const AccuracyReport r = evaluate_accuracy(ExactScene(*d.truth), *d.truth, h, rays, c);
    INFO(spec);
    REQUIRE(r.judged_hits > 2000);
    REQUIRE(r.judged_misses > 50);
    REQUIRE(r.holes == 0);
    REQUIRE(r.false_hits == 0);
    REQUIRE(r.distance_p95_h < 1e-2);
    REQUIRE(r.normal_p95_deg < 0.1);
  }
}

TEST_CASE("every method meets the accuracy bounds or misses exactly its documented ones",
          "[accuracy][methods][slow]") {
  for (const char* name : {"sphere", "torus"}) {
    const Dataset d = load_dataset(std::string(name) + ":n=100000");
    OpCounters c;
    const KnnIndex knn(d.cloud.positions);
    const double h = mean_spacing(d.cloud.positions, knn, c);
    const auto rays = accuracy_rays(*d.truth, h, 10000, 7);
    for (const MethodInfo& m : MethodRegistry::instance().all()) {
      Timings t;
      // The oracle's default structure is brute force; the kd-tree gives it the same hits faster.
      const std::string structure = m.structure == "brute_force" ? "kd_tree" : "";
      const PointScene scene(d.cloud, SceneOptions{m.id, structure, {}}, c, t);
      const AccuracyReport r = evaluate_accuracy(scene, *d.truth, h, rays, c);
      INFO(m.id << " on " << name << ": holes " << r.hole_rate << ", false hits "
                << r.false_hit_rate << ", distance median " << r.distance_median_h << " h, p95 "
                << r.distance_p95_h << " h, normal median " << r.normal_median_deg << " deg");
      REQUIRE(missed_bounds(r) == declared_misses(m, name));
    }
  }
}

// The implicit octree's grid starts at the cloud's bounds, so a flat face at the bounds (the
// blade's base) lies on a plane of cell corners: its root sits between one cell's exit and the
// next one's entry, and rounding once gave both the same sign (2.9% of the blade's rays went
// through the base; here about 90% of the rays missed the face).
TEST_CASE("the implicit octree finds a flat face lying on its grid planes", "[accuracy][methods]") {
  const float z = 1.43743f, h = 0.08f;  // the blade's base and spacing
  PointCloud slab;
  for (int layer = 0; layer < 2; ++layer)  // the base (facing down) and a top 8h above it
    for (int i = 0; i < 200; ++i)
      for (int j = 0; j < 200; ++j) {
        slab.positions.emplace_back(-8.0f + h * float(i), 20.0f + h * float(j),
                                    z + 8 * h * float(layer));
        slab.normals.emplace_back(0.0f, 0.0f, layer ? 1.0f : -1.0f);
      }
  OpCounters c;
  Timings t;
  const PointScene scene(slab, SceneOptions{"kashyap_2010_implicit", "", {}}, c, t);
  Rng rng(5, 0);
  int on_base = 0;
  const int rays = 500;
  for (int i = 0; i < rays; ++i) {  // from far below, aimed at the base's middle, tilted
    const Vec3 target(-8.0f + h * (50 + 100 * rng.uniform()),
                      20.0f + h * (50 + 100 * rng.uniform()), z);
    const Vec3 origin = target + Vec3(-180.0f + 40 * rng.uniform(), 20 * rng.uniform(), -70.0f);
    const Ray ray{origin, (target - origin).normalized()};
    Hit hit;
    on_base += scene.closest_hit(ray, hit, c) && std::abs(hit.p.z() - z) < 0.1f * h;
  }
  CHECK(on_base == rays);
}

namespace {

// The plane z = 0 over [-1, 1]^2 with a crease declared along x = 0: the normal spread answers as
// the Surface contract says, for the ball of `radius` around the point nearest x.
struct CreasedPlane final : Surface {
  [[nodiscard]] std::string describe() const override { return "creased plane"; }
  [[nodiscard]] float signed_distance(const Vec3& x) const override { return x.z(); }
  [[nodiscard]] Vec3 normal(const Vec3&) const override { return Vec3::UnitZ(); }
  [[nodiscard]] Aabb bounds() const override { return Aabb{Vec3(-1, -1, 0), Vec3(1, 1, 0)}; }
  Vec3 sample(Rng& rng, Vec3& n) const override {
    n = Vec3::UnitZ();
    return Vec3(2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 0);
  }
  bool intersect(const Ray& ray, float& t, Vec3& n) const override {
    if (ray.d.z() == 0) return false;
    t = -ray.o.z() / ray.d.z();
    n = Vec3::UnitZ();
    return t >= ray.tmin && t <= ray.tmax;
  }
  [[nodiscard]] float normal_spread_deg(const Vec3& x, float radius) const override {
    return std::abs(x.x()) > radius ? 0.0f : 90.0f;
  }
};

// A sheet z = height over x in [x0, x1]: every hit on it is a phantom above the plane.
struct FloatingSheet final : SceneIntersector {
  float x0, x1, height;
  FloatingSheet(float a, float b, float z) : x0(a), x1(b), height(z) {}
  bool closest_hit(const Ray& ray, Hit& hit, OpCounters&) const override {
    const float t = (height - ray.o.z()) / ray.d.z();
    const Vec3 p = ray.at(t);
    if (!(t > 0 && t < hit.t && p.x() >= x0 && p.x() <= x1)) return false;
    hit = Hit{t, p, Vec3::UnitZ(), 0, 0};
    return true;
  }
};

}  // namespace

// Issue 30: a phantom 20 h above the plane, over a point 7.5 h from the crease, is not near it
// (3.5 h of its nearest surface point); the old rule looked |d| + 3.5 h = 23.5 h around it.
TEST_CASE("the evaluator judges a phantom's crease at its nearest surface point", "[accuracy]") {
  const float h = 0.01f;
  const CreasedPlane truth;
  OpCounters c;
  for (const auto& [x, near] : {std::pair{7.5f * h, false}, std::pair{2.0f * h, true}}) {
    INFO("phantoms over x = " << x / h << " h");
    const FloatingSheet sheet(x - 0.5f * h, x + 0.5f * h, 20 * h);
    std::vector<Ray> rays;
    for (int i = 0; i < 10; ++i) rays.push_back(Ray{Vec3(x, 0.05f * float(i), 1), Vec3(0, 0, -1)});
    const AccuracyReport r = evaluate_accuracy(sheet, truth, h, rays, c);
    REQUIRE(r.phantom == 10);
    CHECK(r.phantom_near_crease == (near ? 10u : 0u));
  }
}
