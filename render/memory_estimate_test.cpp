#include "render/memory_estimate.hpp"

#include <catch2/catch.hpp>

#include "core/dataset.hpp"
#include "methods/kernels/splat_blocks.hpp"

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
  // With the same (item-order) disc layout, brute force's one index per point is the least; by
  // default it copies the discs in leaf order (one reference per item), the kd-tree does not.
  const ParamValues item_order = resolve_params(splat.params, {{"disc_blocks", 2}}, "test");
  CHECK(estimate_scene_bytes(splat, "brute_force", with_normals, item_order) <
        estimate_scene_bytes(splat, "kd_tree", with_normals, item_order));
  CHECK(estimate_scene_bytes(splat, "brute_force", with_normals, p) >
        estimate_scene_bytes(splat, "brute_force", with_normals, item_order));
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
  CHECK(plain >
        2 * quantized);  // 70 against 24 B/point (measured at 10^7: 89 and 45 with the cloud)
}

}  // namespace pcrt

namespace pcrt {

TEST_CASE("memory estimate: the disc blocks' layout prices its copy") {
  const auto& splat = MethodRegistry::instance().get("reference_splat", "method");
  const PointCloud cloud = load_dataset("sphere:n=1000").cloud;
  const auto with_layout = [&](DiscBlockLayout l) {
    return resolve_params(splat.params, {{"disc_blocks", double(l)}}, "test");
  };
  for (const StructureInfo& info : StructureRegistry::instance().all()) {
    const std::string& s = info.id;
    INFO(s);
    REQUIRE(info.footprint);  // every structure declares what it costs
    const StructureFootprint f = structure_footprint(s);
    CHECK(f.references_per_item >= 1);
    // A leaf-order copy holds at least a 28-byte disc per reference beyond the references.
    CHECK((f.leaf_order >= f.item_order || f.references_per_item <= 1.0));
    const size_t leaf =
        estimate_scene_bytes(splat, s, cloud, with_layout(DiscBlockLayout::kLeafOrder));
    const size_t item =
        estimate_scene_bytes(splat, s, cloud, with_layout(DiscBlockLayout::kItemOrder));
    const size_t automatic =
        estimate_scene_bytes(splat, s, cloud, with_layout(DiscBlockLayout::kAuto));
    CHECK(leaf - item == 1000 * (f.leaf_order - f.item_order));
    const bool leaf_chosen =
        SplatLeafBlocks::auto_leaf_order(0.8 * f.references_per_item * 1000, 1000);
    CHECK(automatic == (leaf_chosen ? leaf : item));
  }
  // The structures that duplicate references hold more of them than the object partitions;
  // reference_splat's default copies the kd-tree's (3.7 per item) and the octree's (7.2) in leaf
  // order while the copy stays under the cap, and gathers beyond it.
  CHECK(structure_footprint("kd_tree").references_per_item >
        structure_footprint("bvh").references_per_item);
  CHECK(structure_footprint("octree").references_per_item >
        structure_footprint("sphere_tree").references_per_item);
  CHECK(structure_bytes_per_item("kd_tree", 1000000, with_layout(DiscBlockLayout::kAuto)) ==
        structure_footprint("kd_tree").leaf_order);
  // Just past the cap at the footprint's references the layout could go either way (a scan has
  // fewer): the estimate prices the copy.
  const double kd_refs = structure_footprint("kd_tree").references_per_item;
  const auto past_cap = size_t(1.1 * SplatLeafBlocks::kLeafOrderMaxBytes / (28.0 * kd_refs));
  CHECK(!SplatLeafBlocks::auto_leaf_order(kd_refs * double(past_cap), double(past_cap)));
  CHECK(structure_bytes_per_item("kd_tree", past_cap, with_layout(DiscBlockLayout::kAuto)) ==
        structure_footprint("kd_tree").leaf_order);
  // Past 512 MiB of copies (10^7 points on the kd-tree, the scale runs) the leaves gather again.
  CHECK(structure_bytes_per_item("kd_tree", 10000000, with_layout(DiscBlockLayout::kAuto)) ==
        structure_footprint("kd_tree").item_order);
  CHECK(structure_bytes_per_item("kd_tree", 100000000, with_layout(DiscBlockLayout::kAuto)) ==
        structure_footprint("kd_tree").item_order);
}

TEST_CASE("memory estimate: the octree's reference layouts") {
  const auto& splat = MethodRegistry::instance().get("reference_splat", "method");
  const auto with_layout = [&](DiscBlockLayout l) {
    return resolve_params(splat.params, {{"disc_blocks", double(l)}}, "test");
  };
  CHECK(structure_bytes_per_item("octree", 1000000, with_layout(DiscBlockLayout::kAuto)) ==
        structure_footprint("octree").leaf_order);
  CHECK(structure_bytes_per_item("octree", 10000000, with_layout(DiscBlockLayout::kAuto)) ==
        structure_footprint("octree").item_order);
  // The octree's 32-bit references cost more than its compact ones; the default (32-bit up to
  // 2^21 items, compact beyond) is priced as 32-bit, so that it never errs low.
  CHECK(structure_footprint("octree", {{"compact_refs", 0}}).item_order >
        structure_footprint("octree", {{"compact_refs", 1}}).item_order);
  CHECK(structure_footprint("octree").item_order ==
        structure_footprint("octree", {{"compact_refs", 0}}).item_order);
  // The loose octree holds each item once: priced as such, below the cells' leaf-order copy.
  CHECK(structure_footprint("octree", {{"loose", 1}}).references_per_item == 1);
  CHECK(structure_footprint("octree", {{"loose", 1}}).leaf_order <
        structure_footprint("octree").leaf_order);
  // Methods without disc blocks keep every box reference there: priced above the discs' figure.
  const auto& projection = MethodRegistry::instance().get("schaufler_jensen_2000", "method");
  const ParamValues none = resolve_params(projection.params, {}, "test");
  CHECK(structure_bytes_per_item("octree", 1000, none) > structure_footprint("octree").item_order);
  CHECK(structure_bytes_per_item("octree", 1000, none, {{"compact_refs", 0}}) >
        structure_bytes_per_item("octree", 1000, none, {{"compact_refs", 1}}));
}

TEST_CASE("memory estimate: a method's own per-splat data is added") {
  const auto& goradia = MethodRegistry::instance().get("goradia_2010", "method");
  const auto& linsen = MethodRegistry::instance().get("linsen_2007", "method");
  const PointCloud cloud = load_dataset("sphere:n=1000").cloud;
  const size_t g =
      estimate_scene_bytes(goradia, "octree", cloud, resolve_params(goradia.params, {}, "test"));
  const size_t l =
      estimate_scene_bytes(linsen, "octree", cloud, resolve_params(linsen.params, {}, "test"));
  CHECK(linsen.own_data_bytes_per_point == 68);  // normal field 36, own splat 28, point index 4
  CHECK(l - g == 1000 * linsen.own_data_bytes_per_point);
}

}  // namespace pcrt
