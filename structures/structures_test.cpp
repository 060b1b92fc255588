// Every structure must return exactly the closest hit that brute force returns for the same leaf
// intersector, on synthetic and real clouds and on degenerate input.
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <utility>

#include "core/dataset.hpp"
#include "core/rng.hpp"
#include "methods/method.hpp"
#include "preprocess/point_attributes.hpp"
#include "render/renderer.hpp"
#include "render/scene.hpp"
#include "structures/structure.hpp"
#include "structures/wide_node.hpp"
#include "tests/test_paths.hpp"

using namespace pcrt;

namespace {

// Every registered structure but the oracle itself: a new one is checked without being named;
// and the variants whose build differs ("id:name=value").
std::vector<std::string> structures_to_check() {
  std::vector<std::string> ids;
  for (const StructureInfo& info : StructureRegistry::instance().all())
    if (info.id != "brute_force") ids.push_back(info.id);
  ids.push_back("kd_tree:split=1");
  ids.push_back("octree:loose=1");
  ids.push_back("octree:leaf_slabs=0");
  ids.push_back("kd_tree:leaf_slabs=0");
  return ids;
}

// The structure "id" or "id:name=value", not built yet.
std::unique_ptr<Structure> create_structure(const std::string& spec) {
  const size_t colon = spec.find(':');
  const std::string id = spec.substr(0, colon);
  ParamValues set;
  if (colon != std::string::npos) {
    const size_t eq = spec.find('=', colon);
    set[spec.substr(colon + 1, eq - colon - 1)] = std::stod(spec.substr(eq + 1));
  }
  const StructureInfo& info = StructureRegistry::instance().get(id, "structure");
  return info.create(resolve_params(info.params, set, id));
}

// Primary-like rays from outside aimed at cloud points, incoherent rays from inside the bounds,
// and rays from far away aimed at random spots of the box: a third each.
std::vector<Ray> random_rays(const PointCloud& cloud, size_t count, uint64_t seed) {
  Rng rng(seed);
  const Aabb b = cloud.bounds();
  const float diag = std::max(b.diagonal(), 1e-3f);
  auto in_box = [&](float grow) {
    const Vec3 u(rng.uniform(), rng.uniform(), rng.uniform());
    return Vec3(b.lo - grow * Vec3::Constant(diag) +
                u.cwiseProduct(b.extent() + 2 * grow * Vec3::Constant(diag)));
  };
  auto direction = [&] {
    Vec3 d;
    do d = Vec3(rng.uniform() * 2 - 1, rng.uniform() * 2 - 1, rng.uniform() * 2 - 1);
    while (d.squaredNorm() > 1 || d.squaredNorm() < 1e-4f);
    return Vec3(d.normalized());
  };
  const Vec3 eye = b.center() + 1.5f * diag * Vec3(0.5f, -0.7f, 0.5f).normalized();
  std::vector<Ray> rays(count);
  for (size_t i = 0; i < count; ++i) {
    Ray& r = rays[i];
    switch (i % 3) {
      case 0: {
        r.o = eye;
        const Vec3 target =
            cloud.positions[rng.below(uint32_t(cloud.size()))] + 0.01f * diag * direction();
        r.d = (target - eye).normalized();
        break;
      }
      case 1:
        r.o = in_box(0.0f);
        r.d = direction();
        break;
      default:
        r.o = b.center() + 2.0f * diag * direction();
        r.d = (in_box(0.1f) - r.o).normalized();
    }
    if (!r.d.allFinite()) r.d = Vec3::UnitZ();
  }
  return rays;
}

struct Traced {
  std::vector<Hit> hits;
  std::vector<char> found;
  uint64_t items = 0;
};

Traced trace_all(const Structure& s, const Method& m, const std::vector<Ray>& rays) {
  Traced out{std::vector<Hit>(rays.size()), std::vector<char>(rays.size()), 0};
  std::vector<uint64_t> items(rays.size());
  tbb::parallel_for(size_t(0), rays.size(), [&](size_t i) {
    OpCounters c;
    out.found[i] = s.closest_hit(rays[i], m, out.hits[i], c);
    items[i] = c.get(kItemsVisited);
  });
  for (uint64_t v : items) out.items += v;
  return out;
}

// Occlusion queries agree with the closest hits: a segment ending just past the closest hit is
// blocked, one ending just before it is not, an unbounded ray is blocked exactly when it hits.
void check_any_hit(const Structure& s, const Method& m, const std::vector<Ray>& rays,
                   const Traced& oracle) {
  size_t wrong = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    OpCounters c;
    Ray r = rays[i];
    bool ok = s.any_hit(r, m, c) == bool(oracle.found[i]);
    if (oracle.found[i] && oracle.hits[i].t > r.tmin) {
      r.tmax = oracle.hits[i].t * 1.001f;
      ok = ok && s.any_hit(r, m, c);
      r.tmax = oracle.hits[i].t * 0.999f;
      ok = ok && !s.any_hit(r, m, c);
    }
    if (!ok && wrong++ < 3) UNSCOPED_INFO("any_hit disagrees on ray " << i);
  }
  REQUIRE(wrong == 0);
}

