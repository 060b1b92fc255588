#include "methods/hubo_2006/quantized_kd_tree.hpp"

#include <catch2/catch.hpp>
#include <cmath>
#include <set>

#include "core/dataset.hpp"
#include "core/point_stream.hpp"
#include "preprocess/point_attributes.hpp"
#include "render/accuracy.hpp"
#include "render/scene.hpp"
#include "tests/test_paths.hpp"
#include "tests/variant_hits.hpp"

namespace pcrt {
namespace {

Aabb whole(const QuantizedKdTree& t) {
  Aabb b = t.bounds();
  b.lo -= Vec3::Constant(1);
  b.hi += Vec3::Constant(1);
  return b;
}

// Every point of `cloud` decodes from `tree` exactly once, within 0.01 h of its position and 0.1
// degrees of its normal (12 bits of a leaf box a few spacings wide; 12-bit octahedral normals).
void check_every_point_decodes_once(const QuantizedKdTree& tree, const PointCloud& cloud) {
  OpCounters c;
  std::vector<PackedSplat> all;
  tree.gather(whole(tree), all, c);
  REQUIRE(all.size() == cloud.size());
  std::set<uint32_t> ids;
  float worst_position = 0, worst_cos = 1;
  for (const PackedSplat& p : all) {
    ids.insert(p.index);
    worst_position = std::max(worst_position, (p.c - cloud.positions[p.index]).norm());
    worst_cos = std::min(worst_cos, p.n.dot(cloud.normals[p.index]));
  }
  CHECK(ids.size() == cloud.size());
  CHECK(worst_position < 0.01 * mean_spacing(cloud.positions, c));
  CHECK(worst_cos > std::cos(0.1 * 3.14159265358979 / 180));
  CHECK(c.get(kQkdPointsDecoded) == cloud.size());
}

}  // namespace

TEST_CASE("quantized kd-tree: every point decodes once, near its position and normal",
          "[quantized_kd_tree]") {
  const PointCloud cloud = load_dataset("torus:n=20000,seed=4").cloud;
  QuantizedKdTree tree;
  OpCounters c;
  tree.build(cloud.positions, cloud.normals, 8, c);
  check_every_point_decodes_once(tree, cloud);
  CHECK(double(tree.memory_bytes()) / double(cloud.size()) <= 16.0);
}

TEST_CASE("quantized kd-tree: a gather returns exactly the decoded points in its box",
          "[quantized_kd_tree]") {
  const PointCloud cloud = load_dataset("sphere:n=20000,seed=2").cloud;
  QuantizedKdTree tree;
  OpCounters c;
  tree.build(cloud.positions, cloud.normals, 8, c);
  std::vector<PackedSplat> all;
  tree.gather(whole(tree), all, c);
  for (const Vec3& centre : {Vec3(0, 0, 1), Vec3(0.6f, -0.5f, 0.3f), Vec3(0, 0, 0)}) {
    const Aabb box{centre - Vec3::Constant(0.1f), centre + Vec3::Constant(0.1f)};
    std::set<uint32_t> expected;
    for (const PackedSplat& p : all)
      if ((p.c.array() >= box.lo.array()).all() && (p.c.array() <= box.hi.array()).all())
        expected.insert(p.index);
    std::vector<PackedSplat> got;
    tree.gather(box, got, c);
    std::set<uint32_t> ids;
    for (const PackedSplat& p : got) ids.insert(p.index);
    CHECK(ids == expected);
    CHECK(got.size() == ids.size());
  }
}

TEST_CASE("quantized kd-tree: the walk reaches every point within reach of the ray",
          "[quantized_kd_tree]") {
  const PointCloud cloud = load_dataset("sphere:n=5000,seed=1").cloud;
  QuantizedKdTree tree;
  OpCounters c;
  tree.build(cloud.positions, cloud.normals, 4, c);
  std::vector<PackedSplat> all;
  tree.gather(whole(tree), all, c);
  const float reach = 0.05f;
  for (const Vec3& d : {Vec3(1, 0.2f, 0.1f), Vec3(0, 0, -1), Vec3(-0.3f, 1, 0.5f)}) {
    const Ray ray{Vec3(0.1f, -0.2f, 0.05f) - 3 * d.normalized(), d.normalized()};
    const float stop = kInfinity;
    std::vector<std::pair<float, float>> pieces;
    tree.walk(
        ray, reach, &stop, [&](float t0, float t1) { pieces.emplace_back(t0, t1); }, c);
    size_t near = 0;
    for (const PackedSplat& p : all) {
      const float along = (p.c - ray.o).dot(ray.d);
      if ((ray.at(along) - p.c).norm() >= reach) continue;
      ++near;
      bool covered = false;
      for (const auto& [t0, t1] : pieces) covered |= t0 <= along && along <= t1;
      INFO("point " << p.index << " at t " << along);
      CHECK(covered);
    }
    CHECK(near > 0);
  }
}

// The compression's accuracy loss against the uncompressed method, on the accuracy harness's rays:
// the same surface within a small fraction of the spacing.
TEST_CASE("hubo_2006 quantized finds the uncompressed method's hits", "[quantized_kd_tree]") {
  const auto v = test::compare_variant_hits("sphere:n=20000,seed=3", "hubo_2006",
                                            {{"quantized", 1}}, 0.05, 3000);
  INFO("apart " << v.far << " of " << v.both);
  CHECK(v.both > 1000);
  CHECK(v.one <= 3000 / 500);
  CHECK(v.far <= v.both / 200);
}

// The streamed build (never the whole cloud in float) against the in-memory one on the same
// points: every point once, as near its position, the same bytes a point; the spacing sampled
// from the tree near the whole cloud's mean.
TEST_CASE("quantized kd-tree: a streamed build holds every streamed point", "[quantized_kd_tree]") {
  const char* spec = "torus:n=60000,seed=5,noise=0.002";
  const PointCloud cloud = load_dataset_in_input_order(spec).cloud;
  const auto stream = open_point_stream(spec);
  QuantizedKdTree tree, reference;
  OpCounters c;
  tree.build(*stream, 8, c);
  reference.build(cloud.positions, cloud.normals, 8, c);
  check_every_point_decodes_once(tree, cloud);
  const double h = mean_spacing(cloud.positions, c);
  CHECK(tree.memory_bytes() == reference.memory_bytes());
  CHECK(tree.bounds().lo == reference.bounds().lo);
  CHECK(tree.bounds().hi == reference.bounds().hi);
  // Every point sampled, then one in 30: within 1% and 3% of the whole cloud's mean spacing.
  CHECK(std::abs(tree.sampled_mean_spacing(cloud.size(), c) / h - 1) < 0.01);
  CHECK(std::abs(tree.sampled_mean_spacing(2000, c) / h - 1) < 0.03);
}

// A stream keeps exact duplicates (it cannot drop them without holding the cloud): the spacing
// sample must not decode a run of identical points once per sample (50 000 of them took 30 s).
TEST_CASE("quantized kd-tree: sampling the spacing of identical points is linear",
          "[quantized_kd_tree]") {
  const size_t n = 20000;
  std::vector<Vec3> positions(n, Vec3(0.5f, 0.25f, 1.0f)), normals(n, Vec3::UnitZ());
  positions[0] = Vec3(0, 0, 0), positions[1] = Vec3(1, 0, 0);
  QuantizedKdTree tree;
  OpCounters c;
  tree.build(positions, normals, 8, c);
  OpCounters sampling;
  // Two of the samples are the distinct points (at 0.5 or more from the rest), the rest 0.
  const double h = tree.sampled_mean_spacing(n, sampling);
  CHECK(h > 0);
  CHECK(h < 2.5 / double(n));
  INFO(sampling.get(kQkdPointsDecoded) << " points decoded for " << n << " samples");
  CHECK(sampling.get(kQkdPointsDecoded) < 10 * n);
}

// hubo_2006 quantized prepared twice from `spec`: from the whole cloud and from its stream.
struct QuantizedBothWays {
  explicit QuantizedBothWays(const std::string& spec)
      : d(load_dataset(spec)),
        stream(open_point_stream(spec)),
        h(mean_spacing(d.cloud.positions, c)),
        whole(d.cloud, options(), c, t),
        streamed(*stream, options(), c, t) {}
  static SceneOptions options() { return {"hubo_2006", "", {{"quantized", 1}}}; }

