// The mesh ground truth: distances, normals, sampling, first hits and smoothness on a box whose
// answers are known, and the evaluator's false-hit causes on a plate with one face removed.
#include "reconstruction/mesh_surface.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <tuple>

#include "core/error.hpp"
#include "core/morton.hpp"
#include "render/accuracy.hpp"
#include "render/mesh_truth.hpp"
#include "render/scene.hpp"

using namespace pcrt;

namespace {

// An axis-aligned box [lo, hi] as 12 triangles facing inward when `inward` (the surface must
// orient it outward itself).
TriangleMesh box_mesh(const Vec3& lo, const Vec3& hi, bool inward) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(),
                            i & 4 ? hi.z() : lo.z());
  // Outward quads (counter-clockwise seen from outside), each as two triangles.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({uint32_t(q[0]), uint32_t(q[1]), uint32_t(q[2])});
    m.triangles.push_back({uint32_t(q[0]), uint32_t(q[2]), uint32_t(q[3])});
  }
  if (inward)
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

}  // namespace

TEST_CASE("A mesh surface answers distances, normals, samples and hits of a box", "[mesh_truth]") {
  const MeshSurface s(box_mesh(Vec3(0, 0, 0), Vec3(2, 1, 1), true), "box", "bvh");
  CHECK(s.area() == Approx(2 * (2 + 2 + 1)));
  CHECK(s.signed_distance(Vec3(1, 0.5f, 1.5f)) == Approx(0.5f));
  CHECK(s.signed_distance(Vec3(1, 0.5f, 0.8f)) == Approx(-0.2f));
  CHECK(s.normal(Vec3(1, 0.5f, 1.5f)).isApprox(Vec3::UnitZ()));  // flipped outward
  Rng rng(7);
  for (int i = 0; i < 200; ++i) {
    Vec3 n;
    const Vec3 x = s.sample(rng, n);
    REQUIRE(std::abs(s.signed_distance(x)) < 1e-5f);
    REQUIRE(n.isApprox(s.normal(x)));
  }
  float t = 0;
  Vec3 n;
  REQUIRE(s.intersect(Ray{Vec3(1, 0.5f, 5), Vec3(0, 0, -1)}, t, n));
  CHECK(t == Approx(4.0f));
  CHECK(std::abs(n.z()) == Approx(1.0f));
  CHECK_FALSE(s.intersect(Ray{Vec3(1, 0.5f, 5), Vec3(0, 0, 1)}, t, n));
  CHECK(s.smooth_at(Vec3(1, 0.5f, 1), 0.1f));            // a face's middle
  CHECK_FALSE(s.smooth_at(Vec3(1.95f, 0.5f, 1), 0.1f));  // 0.05 from an edge
}

TEST_CASE("A mesh of zero area is refused naming it", "[mesh_truth]") {
  TriangleMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  m.triangles = {{0, 1, 2}};
  REQUIRE_THROWS_WITH(MeshSurface(m, "flat.off", "bvh"), Catch::Contains("flat.off"));
}

TEST_CASE("Sampling specs parse and bad ones name the spec", "[mesh_truth]") {
  const MeshSampling s = parse_mesh_sampling("n=500,noise=0.5,normals=none,density=0.3");
  CHECK(s.n == 500);
  CHECK(s.noise_h == 0.5);
  CHECK(s.density == 0.3);
  CHECK(s.normals == NormalSource::kNone);
  CHECK(parse_mesh_sampling("").n == 100000);
  for (const char* bad : {"n=5", "normals=maybe", "noise=-1", "colour=2", "n=100,n=200", "n"})
    REQUIRE_THROWS_WITH(parse_mesh_sampling(bad), Catch::Contains(bad));
}