// reference_splat with its defaults, prepared on `cloud`: the leaf test of these checks.
std::unique_ptr<Method> prepared_reference_splat(const PointCloud& cloud) {
  const MethodInfo& info = MethodRegistry::instance().get("reference_splat", "method");
  auto method = info.create(resolve_params(info.params, {}, "test"));
  OpCounters prep;
  Timings t;
  PrepareContext ctx{prep, t};
  method->prepare(cloud, ctx);
  return method;
}

void check_against_brute_force(const PointCloud& cloud, size_t ray_count, const std::string& label,
                               bool expect_pruning = true) {
  const auto method = prepared_reference_splat(cloud);
  const auto rays = random_rays(cloud, ray_count, 99);
  auto make = [&](const std::string& id) {
    auto s = create_structure(id);
    OpCounters c;
    s->build(method->items(), c);
    return s;
  };
  const auto oracle = trace_all(*make("brute_force"), *method, rays);
  size_t hits = 0;
  for (char f : oracle.found) hits += size_t(f);
  for (const std::string& id : structures_to_check()) {
    INFO(label << " on " << id << " (" << hits << " of " << rays.size() << " rays hit)");
    const auto got = trace_all(*make(id), *method, rays);
    size_t mismatches = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      const bool same = got.found[i] == oracle.found[i] &&
                        (!got.found[i] || (got.hits[i].prim == oracle.hits[i].prim &&
                                           got.hits[i].t == oracle.hits[i].t));
      if (!same && mismatches++ < 3)
        UNSCOPED_INFO("ray " << i << ": found " << int(got.found[i]) << " t " << got.hits[i].t
                             << " prim " << got.hits[i].prim << ", brute force "
                             << int(oracle.found[i]) << " t " << oracle.hits[i].t << " prim "
                             << oracle.hits[i].prim);
    }
    REQUIRE(mismatches == 0);
    check_any_hit(*make(id), *method, rays, oracle);
    if (expect_pruning) REQUIRE(got.items * 4 < oracle.items);  // the structure prunes
  }
  REQUIRE(hits > rays.size() / 10);  // the rays do exercise the surface
}

}  // namespace

TEST_CASE("structures return brute force's closest hits on synthetic clouds",
          "[structures][slow]") {
  check_against_brute_force(load_dataset("sphere:n=1000,seed=3").cloud, 100000, "sphere 1e3");
  check_against_brute_force(load_dataset("torus:n=10000,seed=4,noise=0.002").cloud, 100000,
                            "noisy torus 1e4");
  check_against_brute_force(load_dataset("plane:n=10000,seed=5,density=0.9").cloud, 100000,
                            "non-uniform plane 1e4");
  check_against_brute_force(load_dataset("bumpy_sphere:n=100000,seed=6").cloud, 100000,
                            "bumpy sphere 1e5");
}

TEST_CASE("structures return brute force's closest hits on real scans",
          "[structures][data][slow]") {
  const std::filesystem::path dir = pcrt::test::data_dir();
  size_t used = 0;
  for (const char* f :
       {"cgal/points_3/kitten.xyz", "cgal/points_3/building.ply", "bunny/bunny.ply"}) {
    if (!std::filesystem::exists(dir / f)) continue;
    check_against_brute_force(load_dataset((dir / f).string()).cloud, 30000, f);
    ++used;
  }
  if (used == 0) PCRT_SKIP("data/ not fetched (scripts/fetch_data.sh): no real scans");
}

TEST_CASE("degenerate clouds build bounded structures that still agree with brute force",
          "[structures][slow]") {
  auto cloud_of = [](std::vector<Vec3> pts, float radius) {
    PointCloud c;
    c.name = "degenerate";
    c.positions = std::move(pts);
    c.normals.assign(c.positions.size(), Vec3(0, 0.6f, 0.8f));
    c.radii.assign(c.positions.size(), radius);
    return c;
  };
  std::vector<Vec3> same(100000, Vec3(0.5f, -0.25f, 2.0f));
  check_against_brute_force(cloud_of(same, 0.01f), 300, "1e5 identical points", false);
  std::vector<Vec3> line, plane;
  for (int i = 0; i < 20000; ++i) line.emplace_back(float(i) * 1e-3f, 0, 0);
  check_against_brute_force(cloud_of(line, 2e-3f), 20000, "points on a line");
  Rng rng(1);
  for (int i = 0; i < 20000; ++i) plane.emplace_back(rng.uniform(), rng.uniform(), 0);
  check_against_brute_force(cloud_of(plane, 0.01f), 20000, "points on a plane");
  check_against_brute_force(cloud_of({Vec3(1, 2, 3)}, 0.1f), 3000, "a single point", false);
  check_against_brute_force(cloud_of({Vec3(1, 2, 3)}, 0.0f), 300, "a single point of radius 0",
                            false);
  std::vector<Vec3> huge, tiny;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 u(rng.uniform(), rng.uniform(), rng.uniform());
    huge.push_back(1e6f * Vec3::Constant(1) + 1e3f * u);
    tiny.push_back(1e-6f * u);
  }
  check_against_brute_force(cloud_of(huge, 30.0f), 20000, "huge coordinates");
  check_against_brute_force(cloud_of(tiny, 3e-8f), 20000, "tiny coordinates");
}

