// Reconstruction and triangle engines: exact cell counts where the combinatorics are known,
// clear errors on degenerate input, and the three engines agreeing ray by ray.
#include "reconstruction/reconstruction.hpp"

#include <catch2/catch.hpp>
#include <filesystem>

#include "core/dataset.hpp"
#include "core/error.hpp"
#include "core/rng.hpp"
#include "reconstruction/mesh_engine.hpp"
#include "render/renderer.hpp"
#include "tests/test_paths.hpp"

using namespace pcrt;

namespace {
const ReconstructionInfo& reconstruction(const char* id) {
  return ReconstructionRegistry::instance().get(id, "reconstruction");
}
}  // namespace

TEST_CASE("Delaunay of two skew lines has (N/2 - 1)^2 cells", "[reconstruction]") {
  for (int n : {20, 60, 200}) {
    const Dataset d = load_dataset("skew_lines:n=" + std::to_string(n));
    const ReconstructionReport r = reconstruction("delaunay").run(d.cloud);
    REQUIRE(r.cells.has_value());
    const uint64_t half = uint64_t(n / 2);
    REQUIRE(*r.cells == (half - 1) * (half - 1));
    REQUIRE(r.vertices == size_t(n));
  }
}

TEST_CASE("Delaunay of uniform points: Euler's relation for a ball's tetrahedralization",
          "[reconstruction]") {
  const Dataset d = load_dataset("cube:n=2000");
  const ReconstructionReport r = reconstruction("delaunay").run(d.cloud);
  // Every finite cell has 4 facets; interior facets are shared by two cells, hull facets by one:
  // 4 C = 2 F - H, with H > 0 hull facets, so F lies strictly between 2C and 4C.
  REQUIRE(*r.facets > 2 * *r.cells);
  REQUIRE(*r.facets < 4 * *r.cells);
  // About 6.7 cells per point for uniform points (Delaunay statistics).
  REQUIRE(double(*r.cells) / 2000 == Approx(6.5).margin(1.0));
}

TEST_CASE("Delaunay's counted predicates: quadratic on skew lines, linear on a uniform ball",
          "[reconstruction]") {
  auto predicates = [](const std::string& spec) {
    const ReconstructionReport r = reconstruction("delaunay").run(load_dataset(spec).cloud);
    REQUIRE(r.predicates.has_value());
    return double(*r.predicates);
  };
  // Each new point on a line conflicts with the cells of every point on the other: 4x per 2x N.
  REQUIRE(predicates("skew_lines:n=800") / predicates("skew_lines:n=400") == Approx(4).margin(0.3));
  // Spatially sorted insertion into uniform points touches O(1) cells per point.
  REQUIRE(predicates("ball:n=16000") / predicates("ball:n=8000") == Approx(2).margin(0.2));
  // Counts are exact: the same input gives the same count.
  REQUIRE(predicates("ball:n=3000") == predicates("ball:n=3000"));
}

TEST_CASE("Degenerate input gives a clear error, not a crash", "[reconstruction]") {
  PointCloud three;
  three.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  REQUIRE_THROWS_AS(reconstruction("delaunay").run(three), InputError);
  REQUIRE_THROWS_AS(reconstruction("afsr").run(three), InputError);
  const Dataset plane = load_dataset("plane:n=200");
  REQUIRE_THROWS_WITH(reconstruction("delaunay").run(plane.cloud), Catch::Contains("coplanar"));
  REQUIRE_THROWS_WITH(reconstruction("afsr").run(plane.cloud), Catch::Contains("coplanar"));
}

TEST_CASE("Advancing front closes a sphere and the three engines agree", "[reconstruction]") {
  const Dataset d = load_dataset("sphere:n=3000");
  const ReconstructionReport r = reconstruction("afsr").run(d.cloud);
  // A closed triangulated sphere on V vertices has 2V - 4 triangles.
  REQUIRE(*r.triangles == 2 * d.cloud.size() - 4);
  REQUIRE(*r.boundary_edges == 0);
  OpCounters counters;
  Timings timings;
  const MeshScene bvh(r.mesh, "bvh", counters, timings);
  const MeshScene cgal(r.mesh, "cgal_aabb", counters, timings);
  const MeshScene embree(r.mesh, "embree", counters, timings);
  Rng rng(7, 1);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 o = 3.0f * Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, 1.0f).normalized();
    const Vec3 target(1.2f * (rng.uniform() - 0.5f), 1.2f * (rng.uniform() - 0.5f), 0.0f);
    const Ray ray{o, (target - o).normalized()};
    Hit a, b, c;
    const bool fa = bvh.closest_hit(ray, a, counters);
    const bool fb = cgal.closest_hit(ray, b, counters);
    const bool fc = embree.closest_hit(ray, c, counters);
    REQUIRE(fa == fb);
    REQUIRE(fa == fc);
    if (!fa) continue;
    ++hits;
    REQUIRE(a.t == Approx(b.t).epsilon(1e-5));
    REQUIRE(a.t == Approx(c.t).epsilon(1e-5));
  }
  REQUIRE(hits > 1000);
  REQUIRE(counters.get(kTriangleTests) > 0);
}

