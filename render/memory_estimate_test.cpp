#include "render/memory_estimate.hpp"

#include <catch2/catch.hpp>

#include "core/dataset.hpp"

namespace pcrt {

TEST_CASE("memory estimate: grows with N, counts normal estimation, MLS below splats") {
  const auto& splat = MethodRegistry::instance().get("reference_splat", "method");
  const auto& mls = MethodRegistry::instance().get("adamson_alexa_2003", "method");
  PointCloud with_normals = load_dataset("sphere:n=1000").cloud;
  PointCloud bare = with_normals;
  bare.normals.clear();
  const ParamValues p = resolve_params(splat.params, {}, "test");
  const size_t a = estimate_scene_bytes(splat, "kd_tree", with_normals, p);
  const size_t b = estimate_scene_bytes(splat, "kd_tree", bare, p);
  CHECK(a % 1000 == 0);
  CHECK(b - a == 1000 * (16 * sizeof(uint32_t) + 1 + sizeof(Vec3)));  // the k-NN graph, normal_k 16
  CHECK(estimate_scene_bytes(splat, "brute_force", with_normals, p) < a);
  const ParamValues q = resolve_params(mls.params, {}, "test");
  CHECK(estimate_scene_bytes(mls, "sphere_tree", with_normals, q) <
        estimate_scene_bytes(splat, "sphere_tree", with_normals, p));
  PointCloud twice = with_normals;
  twice.positions.insert(twice.positions.end(), with_normals.positions.begin(),
                         with_normals.positions.end());
  twice.normals.insert(twice.normals.end(), with_normals.normals.begin(),
                       with_normals.normals.end());
  CHECK(estimate_scene_bytes(splat, "kd_tree", twice, p) == 2 * a);
}

TEST_CASE("memory estimate: a method's own rule for its compressed variant") {
  const auto& hubo = MethodRegistry::instance().get("hubo_2006", "method");
  const PointCloud cloud = load_dataset("sphere:n=1000").cloud;
  const size_t plain = estimate_scene_bytes(hubo, "kd_tree", cloud, {});
  const size_t quantized = estimate_scene_bytes(hubo, "kd_tree", cloud, {{"quantized", 1}});
  CHECK(quantized == 1000 * 24);  // the quantized kd-tree alone, normals given
  CHECK(plain > 3 * quantized);
}

}  // namespace pcrt

namespace pcrt {

TEST_CASE("memory estimate: each structure's build peak holds at least its references") {
  const auto& splat = MethodRegistry::instance().get("reference_splat", "method");
  const PointCloud cloud = load_dataset("sphere:n=1000").cloud;
  const ParamValues p = resolve_params(splat.params, {}, "test");
  for (const char* s : {"brute_force", "sphere_tree", "bvh", "grid", "kd_tree", "octree"}) {
    INFO(s);
    CHECK(double(structure_bytes_per_item(s)) >=
          sizeof(uint32_t) * structure_references_per_item(s));
    CHECK(structure_references_per_item(s) >= 1);
    CHECK(estimate_scene_bytes(splat, s, cloud, p) -
              estimate_scene_bytes(splat, "brute_force", cloud, p) ==
          1000 * (structure_bytes_per_item(s) - structure_bytes_per_item("brute_force")));
  }
  // The structures that duplicate references hold more of them than the object partitions.
  CHECK(structure_references_per_item("kd_tree") > structure_references_per_item("bvh"));
  CHECK(structure_references_per_item("octree") > structure_references_per_item("sphere_tree"));
}

}  // namespace pcrt