TEST_CASE("structure parameters and memory", "[structures]") {
  const Dataset d = load_dataset("sphere:n=20000,seed=2");
  std::vector<float> radii(d.cloud.size(), 0.01f);
  for (const std::string& id : structures_to_check()) {
    auto s = create_structure(id);
    OpCounters c;
    s->build(ItemSet{d.cloud.positions, radii, {}}, c);
    INFO(id << ": " << s->memory_bytes() << " bytes");
    REQUIRE(s->memory_bytes() > 0);
    REQUIRE(s->memory_bytes() < 64 * d.cloud.size());  // indices, not copies of points
    REQUIRE(c.get(kBuildItemRefs) >= d.cloud.size());
  }
}

namespace {

// Records the largest leaf handed over; never reports a hit, so every leaf a ray crosses is seen.
class LeafSizes final : public LeafIntersector {
 public:
  bool intersect_leaf(const Ray&, const LeafVisit& leaf, Hit&, OpCounters&) const override {
    size_t seen = largest.load();
    while (leaf.items.size() > seen && !largest.compare_exchange_weak(seen, leaf.items.size())) {
    }
    return false;
  }
  mutable std::atomic<size_t> largest{0};
};

size_t largest_leaf(const std::string& id, const ItemSet& items, ParamValues set,
                    const std::vector<Ray>& rays) {
  const StructureInfo& info = StructureRegistry::instance().get(id, "structure");
  auto s = info.create(resolve_params(info.params, set, id));
  OpCounters c;
  s->build(items, c);
  LeafSizes sizes;
  for (const Ray& r : rays) {
    Hit h;
    s->closest_hit(r, sizes, h, c);
  }
  return sizes.largest.load();
}

}  // namespace

TEST_CASE("bvh and loose octree leaves hold at most leaf_size items", "[structures]") {
  const Dataset d = load_dataset("sphere:n=20000,seed=7");
  std::vector<float> radii(d.cloud.size(), 0.04f);  // each disc overlaps about 8 neighbours
  const ItemSet items{d.cloud.positions, radii, {}};
  const auto rays = random_rays(d.cloud, 3000, 5);
  for (const auto& [id, set] :
       std::vector<std::pair<std::string, ParamValues>>{{"bvh", {}}, {"octree", {{"loose", 1}}}}) {
    for (double k : {1.0, 4.0, 8.0}) {
      ParamValues with_k = set;
      with_k["leaf_size"] = k;
      const size_t got = largest_leaf(id, items, with_k, rays);
      INFO(id << " leaf_size " << k << ": largest leaf " << got);
      REQUIRE(got <= size_t(k));
      REQUIRE(got >= 1);
    }
  }
}

// leaf_size=0 sizes the bvh's leaves to the method's leaf test: 8 items one at a time, two blocks
// where the test takes blocks (16 for the disc methods' eight). The largest leaf a ray meets is
// the bound reached: the SAH splits of 20 000 items leave some leaves full.
TEST_CASE("the bvh's automatic leaf size follows the method's leaf block", "[structures]") {
  const Dataset d = load_dataset("sphere:n=20000,seed=7");
  std::vector<float> radii(d.cloud.size(), 0.04f);
  const auto rays = random_rays(d.cloud, 3000, 5);
  for (const uint32_t block : {1u, 5u, 8u, 16u}) {
    ItemSet items{d.cloud.positions, radii, {}};
    items.leaf_block = block;
    const size_t expected = std::max<size_t>(8, 2 * size_t(block));
    INFO("leaf block " << block);
    CHECK(largest_leaf("bvh", items, {}, rays) == expected);
    CHECK(largest_leaf("bvh", items, {{"leaf_size", 5}}, rays) <= 5);
  }
}

// The methods that test discs in blocks of eight say so (ItemSet::leaf_block), so their bvh
// leaves hold 16; the Gaussian particle methods, which test one particle at a time, keep 8. The
// scene records the size its bvh was built with (what a run's stats report), and a size given is
// the size used.
TEST_CASE("a scene's bvh leaf size follows its method's leaf block and is recorded",
          "[structures]") {
  const PointCloud cloud = load_dataset("sphere:n=2000,seed=3").cloud;
  for (const auto& [id, leaf_size] :
       std::vector<std::pair<std::string, double>>{{"reference_splat", 16},
                                                   {"goradia_2010", 16},
                                                   {"kashyap_2010_splat", 16},
                                                   {"linsen_2007", 16},
                                                   {"grt_2024", 8},
                                                   {"ever_2024", 8}}) {
    OpCounters c;
    Timings t;
    const PointScene automatic(cloud, SceneOptions{id, "bvh", {}}, c, t);
    const PointScene given(cloud, SceneOptions{id, "bvh", {{"leaf_size", 5}}}, c, t);
    INFO(id);
    CHECK(automatic.structure_params().at("leaf_size") == leaf_size);
    CHECK(given.structure_params().at("leaf_size") == 5);
  }
}