TEST_CASE("Meshes round-trip through PLY, and bad meshes are refused", "[reconstruction]") {
  TriangleMesh m;
  m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  m.triangles = {{0, 1, 2}, {0, 1, 3}};
  const std::string path =
      (std::filesystem::temp_directory_path() / "pcrt_mesh_roundtrip.ply").string();
  write_mesh_ply(path, m);
  const TriangleMesh back = read_mesh(path);
  REQUIRE(back.vertices == m.vertices);
  REQUIRE(back.triangles == m.triangles);
  REQUIRE(back.boundary_edges() == 4);
  std::filesystem::remove(path);
  REQUIRE_THROWS_AS(read_mesh((pcrt::test::data_dir() / "no_such_mesh.ply").string()), InputError);
}

TEST_CASE("Mesh rendering is the same at 1 and 2 threads on every engine", "[reconstruction]") {
  const Dataset d = load_dataset("torus:n=3000");
  const ReconstructionReport r = reconstruction("afsr").run(d.cloud);
  PointCloud vertices;
  vertices.positions = r.mesh.vertices;
  for (const MeshEngineInfo& e : MeshEngineRegistry::instance().all()) {
    OpCounters counters;
    Timings timings;
    const MeshScene scene(r.mesh, e.id, counters, timings);
    RenderSettings rs;
    rs.width = rs.height = 48;
    rs.spp = 2;
    rs.threads = 1;
    const RenderResult one = render(scene, vertices, rs);
    rs.threads = 2;
    const RenderResult two = render(scene, vertices, rs);
    INFO(e.id);
    REQUIRE(one.image.pixels() == two.image.pixels());
    REQUIRE(one.counters.to_map() == two.counters.to_map());
    REQUIRE(one.counters.get(kRayHits) > 0);
  }
}

// Issue 14: a vertex near float's limit made the BVH's centroid extent infinite and its bin index
// NaN -> INT_MIN (a segfault in Release). Mesh scenes refuse such vertices; the BVH itself must
// still build and trace without leaving its bins.
TEST_CASE("Huge mesh vertices: scenes refuse them, the BVH survives them", "[reconstruction]") {
  TriangleMesh mesh;
  for (int i = 0; i < 40; ++i) {  // triangle i: z = 0, x in [i, i + 0.9], y in [0, 1]
    const float x = float(i);
    mesh.vertices.push_back(Vec3(x, 0, 0));
    mesh.vertices.push_back(Vec3(x + 0.9f, 0, 0));
    mesh.vertices.push_back(Vec3(x, 1, 0));
  }
  // Triangle 1 far out in y: its centroid, (lo + hi) / 2, overflows to infinity.
  mesh.vertices[3] = Vec3(0, 2e38f, 0);
  mesh.vertices[4] = Vec3(1, 3e38f, 0);
  mesh.vertices[5] = Vec3(0, 3e38f, 1);
  for (uint32_t t = 0; t < 40; ++t) mesh.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  OpCounters counters;
  Timings timings;
  for (const char* engine : {"bvh", "cgal_aabb", "embree"})
    REQUIRE_THROWS_WITH(MeshScene(mesh, engine, counters, timings),
                        Catch::Matchers::Contains("mesh vertex 3 has a coordinate beyond"));
  const auto bvh =
      MeshEngineRegistry::instance().get("bvh", "mesh engine").create(mesh, counters, timings);
  Hit hit;
  Ray ray;
  ray.o = Vec3(20.2f, 0.2f, 5);
  ray.d = Vec3(0, 0, -1);
  REQUIRE(bvh->closest_hit(ray, hit, counters));
  REQUIRE(hit.prim == 20);
}