TEST_CASE("Sampled clouds: noise in units of h, estimated or absent normals", "[mesh_truth]") {
  const MeshSurface s(box_mesh(Vec3(0, 0, 0), Vec3(2, 1, 1), false), "box", "bvh");
  OpCounters c;
  MeshSampling spec = parse_mesh_sampling("n=4000,noise=0.5");
  const SampledCloud noisy = sample_cloud(s, spec, "box", c);
  double sq = 0;
  for (const Vec3& x : noisy.cloud.positions) sq += std::pow(s.signed_distance(x), 2);
  // Away from edges the distance is the noise's normal component: standard deviation 0.5 h.
  CHECK(std::sqrt(sq / 4000) / noisy.spacing == Approx(0.5).epsilon(0.15));
  spec.normals = NormalSource::kEstimated;
  spec.noise_h = 0;
  const SampledCloud est = sample_cloud(s, spec, "box", c);
  size_t aligned = 0;
  for (size_t i = 0; i < est.cloud.size(); ++i)
    aligned += std::abs(est.cloud.normals[i].dot(s.normal(est.cloud.positions[i]))) > 0.95f;
  CHECK(aligned > 3200);  // PCA normals agree except within a few spacings of the 12 edges
  spec.normals = NormalSource::kNone;
  CHECK_FALSE(sample_cloud(s, spec, "box", c).cloud.has_normals());
}

TEST_CASE("Sampled clouds are Morton-ordered like loaded ones, noisy or not", "[mesh_truth]") {
  const MeshSurface s(box_mesh(Vec3(0, 0, 0), Vec3(2, 1, 1), false), "box", "bvh");
  OpCounters c;
  for (const char* spec : {"n=3000", "n=3000,noise=0.5", "n=3000,noise=0.3,normals=estimated"}) {
    INFO(spec);
    const SampledCloud sampled = sample_cloud(s, parse_mesh_sampling(spec), "box", c);
    const std::vector<uint32_t> order = morton_order(sampled.cloud.positions);
    size_t in_place = 0;
    for (size_t k = 0; k < order.size(); ++k) in_place += order[k] == k;
    CHECK(in_place == sampled.cloud.size());
  }
}

TEST_CASE("The evaluator splits false hits into see-through, early and phantom", "[mesh_truth]") {
  // Truth: a plate 1 thick. Judged: the same plate traced exactly (perfect), then only its back
  // half-space's face (every front hit becomes see-through).
  const auto truth = std::make_shared<MeshSurface>(box_mesh(Vec3(0, 0, 0), Vec3(10, 10, 1), false),
                                                   "plate", "bvh");
  const double h = 0.02;
  const auto rays = accuracy_rays(*truth, h, 2000, 3);
  OpCounters prep, c;
  Timings timings;
  const MeshScene exact(truth->mesh(), "bvh", prep, timings);
  const AccuracyReport perfect = evaluate_accuracy(exact, *truth, h, rays, c);
  CHECK(perfect.false_hits == 0);
  CHECK(perfect.holes == 0);
  CHECK(perfect.distance_median_h < 1e-3);

  // A scene that sees only the bottom face z = 0: rays from above pass the top face.
  TriangleMesh bottom = truth->mesh();
  std::erase_if(bottom.triangles, [&](const auto& t) {
    return bottom.vertices[t[0]].z() + bottom.vertices[t[1]].z() + bottom.vertices[t[2]].z() > 0;
  });
  const MeshScene back(bottom, "bvh", prep, timings);
  const AccuracyReport r = evaluate_accuracy(back, *truth, h, rays, c);
  CHECK(r.see_through > 100);
  CHECK(r.see_through_smooth > 0);
  CHECK(r.phantom == 0);
  CHECK(r.early == 0);
}