TEST_CASE("the 8-wide node tests hit the same children with AVX2, its offsets and SSE",
          "[structures]") {
  if (!wide_nodes_use_avx2()) PCRT_SKIP("no AVX2 on this CPU: nothing to compare");
  Rng rng(23);
  size_t hits = 0;
  for (int r = 0; r < 20000; ++r) {
    WideNode n;
    for (int k = 0; k < kWideWidth; ++k)
      for (int a = 0; a < 3; ++a) {
        const float c = rng.uniform() * 2 - 1, e = 0.3f * rng.uniform();
        // Some boxes flat along an axis, some slots empty, as in real trees.
        n.lo[a][k] = c - (k == 7 ? kInfinity : (r % 5 == 0 && a == 0 ? 0.0f : e));
        n.hi[a][k] = c + (k == 7 ? -kInfinity : (r % 5 == 0 && a == 0 ? 0.0f : e));
      }
    Vec3 o(rng.uniform() * 4 - 2, rng.uniform() * 4 - 2, rng.uniform() * 4 - 2);
    Vec3 d = Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f).normalized();
    if (r % 7 == 0) d[r % 3] = 0;        // axis-parallel rays: inv = inf
    if (r % 11 == 0) o[0] = n.lo[0][0];  // an origin on a slab plane: 0 * inf = NaN
    const RaySlabs slabs(Ray{o, d});
    const float limit = r % 3 == 0 ? kInfinity : 2.0f;
    alignas(32) float a0[kWideWidth], a1[kWideWidth], b0[kWideWidth], b1[kWideWidth];
    alignas(32) float c0[kWideWidth], c1[kWideWidth];
    const uint32_t ma = node_test_sse(n, slabs, limit, a0, a1);
    const uint32_t mb = node_test_avx2(n, slabs, limit, b0, b1);
    const uint32_t mc = node_test_avx2_offsets(n, slabs, limit, c0, c1);
    REQUIRE(ma == mb);
    REQUIRE(ma == mc);
    for (int k = 0; k < kWideWidth; ++k) {
      if (!((ma >> k) & 1)) continue;
      REQUIRE(std::memcmp(&a0[k], &b0[k], sizeof(float)) == 0);
      REQUIRE(std::memcmp(&a1[k], &b1[k], sizeof(float)) == 0);
      REQUIRE(std::memcmp(&a0[k], &c0[k], sizeof(float)) == 0);
      REQUIRE(std::memcmp(&a1[k], &c1[k], sizeof(float)) == 0);
      ++hits;
    }
  }
  REQUIRE(hits > 500);  // about 1300 children hit
}

TEST_CASE("the octree's eight octants are the same with AVX2 and with SSE", "[structures]") {
  if (!wide_nodes_use_avx2()) PCRT_SKIP("no AVX2 on this CPU: nothing to compare");
  Rng rng(29);
  size_t hits = 0;
  for (int r = 0; r < 20000; ++r) {
    const Vec3 lo(rng.uniform() * 2 - 1, rng.uniform() * 2 - 1, rng.uniform() * 2 - 1);
    const float half = r % 13 == 0 ? 0.0f : 0.5f * rng.uniform();  // a zero-size cube too
    Vec3 o(rng.uniform() * 4 - 2, rng.uniform() * 4 - 2, rng.uniform() * 4 - 2);
    Vec3 d = Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f).normalized();
    if (r % 7 == 0) d[r % 3] = 0;          // axis-parallel rays: inv = inf
    if (r % 11 == 0) o[1] = lo[1] + half;  // an origin on a mid-plane: 0 * inf = NaN
    const RaySlabs slabs(Ray{o, d});
    const float limit = r % 3 == 0 ? kInfinity : 2.0f;
    alignas(32) float a0[8], a1[8], b0[8], b1[8];
    const uint32_t ma = octant_test_sse(lo, half, slabs, limit, a0, a1);
    const uint32_t mb = octant_test_avx2(lo, half, slabs, limit, b0, b1);
    REQUIRE(ma == mb);
    for (int k = 0; k < 8; ++k) {
      if (!((ma >> k) & 1)) continue;
      REQUIRE(std::memcmp(&a0[k], &b0[k], sizeof(float)) == 0);
      REQUIRE(std::memcmp(&a1[k], &b1[k], sizeof(float)) == 0);
      ++hits;
    }
  }
  REQUIRE(hits > 500);  // about 680 octants hit
}