TEST_CASE("Huge and tiny triangles keep their normals on every engine", "[reconstruction]") {
  // Edges of 1e10: the float cross product squares to infinity and the normal came out zero.
  TriangleMesh mesh;
  mesh.vertices = {Vec3(0, 0, 0), Vec3(1e10f, 0, 0), Vec3(0, 1e10f, 1e10f)};
  mesh.triangles = {{0, 1, 2}};
  const Vec3 expected = Vec3(0, -1, 1).normalized();
  REQUIRE((mesh.normal(0) - expected).norm() < 1e-6f);
  OpCounters counters;
  Timings timings;
  for (const char* engine : {"bvh", "cgal_aabb", "embree"}) {
    CAPTURE(engine);
    const MeshScene scene(mesh, engine, counters, timings);
    Hit hit;
    const Ray ray{Vec3(1e9f, 1e9f, 5e10f), Vec3(0, 0, -1)};
    REQUIRE(scene.closest_hit(ray, hit, counters));
    CHECK(hit.n.allFinite());
    CHECK((hit.n - expected).norm() < 1e-5f);
  }
  // Edges of 1e-20: the float cross product (1e-40) squares to zero, and the normal was +z.
  TriangleMesh tiny;
  tiny.vertices = {Vec3(0, 0, 0), Vec3(1e-20f, 0, 0), Vec3(0, 0, 1e-20f)};
  tiny.triangles = {{0, 1, 2}};
  REQUIRE((tiny.normal(0) - Vec3(0, -1, 0)).norm() < 1e-6f);
}

TEST_CASE("The triangle BVH returns exactly brute force's closest triangle", "[reconstruction]") {
  const Dataset d = load_dataset("sphere:n=3000");
  const ReconstructionReport r = reconstruction("afsr").run(d.cloud);
  OpCounters counters;
  Timings timings;
  const MeshScene bvh(r.mesh, "bvh", counters, timings);
  Rng rng(11, 1);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    // Origins inside and outside, directions everywhere: near and far sides, grazing rays.
    const Vec3 o = 2.5f * Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f);
    const Vec3 dir =
        Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f).normalized();
    const Ray ray{o, dir};
    float best_t = kInfinity;
    uint32_t best = 0;
    for (uint32_t k = 0; k < r.mesh.triangles.size(); ++k) {
      const auto& t = r.mesh.triangles[k];
      const float tk = intersect_triangle(ray, r.mesh.vertices[t[0]], r.mesh.vertices[t[1]],
                                          r.mesh.vertices[t[2]], ray.tmin, ray.tmax);
      if (tk < best_t) best_t = tk, best = k;  // ascending k: the lower index wins a tie
    }
    Hit h;
    const bool found = bvh.closest_hit(ray, h, counters);
    REQUIRE(found == (best_t < kInfinity));
    if (!found) continue;
    ++hits;
    REQUIRE(h.t == best_t);
    REQUIRE(h.prim == best);
    REQUIRE(h.n == r.mesh.normal(best));  // the normal from the leaf's block is the mesh's
  }
  REQUIRE(hits > 500);  // about 800 of the 2000 rays hit
}

TEST_CASE("Mesh any-hit queries agree with closest hits within tmax on every engine",
          "[reconstruction]") {
  const Dataset d = load_dataset("sphere:n=3000");
  const ReconstructionReport r = reconstruction("afsr").run(d.cloud);
  OpCounters counters;
  Timings timings;
  for (const char* engine : {"bvh", "embree", "cgal_aabb"}) {
    const MeshScene scene(r.mesh, engine, counters, timings);
    Rng rng(13, 1);
    int blocked = 0, open = 0;
    for (int i = 0; i < 2000; ++i) {
      // Shadow-like segments from inside and outside, ending before, at or past the surface.
      const Vec3 o = 2.5f * Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f);
      const Vec3 dir =
          Vec3(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f).normalized();
      const Ray ray{o, dir, 0.0f, 3.0f * rng.uniform()};
      Hit h;
      h.t = ray.tmax;
      const bool closest = scene.closest_hit(ray, h, counters);
      CAPTURE(engine, i);
      REQUIRE(scene.any_hit(ray, counters) == closest);
      (closest ? blocked : open) += 1;
    }
    REQUIRE(blocked > 300);
    REQUIRE(open > 300);
  }
  REQUIRE(counters.get(kAnyHitRays) == 3 * 2000);
}
