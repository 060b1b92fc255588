// 64-bit reference offsets (core/offsets.hpp): the node encodings with values past 2^32, and the
// octree and grid built in their 64-bit layouts (the narrow limit lowered so that a small cloud
// needs them) answering exactly as in their 32-bit ones.
#include "core/offsets.hpp"

#include <catch2/catch.hpp>

#include "core/dataset.hpp"
#include "core/rng.hpp"
#include "methods/method.hpp"
#include "structures/structure.hpp"
#include "structures/tree_nodes.hpp"

using namespace pcrt;

TEST_CASE("kd-tree and octree leaves hold offsets past 2^32", "[structures]") {
  const uint64_t two32 = uint64_t(1) << 32;
  for (const uint64_t first :
       {uint64_t(0), two32 - 1, two32, two32 + 12345, uint64_t(5e9), (uint64_t(1) << 40) + 7}) {
    INFO(first);
    const KdNode kd = KdNode::leaf(first, 17);
    CHECK(kd.is_leaf());
    CHECK(kd.first() == first);
    CHECK(kd.count() == 17);
    const OctNode64 oct = OctNode64::make(first, 17);
    CHECK(oct.leaf());
    CHECK(oct.first() == first);
    CHECK(oct.count == 17);
  }
  // A subtree's leaf moved past 2^32 by its place in its parent's references; inner nodes keep
  // their plane and move by the node base only.
  const KdNode moved = KdNode::leaf(two32 - 10, 5).shifted(100, 20);
  CHECK(moved.first() == two32 + 10);
  CHECK(moved.count() == 5);
  const KdNode inner = KdNode::inner(0.25f, 1).shifted(7, 3 * two32);
  CHECK_FALSE(inner.is_leaf());
  CHECK(inner.split == 0.25f);
  CHECK(inner.a == 7);
  // The narrow octree node cannot: why the wide one exists.
  CHECK(OctNode32::make(two32 + 5, 1).first() != two32 + 5);
  CHECK(fits_narrow_offset(two32 - 1));
  CHECK_FALSE(fits_narrow_offset(two32));
}

namespace {

struct Traced {
  std::vector<Hit> hits;
  std::vector<char> found;
  OpCounters counters;
  size_t memory = 0;
};

Traced build_and_trace(const std::string& id, const Method& method, const std::vector<Ray>& rays) {
  const StructureInfo& info = StructureRegistry::instance().get(id, "structure");
  auto s = info.create(resolve_params(info.params, {}, id));
  Traced out;
  s->build(method.items(), out.counters);
  out.memory = s->memory_bytes();
  for (const Ray& r : rays) {
    Hit h;
    out.found.push_back(char(s->closest_hit(r, method, h, out.counters)));
    out.hits.push_back(h);
    Ray shadow = r;
    shadow.tmax = out.found.back() ? 0.5f * h.t : r.tmax;
    (void)s->any_hit(shadow, method, out.counters);
  }
  return out;
}

}  // namespace

TEST_CASE("octree and grid in 64-bit offsets trace exactly as in 32-bit ones", "[structures]") {
  const PointCloud cloud = load_dataset("bumpy_sphere:n=5000,seed=8").cloud;
  const MethodInfo& info = MethodRegistry::instance().get("reference_splat", "method");
  auto method = info.create(resolve_params(info.params, {}, "test"));
  OpCounters prep;
  Timings t;
  PrepareContext ctx{prep, t};
  method->prepare(cloud, ctx);
  Rng rng(3);
  std::vector<Ray> rays;
  const Vec3 eye(2.5f, -1.5f, 1.0f);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 target = cloud.positions[rng.below(uint32_t(cloud.size()))];
    rays.push_back(Ray{eye, (target - eye).normalized()});
  }
  for (const char* id : {"octree", "grid", "kd_tree"}) {
    INFO(id);
    const Traced narrow = build_and_trace(id, *method, rays);
    Traced wide;
    {
      const NarrowOffsetLimit limit(100);  // any leaf past the 100th reference needs 64 bits
      wide = build_and_trace(id, *method, rays);
    }
    CHECK(wide.counters.to_map() == narrow.counters.to_map());
    size_t same = 0, hits = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      hits += size_t(narrow.found[i]);
      same += size_t(wide.found[i] == narrow.found[i] &&
                     (!narrow.found[i] || (wide.hits[i].prim == narrow.hits[i].prim &&
                                           wide.hits[i].t == narrow.hits[i].t)));
    }
    CHECK(same == rays.size());
    CHECK(hits > rays.size() / 2);
    const uint64_t nodes = narrow.counters.get(kBuildNodes);
    if (std::string(id) == "octree")
      CHECK(wide.memory == narrow.memory + nodes * (sizeof(OctNode64) - sizeof(OctNode32)));
    else if (std::string(id) == "grid")  // one offset per cell and one more
      CHECK(wide.memory == narrow.memory + (nodes + 1) * (sizeof(uint64_t) - sizeof(uint32_t)));
    else  // the kd-tree's leaves always hold 64 bits in their 16 bytes
      CHECK(wide.memory == narrow.memory);
  }
}