TEST_CASE("the octree's leaves drop the discs whose plane misses them", "[structures]") {
  // The same boxes twice: stored (so nothing says the items are discs) and derived from the disc
  // normals of a method that hits only on the discs. Splits go by the boxes, so the trees have the
  // same cells; with the normals a leaf keeps only the discs whose plane cuts its cube, and
  // children no plane reaches are not stored.
  const Dataset d = load_dataset("sphere:n=20000,seed=8");
  std::vector<float> radii(d.cloud.size(), 0.05f);
  std::vector<Vec3> boxes(d.cloud.size());
  for (size_t i = 0; i < boxes.size(); ++i)
    for (int a = 0; a < 3; ++a)
      boxes[i][a] = ItemSet::disc_half_extent(d.cloud.normals[i][a], radii[i]);
  const StructureInfo& info = StructureRegistry::instance().get("octree", "structure");
  auto build = [&](const ItemSet& items) {
    OpCounters c;
    info.create(resolve_params(info.params, {}, "octree"))->build(items, c);
    return std::pair{c.get(kBuildItemRefs), c.get(kBuildNodes)};
  };
  const auto [box_refs, box_nodes] = build(ItemSet{d.cloud.positions, radii, boxes});
  const auto [disc_refs, disc_nodes] =
      build(ItemSet{d.cloud.positions, radii, {}, d.cloud.normals, true});
  INFO("references " << box_refs << " -> " << disc_refs << ", nodes " << box_nodes << " -> "
                     << disc_nodes);
  REQUIRE(disc_refs < box_refs * 9 / 10);
  REQUIRE(disc_refs >= d.cloud.size());
  REQUIRE(disc_nodes < box_nodes);
  // A method whose hits may lie off the discs (hits_on_discs false) keeps every box reference.
  const auto [off_disc_refs, off_disc_nodes] =
      build(ItemSet{d.cloud.positions, radii, {}, d.cloud.normals, false});
  REQUIRE(off_disc_refs == box_refs);
  REQUIRE(off_disc_nodes == box_nodes);
}

TEST_CASE("the octree's compact references trace as its 32-bit ones, in fewer bytes",
          "[structures]") {
  const PointCloud cloud = load_dataset("bumpy_sphere:n=20000,seed=9").cloud;
  const MethodInfo& info = MethodRegistry::instance().get("reference_splat", "method");
  auto leaf_order = info.create(resolve_params(info.params, {{"disc_blocks", 1}}, "test"));
  OpCounters prep;
  Timings t;
  PrepareContext ctx{prep, t};
  leaf_order->prepare(cloud, ctx);
  const StructureInfo& octree = StructureRegistry::instance().get("octree", "structure");
  auto build = [&](double compact) {
    auto s = octree.create(resolve_params(octree.params, {{"compact_refs", compact}}, "octree"));
    OpCounters c;
    s->build(leaf_order->items(), c);
    return s;
  };
  const auto plain = build(0), compact = build(1);
  const auto rays = random_rays(cloud, 20000, 13);
  const Traced a = trace_all(*plain, *leaf_order, rays), b = trace_all(*compact, *leaf_order, rays);
  size_t same = 0, hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    hits += size_t(a.found[i]);
    same +=
        size_t(a.found[i] == b.found[i] &&
               (!a.found[i] || (a.hits[i].prim == b.hits[i].prim && a.hits[i].t == b.hits[i].t)));
  }
  CHECK(same == rays.size());
  CHECK(hits > rays.size() / 10);
  CHECK(a.items == b.items);
  INFO("bytes " << plain->memory_bytes() << " -> " << compact->memory_bytes());
  CHECK(compact->memory_bytes() * 10 < plain->memory_bytes() * 7);
  // Decoded leaves are no pieces of one array: a leaf-order disc copy is refused, in words.
  CHECK(compact->leaf_references().empty());
  REQUIRE_THROWS_WITH(leaf_order->bind_leaf_references(compact->leaf_references()),
                      Catch::Contains("compact_refs=0"));
  REQUIRE_NOTHROW(leaf_order->bind_leaf_references(plain->leaf_references()));
}

namespace {

// Two octree variants of one method on the same rays: rays whose hits differ (hit or miss, item,
// t or normal of the closest, or the occlusion answer), rays the second hits, nodes and leaves
// each visits.
struct OctreeVariants {
  size_t differ = 0, hits = 0;
  uint64_t nodes_first = 0, nodes_second = 0, leaves_first = 0, leaves_second = 0;
};
OctreeVariants compare_octree_variants(const PointScene& first, const PointScene& second,
                                       const std::vector<Ray>& rays) {
  OctreeVariants v;
  for (const Ray& r : rays) {
    Hit a, b;
    OpCounters ca, cb;
    const bool fa = first.closest_hit(r, a, ca), fb = second.closest_hit(r, b, cb);
    v.hits += size_t(fb);
    v.differ += size_t(fa != fb || (fa && (a.prim != b.prim || a.t != b.t || a.n != b.n)) ||
                       first.any_hit(r, ca) != second.any_hit(r, cb));
    v.nodes_first += ca.get(kNodesVisited);
    v.nodes_second += cb.get(kNodesVisited);
    v.leaves_first += ca.get(kLeavesVisited);
    v.leaves_second += cb.get(kLeavesVisited);
  }
  return v;
}

}  // namespace