TEST_CASE("Secondary rays: a mesh against itself is exact, a plate without its top misses it",
          "[mesh_truth]") {
  const auto truth = std::make_shared<MeshSurface>(box_mesh(Vec3(0, 0, 0), Vec3(10, 10, 1), false),
                                                   "plate", "bvh");
  OpCounters prep, c;
  Timings timings;
  const MeshScene exact(truth->mesh(), "bvh", prep, timings);
  const SecondaryReport same = evaluate_secondary(exact, *truth, 0.02, 2000, 5, c);
  CHECK(same.outward.rays + same.inward.rays > 1900);
  CHECK(same.outward.self_hits + same.inward.self_hits == 0);
  CHECK(same.outward.missed_occluders + same.inward.missed_occluders == 0);
  CHECK(same.outward.false_occluders + same.inward.false_occluders == 0);

  TriangleMesh bottom = truth->mesh();
  std::erase_if(bottom.triangles, [&](const auto& t) {
    return bottom.vertices[t[0]].z() + bottom.vertices[t[1]].z() + bottom.vertices[t[2]].z() > 0;
  });
  const MeshScene back(bottom, "bvh", prep, timings);
  const SecondaryReport r = evaluate_secondary(back, *truth, 0.02, 2000, 5, c);
  // Inward rays leaving the bottom face meet the missing top: missed occluders.
  CHECK(r.inward.missed_occluders > 300);
  CHECK(r.outward.self_hits == 0);
}