  OpCounters c;
  Timings t;
  Dataset d;
  std::unique_ptr<PointStream> stream;
  double h;  // the whole cloud's mean spacing
  PointScene whole, streamed;
};

// What `pcrt render --stream` traces: hubo_2006 prepared from the stream finds the hits of the
// same method prepared from the whole cloud (its spacing h sampled, not averaged over all).
TEST_CASE("hubo_2006 quantized from a stream finds the in-memory hits", "[quantized_kd_tree]") {
  QuantizedBothWays q("sphere:n=20000,seed=3");
  const auto [both, one, far] =
      test::compare_scene_hits(q.whole, q.streamed, accuracy_rays(*q.d.truth, q.h, 3000, 5),
                               test::apart_along_normal(0.01 * q.h));
  INFO("one-sided " << one << ", apart " << far << " of " << both);
  CHECK(both > 1000);
  CHECK(one <= 3);
  CHECK(far <= both / 200);
  const SceneOptions plain{"reference_splat", "", {}};
  REQUIRE_THROWS_WITH(PointScene(*q.stream, plain, q.c, q.t),
                      Catch::Matchers::Contains("does not prepare from a stream"));
}

// Real scans (CGAL's binary PLYs and XYZ/PWN text with normals), streamed and read whole: rays
// from around the scan towards every tenth point find the same surface.
TEST_CASE("hubo_2006 quantized streamed from a real scan finds the whole-read hits",
          "[quantized_kd_tree]") {
  const std::filesystem::path dir = test::data_dir() / "cgal" / "points_3";
  if (!std::filesystem::exists(dir / "oni.ply"))
    PCRT_SKIP("data/ not fetched (scripts/fetch_data.sh)");
  for (const char* name : {"oni.ply", "hippo1.ply", "oni.pwn", "kitten.xyz", "cube.pwn"}) {
    const std::string path = (dir / name).string();
    INFO(path);
    QuantizedBothWays q(path);
    const Aabb box = q.d.cloud.bounds();
    std::vector<Ray> towards;
    for (size_t i = 0; i < q.d.cloud.size(); i += 10) {
      const Vec3 p = q.d.cloud.positions[i];
      const Vec3 from = box.center() + box.diagonal() * (p - box.center()).normalized() * 2;
      towards.push_back(Ray{from, (p - from).normalized()});
    }
    const size_t rays = towards.size();
    const auto [both, one, far] = test::compare_scene_hits(
        q.whole, q.streamed, towards,
        [&](const Hit& a, const Hit& b) { return std::abs(a.t - b.t) > 0.05 * q.h; });
    INFO("one-sided " << one << ", apart " << far << " of " << both << " (" << rays << " rays)");
    CHECK(both > rays / 2);
    CHECK(one <= rays / 200);
    CHECK(far <= both / 200);
  }
}

}  // namespace pcrt