// A switch of a structure (`param`, on by default) turned off against the defaults, every method
// on the same rays: the same hits, bit for bit; the work Work(variants) returns (before, after) no
// higher with it, and at least the splat family's lower by a tenth.
template <class Work>
void check_structure_switch(const char* structure, const char* param, uint64_t seed, Work&& work) {
  const PointCloud cloud = load_dataset("bumpy_sphere:n=4000,seed=5").cloud;
  const auto rays = random_rays(cloud, 6000, seed);
  size_t fewer = 0;
  for (const MethodInfo& info : MethodRegistry::instance().all()) {
    if (!info.own_structure.empty()) continue;
    INFO(info.id);
    OpCounters c;
    Timings t;
    const PointScene off(cloud, SceneOptions{info.id, structure, {{param, 0}}}, c, t);
    const PointScene on(cloud, SceneOptions{info.id, structure, {}}, c, t);
    const OctreeVariants v = compare_octree_variants(off, on, rays);
    CHECK(v.differ == 0);
    CHECK(v.hits > rays.size() / 10);
    const auto [before, after] = work(v);
    INFO(param << ": " << before << " -> " << after);
    CHECK(after <= before);
    fewer += size_t(after * 10 < before * 9);
  }
  CHECK(fewer >= 4);  // the splat family at least
}

TEST_CASE("the octree's child boxes find its cells' hits for every method, in fewer nodes",
          "[structures]") {
  // A ray skips a child whose footprint box it misses; every method's hits lie within its items'
  // footprints, so the hits (item and t, closest and any) are the cells' own, bit for bit.
  // Methods hit on their discs keep the boxes; the others' walk is the cells' own.
  check_structure_switch("octree", "child_bounds", 21, [](const OctreeVariants& v) {
    return std::pair(v.nodes_first, v.nodes_second);
  });
}

TEST_CASE("the octree's leaf slabs skip leaves for every method, never a hit", "[structures]") {
  // A leaf is skipped when the ray misses the slab of its discs from hits_before_leaf before its
  // cell on: no crossing a hit of that leaf could be made of lies there, so the hits (item, t
  // and normal, closest and any) are those of the walk without slabs, bit for bit. Rays from
  // inside the bounds start near the surface, as bounce and shadow rays do.
  check_structure_switch("octree", "leaf_slabs", 23, [](const OctreeVariants& v) {
    return std::pair(v.leaves_first, v.leaves_second);
  });
}

TEST_CASE("the kd-tree's leaf slabs skip leaves for every method, never a hit", "[structures]") {
  // As the octree's: a leaf's interval is its cell's, shared with its neighbours at the planes,
  // and the slab test looks hits_before_leaf back from it.
  check_structure_switch("kd_tree", "leaf_slabs", 29, [](const OctreeVariants& v) {
    return std::pair(v.leaves_first, v.leaves_second);
  });
}

namespace {

// A blend's stand-in: the mean t of the leaf's disc crossings within [t_enter - hits_before_leaf,
// t_exit] (crossings on a disc, from tmin), at the lowest such item, if there are at least two (a
// coverage rule, as the blends' min_weight). A crossing before the leaf lies in an earlier cell,
// which holds its disc; but there it may be alone, below coverage, where the later leaf holds it
// with another: then only the later leaf reports a hit, before its own interval, and a walk that
// skips a leaf whose slab the ray meets only before that interval loses it.
class MeanOfCrossings final : public LeafIntersector {
 public:
  explicit MeanOfCrossings(const ItemSet& items) : items_(items) {}
  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit, OpCounters&) const override {
    double sum = 0;
    uint32_t count = 0, lowest = 0;
    for (const uint32_t i : leaf.items) {
      const float t = crossing(ray, i);
      if (t < leaf.t_enter - items_.hits_before_leaf || t > leaf.t_exit) continue;
      lowest = count++ == 0 ? i : std::min(lowest, i);
      sum += t;
    }
    const auto t = count < 2 ? kInfinity : float(sum / count);
    if (t >= hit.t) return false;
    hit.t = t;
    hit.prim = lowest;
    return true;
  }