namespace {

// A flat square z = 0 and a small fin at right angles to it (normal along y) whose nearest point
// to p is p + offset * (1, 1, 1): |offset| * sqrt(3) away, inside the cube of half side |offset|.
TriangleMesh plane_with_fin(const Vec3& p, float offset, float h) {
  TriangleMesh m;
  m.vertices = {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  const Vec3 c = p + Vec3::Constant(offset);
  m.vertices.insert(m.vertices.end(), {c, c + Vec3(0.3f * h, 0, 0), c + Vec3(0, 0, 0.3f * h)});
  m.triangles.push_back({4, 5, 6});
  return m;
}

// One ray straight down onto p, judged against the truth traced exactly.
AccuracyReport judge_down(const MeshSurface& truth, const Vec3& p, double h) {
  OpCounters prep, c;
  Timings timings;
  const MeshScene exact(truth.mesh(), "bvh", prep, timings);
  return evaluate_accuracy(exact, truth, h, {Ray{p + Vec3(0, 0, 1), Vec3(0, 0, -1)}}, c);
}

// Two triangles z = z0 over [x0, x1] x [4, 6]: a sheet floating above a 10 x 10 plate.
TriangleMesh sheet(float x0, float x1, float z0) {
  TriangleMesh m;
  m.vertices = {Vec3(x0, 4, z0), Vec3(x1, 4, z0), Vec3(x1, 6, z0), Vec3(x0, 6, z0)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

}  // namespace

// Issue 30: "a crease within 3.5 h" is a ball, not CGAL's box query (which reaches 3.5 h sqrt(3)
// = 6.1 h along a diagonal). The fin stands 5.2 h away on the diagonal: inside the box only.
TEST_CASE("The crease neighbourhood is a ball of 3.5 h, not a box", "[mesh_truth][accuracy]") {
  const float h = 0.01f, reach = FeatureSplit::kFeatureReachH * h;
  const Vec3 p(0.25f, -0.25f, 0);  // off the square's diagonal seam
  const MeshSurface far(plane_with_fin(p, 3.0f * h, h), "fin at 5.2 h", "bvh");
  const MeshSurface near(plane_with_fin(p, 1.5f * h, h), "fin at 2.6 h", "bvh");
  CHECK(far.smooth_at(p, reach));
  CHECK_FALSE(near.smooth_at(p, reach));
  const AccuracyReport r_far = judge_down(far, p, h), r_near = judge_down(near, p, h);
  REQUIRE(r_far.judged_hits == 1);
  CHECK(r_far.judged_split.crease == 0);
  CHECK(r_far.judged_split.open == 1);
  REQUIRE(r_near.judged_hits == 1);
  CHECK(r_near.judged_split.crease == 1);
}

// Issue 30: a phantom is near a crease when one lies within 3.5 h of the phantom's nearest surface
// point, not within |d| + 3.5 h of the phantom itself. Sheets 20 h above a plate's top face stand
// over points 7.5 h (not near) and 2 h (near) from its edge x = 10.
TEST_CASE("Phantoms are judged near a crease at their nearest surface point",
          "[mesh_truth][accuracy]") {
  const float h = 0.02f;
  const MeshSurface truth(box_mesh(Vec3(0, 0, 0), Vec3(10, 10, 1), false), "plate", "bvh");
  OpCounters prep, c;
  Timings timings;
  for (const auto& [x0, x1, near] :
       {std::tuple{10 - 10 * h, 10 - 5 * h, false}, std::tuple{10 - 3 * h, 10 - 1 * h, true}}) {
    INFO("sheet over x in [" << x0 << ", " << x1 << "]");
    const TriangleMesh floating = sheet(x0, x1, 1 + 20 * h);
    const MeshScene scene(floating, "bvh", prep, timings);
    std::vector<Ray> rays;
    for (int i = 0; i < 10; ++i)
      rays.push_back(Ray{Vec3(0.5f * (x0 + x1), 4.5f + 0.1f * float(i), 5), Vec3(0, 0, -1)});
    const AccuracyReport r = evaluate_accuracy(scene, truth, h, rays, c);
    REQUIRE(r.phantom == 10);
    CHECK(r.phantom_near_crease == (near ? 10u : 0u));
  }
}

namespace {

// A valley: a strip z = 0 for |x| <= h between two faces rising at 10 degrees on either side.
// Each side is 10 degrees from the strip and 20 degrees from the other side.
TriangleMesh valley(float h) {
  const float rise = (1 - h) * std::tan(float(10 * M_PI / 180));
  TriangleMesh m;
  for (const float y : {-1.0f, 1.0f})
    m.vertices.insert(m.vertices.end(),
                      {Vec3(-1, y, rise), Vec3(-h, y, 0), Vec3(h, y, 0), Vec3(1, y, rise)});
  for (uint32_t i = 0; i < 3; ++i) {  // the quad between columns i and i + 1
    m.triangles.push_back({i, i + 1, i + 5});
    m.triangles.push_back({i, i + 5, i + 4});
  }
  return m;
}

}  // namespace

// Issue 30: the normal spread is the widest pair of faces in the ball, not the widest angle to
// the nearest face: the valley floor is a 20-degree crease though no face is 15 degrees off it.
TEST_CASE("The normal spread is the widest pair of faces within the ball",
          "[mesh_truth][accuracy]") {
  const float h = 0.01f, reach = FeatureSplit::kFeatureReachH * h;
  const MeshSurface v(valley(h), "valley", "bvh");
  CHECK(v.normal_spread_deg(Vec3(0, 0.1f, 0), reach) == Approx(20.0f).margin(0.01));
  CHECK_FALSE(v.smooth_at(Vec3(0, 0.1f, 0), reach));
  CHECK(v.normal_spread_deg(Vec3(0.5f, 0.1f, 0.1f), reach) == Approx(0.0f).margin(0.01));
  const MeshSurface box(box_mesh(Vec3(0, 0, 0), Vec3(2, 1, 1), false), "box", "bvh");
  CHECK(box.normal_spread_deg(Vec3(1, 0.5f, 1), 0.1f) == Approx(0.0f).margin(0.01));
  CHECK(box.normal_spread_deg(Vec3(1.95f, 0.5f, 1), 0.1f) == Approx(90.0f).margin(0.01));
}

namespace {

size_t sum_thin_hits(const AccuracyReport& r) {
  size_t n = 0;
  for (const SpreadBand& b : r.spread_bands) n += b.thin_hits;
  return n;
}

}  // namespace

// Every judged hit is in one band of the normal spread, and so is every failure on a ray that hits
// the surface; a box has faces 0 or 90 degrees apart, nothing between.
TEST_CASE("Judged hits and failures are counted by the normal spread at the exact hit",
          "[mesh_truth][accuracy]") {
  const auto truth = std::make_shared<MeshSurface>(box_mesh(Vec3(0, 0, 0), Vec3(10, 10, 1), false),
                                                   "plate", "bvh");
  const double h = 0.02;
  const auto rays = accuracy_rays(*truth, h, 2000, 3);
  TriangleMesh bottom = truth->mesh();
  std::erase_if(bottom.triangles, [&](const auto& t) {
    return bottom.vertices[t[0]].z() + bottom.vertices[t[1]].z() + bottom.vertices[t[2]].z() > 0;
  });
  OpCounters prep, c;
  Timings timings;
  const MeshScene back(bottom, "bvh", prep, timings);
  const AccuracyReport r = evaluate_accuracy(back, *truth, h, rays, c);
  SpreadBand sum;
  for (const SpreadBand& b : r.spread_bands) {
    sum.judged_hits += b.judged_hits, sum.holes += b.holes, sum.see_through += b.see_through;
    sum.early += b.early, sum.phantom += b.phantom;
  }
  CHECK(sum.judged_hits == r.judged_hits);
  CHECK(sum.holes == r.holes);
  CHECK(sum.see_through == r.see_through);
  CHECK(r.spread_bands.front().lo_deg == 0);
  CHECK(r.spread_bands.back().hi_deg == 180);
  CHECK(r.spread_bands[0].see_through > 100);  // the missing top face, away from its edges
  CHECK(r.spread_bands[4].judged_hits > 0);    // within 3.5 h of the plate's edges
  for (size_t k = 1; k < 4; ++k) CHECK(r.spread_bands[k].judged_hits == 0);
  CHECK(r.spread_bands[4].judged_hits == r.judged_split.crease);
  CHECK(sum_thin_hits(r) == 0);  // the plate is 50 h thick
  // At h = 0.2 the plate is 5 h thick, a thin wall: the failures of its missing top (see-through
  // to the bottom, holes where a slanted ray leaves through the missing sides) are counted on it,
  // in the band of its flat faces.
  const AccuracyReport coarse = evaluate_accuracy(back, *truth, 0.2, rays, c);
  REQUIRE(coarse.judged_split.thin > 100);
  CHECK(sum_thin_hits(coarse) == coarse.judged_split.thin);
  CHECK(coarse.spread_bands[0].see_through > 100);
  CHECK(coarse.spread_bands[0].thin_failures == coarse.spread_bands[0].failures());
  CHECK(coarse.spread_bands[4].thin_hits == 0);  // a crease comes before a thin wall
}

// Issue 30: on a flat face the normal field sees no curvature, so linsen_2007's radius rule alone
// grows each splat to max_radius_scale cover radii (about 6 h here), and those within that reach
// of a 90-degree edge overhang it into empty space, where rays coming up the side face stop. The
// radius is cut at the nearest covered point off the splat's plane, so the box meets the 1% bound
// (phantoms 257 of 3697 judged hits before the cut, 17 after).
TEST_CASE("linsen_2007's splats stop at an edge their curvature fit cannot see",
          "[mesh_truth][accuracy][methods]") {
  const MeshSurface box(box_mesh(Vec3(0, 0, 0), Vec3(2, 1, 1), false), "box", "bvh");
  OpCounters prep, c;
  Timings timings;
  MeshSampling sampling;
  sampling.n = 30000;
  const SampledCloud sampled = sample_cloud(box, sampling, "box", prep);
  const PointScene scene(sampled.cloud, SceneOptions{"linsen_2007", "", {}}, prep, timings);
  const auto rays = accuracy_rays(box, sampled.spacing, 4000, 5);
  const AccuracyReport r = evaluate_accuracy(scene, box, sampled.spacing, rays, c);
  INFO("phantoms " << r.phantom << ", early " << r.early << " of " << r.judged_hits);
  REQUIRE(r.judged_hits > 2000);
  CHECK(prep.to_map()["splats_cut_by_cover"] > 1000);
  CHECK(r.phantom_rate() < 0.01);
}