 private:
  // Where the ray crosses disc i, or infinity (parallel, before tmin, off the disc).
  [[nodiscard]] float crossing(const Ray& ray, uint32_t i) const {
    const Vec3& n = items_.disc_normals[i];
    const float denom = n.dot(ray.d);
    if (denom == 0) return kInfinity;
    const float t = n.dot(items_.positions[i] - ray.o) / denom;
    const float r = items_.radius(i);
    if (!(t >= ray.tmin) || (ray.at(t) - items_.positions[i]).squaredNorm() > r * r)
      return kInfinity;
    return t;
  }
  const ItemSet& items_;
};

// Closest hits (t and item) and occlusion of every ray, for MeanOfCrossings over `items` in
// structure `spec`; and the leaves visited.
struct MeanHits {
  std::vector<std::pair<float, uint32_t>> closest;
  std::vector<bool> occluded;
  uint64_t leaves = 0;
};
MeanHits mean_hits(const std::string& spec, const ItemSet& items, const std::vector<Ray>& rays) {
  auto s = create_structure(spec);
  OpCounters c;
  s->build(items, c);
  const MeanOfCrossings leaf(items);
  MeanHits out;
  for (const Ray& r : rays) {
    Hit h;
    h.t = r.tmax;
    out.closest.emplace_back(s->closest_hit(r, leaf, h, c) ? h.t : kInfinity,
                             h.t < r.tmax ? h.prim : 0);
    out.occluded.push_back(s->any_hit(r, leaf, c));
  }
  out.leaves = c.get(kLeavesVisited);
  return out;
}

}  // namespace

TEST_CASE("the leaf slabs look back as far as a leaf's hits may lie before it", "[structures]") {
  // A noisy sphere's discs as wide as the points are apart, and hits made of crossings up to three
  // radii before their leaf (hits_before_leaf): the slabs must keep every hit of the walk without
  // them, which they do only by looking that far back from the leaf's interval. Checked by
  // mutation: looking back from the interval alone, the octree's walk lost 18 closest hits and 15
  // occlusions of 60 000 rays, the kd-tree's 19 and 18 (on the clouds of the frames test below,
  // the three blends' frames did not change without the kd-tree's look-back).
  const PointCloud cloud = load_dataset("sphere:n=4000,seed=3,noise=0.03").cloud;
  OpCounters c;
  const auto r = float(mean_spacing(cloud.positions, c));
  const std::vector<float> radii(cloud.size(), r);
  ItemSet items{cloud.positions, radii, {}, cloud.normals, true};
  items.hits_before_leaf = 3 * r;
  const auto rays = random_rays(cloud, 60000, 31);
  for (const char* structure : {"octree", "kd_tree"}) {
    INFO(structure);
    const std::string id = structure;
    const MeanHits plain = mean_hits(id + ":leaf_slabs=0", items, rays);
    const MeanHits slabs = mean_hits(id, items, rays);
    size_t hits = 0, differ = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      differ += slabs.closest[i] != plain.closest[i] || slabs.occluded[i] != plain.occluded[i];
      hits += plain.closest[i].first < kInfinity;
    }
    CHECK(differ == 0);
    CHECK(hits > rays.size() / 10);
    INFO("leaves " << plain.leaves << " -> " << slabs.leaves);
    CHECK(slabs.leaves < plain.leaves);
  }
}

TEST_CASE("the leaf slabs leave the blends' frames as they were, in fewer leaves", "[structures]") {
  // A blend records a hit up to hits_before_leaf before its leaf: the slab test looks that far
  // back. The frames of all three blends, bounce and shadow rays from their hits included, are
  // the same bit for bit with and without slabs (looking back from the cell alone changes some
  // pixels of the noisy torus at this size).
  RenderSettings settings;
  settings.width = settings.height = 256;
  settings.bounces = 2;
  settings.threads = 1;
  for (const char* data : {"torus:n=4000,seed=4,noise=0.002", "bumpy_sphere:n=4000,seed=5"}) {
    const PointCloud cloud = load_dataset(data).cloud;
    for (const char* structure : {"octree", "kd_tree"})
      for (const char* id : {"goradia_2010", "kashyap_2010_splat", "linsen_2007"}) {
        INFO(data << ", " << structure << ", " << id);
        OpCounters c;
        Timings t;
        const PointScene plain(cloud, SceneOptions{id, structure, {{"leaf_slabs", 0}}}, c, t);
        const PointScene slabs(cloud, SceneOptions{id, structure, {}}, c, t);
        const RenderResult a = render(plain, cloud, settings), b = render(slabs, cloud, settings);
        CHECK(a.image.pixels() == b.image.pixels());
        CHECK(a.primary_t == b.primary_t);
        CHECK(a.primary_n == b.primary_n);
        INFO("leaves " << a.counters.get(kLeavesVisited) << " -> "
                       << b.counters.get(kLeavesVisited));
        CHECK(b.counters.get(kLeavesVisited) < a.counters.get(kLeavesVisited));
      }
  }
}

TEST_CASE("the loose octree holds each item once and finds the disc methods' octree hits",
          "[structures]") {
  // The same items behind other leaves: each once, in the cell of its centre, its child box its
  // whole footprint. A nearest-disc method's hits (item and t, closest and any) are the cells'
  // own; the others' depend on which items share a leaf (a blend, a local surface), so only that
  // they hit is checked here (their accuracy: docs/methods.md).
  const PointCloud cloud = load_dataset("bumpy_sphere:n=4000,seed=5").cloud;
  const auto rays = random_rays(cloud, 6000, 21);
  size_t exact = 0;
  for (const MethodInfo& info : MethodRegistry::instance().all()) {
    if (!info.own_structure.empty()) continue;
    INFO(info.id);
    OpCounters c, cl, cb;
    Timings t;
    const PointScene cells(cloud, SceneOptions{info.id, "octree", {}}, c, t);
    const PointScene loose(cloud, SceneOptions{info.id, "octree", {{"loose", 1}}}, cl, t);
    const PointScene bvh(cloud, SceneOptions{info.id, "bvh", {}}, cb, t);
    CHECK(cl.get(kBuildItemRefs) == cb.get(kBuildItemRefs));  // one reference an item
    const OctreeVariants v = compare_octree_variants(cells, loose, rays);
    CHECK(v.hits > rays.size() / 10);
    if (info.family != LeafFamily::kDisc) continue;
    CHECK(v.differ == 0);
    ++exact;
  }
  CHECK(exact >= 1);
}

TEST_CASE("kd-tree builds past the parallel threshold are the same at 1 and 2 threads",
          "[structures]") {
  // Subtrees of over 50 000 references build in parallel and are spliced in a fixed order, for
  // the median and the SAH alike: the same nodes and references whatever the threads.
  const Dataset d = load_dataset("sphere:n=120000,seed=4");
  const std::vector<float> radii(d.cloud.size(), 0.005f);
  const ItemSet items{d.cloud.positions, radii, {}};
  for (const char* spec : {"kd_tree", "kd_tree:split=1"}) {
    INFO(spec);
    auto build = [&](int threads) {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
      auto s = create_structure(spec);
      OpCounters c;
      s->build(items, c);
      const auto refs = s->leaf_references();
      return std::pair{c.to_map(), std::vector<uint32_t>(refs.begin(), refs.end())};
    };
    const auto one = build(1), two = build(2);
    CHECK(one.first == two.first);
    CHECK(one.second == two.second);
    CHECK(one.second.size() >= d.cloud.size());
  }
}

// SceneIntersector::any_hits traces a frame's shadow rays sixteen at a time; the bvh walks each
// sixteen together (walk_wide_occluded), every other structure one by one. Either way each ray's
// answer and the counts must be what sixteen single queries give: coherent rays from a 4x4-blocked
// grid towards a light, partly blocked by a sphere (packets where some rays stop early), and
// random segments (packets that split at once), some empty; 3000 rays, so the last group has 8.
TEST_CASE("sixteen occlusion queries at once answer and count as sixteen single ones",
          "[structures]") {
  const PointCloud cloud = load_dataset("bumpy_sphere:n=20000,seed=7").cloud;
  const auto method = prepared_reference_splat(cloud);
  std::vector<Ray> rays;
  const Vec3 light(0.3f, 0.2f, 3.0f);
  for (int by = 0; by < 40; by += 4)
    for (int bx = 0; bx < 40; bx += 4)
      for (int y = by; y < by + 4; ++y)
        for (int x = bx; x < bx + 4; ++x) {
          const Vec3 o(-1.3f + 0.065f * float(x), -1.3f + 0.065f * float(y), -2.0f);
          const float dist = (light - o).norm();
          rays.push_back(Ray{o, (light - o) / dist, 0.0f, dist});
        }
  Rng rng(3);
  for (Ray r : random_rays(cloud, 3000 - rays.size(), 17)) {
    r.tmax = std::isfinite(r.tmax) ? r.tmax * rng.uniform() : 4.0f * rng.uniform();
    rays.push_back(r);
  }
  // Rays a walk does not enter at all (an empty span) count nothing either way.
  for (size_t i = 5; i < rays.size(); i += 97) rays[i].tmin = rays[i].tmax + 1.0f;
  for (const std::string& id : structures_to_check()) {
    INFO(id);
    auto s = create_structure(id);
    OpCounters build;
    s->build(method->items(), build);
    OpCounters single, grouped;
    std::vector<char> one(rays.size()), sixteen(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) one[i] = char(s->any_hit(rays[i], *method, single));
    for (size_t i = 0; i < rays.size(); i += 16)
      s->any_hits(&rays[i], int(std::min<size_t>(16, rays.size() - i)), *method, &sixteen[i],
                  grouped);
    const auto blocked = size_t(std::count(one.begin(), one.end(), 1));
    INFO(blocked << " of " << rays.size() << " rays blocked");
    CHECK(blocked > rays.size() / 5);
    CHECK(blocked < rays.size() * 4 / 5);
    CHECK(one == sixteen);
    CHECK(single.to_map() == grouped.to_map());
  }
}
