// Georeferenced clouds (core/point_cloud.hpp, kLocalOriginReach): a file far from zero is read
// relative to a local origin, so every method finds on it the hits it finds on the same cloud
// near zero; without the origin, float positions at 10^6 are 6 cm apart and the hits are not.
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>

#include "core/dataset.hpp"
#include "core/point_cloud_io.hpp"
#include "core/ray_io.hpp"
#include "preprocess/point_attributes.hpp"
#include "reconstruction/triangle_mesh.hpp"
#include "render/accuracy.hpp"
#include "render/scene.hpp"
#include "tests/test_helpers.hpp"

namespace pcrt {
namespace {

// A shift with fractional parts: the local cloud is then the original moved by a fraction of a
// unit (a real float translation), not bit for bit the same.
const Vec3d kShift(1e6 + 0.3125, -1e6 + 0.625, 5e5 + 0.1875);

// `cloud` written `origin` away, in double (write_ply writes positions + origin), and read back as
// a user's file is (local origin, Morton order).
Dataset written_and_read(const PointCloud& cloud, const Vec3d& origin, const std::string& name) {
  PointCloud moved = cloud;
  moved.origin = origin;
  const std::string path = (test::scratch_dir() / name).string();
  write_ply(path, moved);
  return load_dataset(path);
}

PointCloud translated(const PointCloud& cloud, const Vec3& offset) {
  PointCloud out = cloud;
  for (Vec3& p : out.positions) p += offset;
  return out;
}

// The generated sphere moved so that its first point is at zero: a file a whole number of units
// away from it is read relative to exactly that number (the rounded first point).
PointCloud sphere_from_zero(Vec3& centre) {
  const Dataset d = load_dataset("sphere:n=20000,seed=3");
  centre = -d.cloud.positions[0];
  return translated(d.cloud, centre);
}

struct HitAgreement {
  size_t rays = 0, hits = 0, one_only = 0, differ = 0;
};

// The rays on `a` and, moved by `offset`, on `b`: how many hit only one, and how many of the hits
// of both differ in point, distance, position (moved back) or normal.
HitAgreement compare_hits(const PointScene& a, const PointScene& b, const std::vector<Ray>& rays,
                          const Vec3& offset) {
  HitAgreement g;
  OpCounters c;
  for (Ray r : rays) {
    Hit ha, hb;
    const bool fa = a.closest_hit(r, ha, c);
    r.o += offset;
    const bool fb = b.closest_hit(r, hb, c);
    ++g.rays;
    if (fa != fb) ++g.one_only;
    if (!(fa && fb)) continue;
    ++g.hits;
    if (ha.prim != hb.prim || ha.t != hb.t || ha.p + offset != hb.p || ha.n != hb.n) ++g.differ;
  }
  return g;
}

// Every method on `a` and `b` along the accuracy harness's rays at the unit sphere around `centre`.
void require_same_hits(const PointCloud& a, const PointCloud& b, const Vec3& centre) {
  OpCounters c;
  const double h = mean_spacing(a.positions, c);
  SphereSurface sphere;
  sphere.center = centre;
  const auto rays = accuracy_rays(sphere, h, 2000, 5);
  for (const MethodInfo& m : MethodRegistry::instance().all()) {
    Timings t;
    const std::string structure = m.structure == "brute_force" ? "kd_tree" : "";
    const PointScene sa(a, SceneOptions{m.id, structure, {}}, c, t);
    const PointScene sb(b, SceneOptions{m.id, structure, {}}, c, t);
    const HitAgreement g = compare_hits(sa, sb, rays, Vec3::Zero());
    INFO(m.id << ": " << g.hits << " hits of " << g.rays << " rays, " << g.one_only
              << " hit by one only, " << g.differ << " not the same hit");
    CHECK(g.hits > g.rays / 2);
    CHECK(g.one_only == 0);
    CHECK(g.differ == 0);
  }
}

}  // namespace

TEST_CASE("a file far from zero is read relative to a local origin", "[io][origin]") {
  const std::string path =
      test::write_text("far.xyz", "600000.25 -4000000.25 120.125\n600001.75 -4000002.25 121\n");
  const PointCloud c = read_point_cloud(path);
  CHECK(c.origin == Vec3d(600000, -4000000, 120));
  CHECK(c.positions[0] == Vec3(0.25f, -0.25f, 0.125f));
  CHECK(c.positions[1] == Vec3(1.75f, -2.25f, 1.0f));
  // Written back in the file's coordinates, as doubles, and read again to the same local cloud.
  const std::string back = (test::scratch_dir() / "far_back.ply").string();
  write_ply(back, c, PlyFormat::kAscii);
  const PointCloud again = read_point_cloud(back);
  CHECK(again.origin == c.origin);
  CHECK(again.positions == c.positions);
  // Rays in the file's coordinates come relative to the same origin.
  const std::string rays =
      test::write_text("far_rays.csv", "ox,oy,oz,dx,dy,dz\n600000.5,-4000000,125,0,0,-1\n");
  CHECK(read_rays_csv(rays, c.origin)[0].o == Vec3(0.5f, 0.0f, 5.0f));
}

TEST_CASE("a file near zero keeps its coordinates", "[io][origin]") {
  const std::string path = test::write_text("near.xyz", "1000.5 -3 2\n1001 -3 2\n");
  const PointCloud c = read_point_cloud(path);
  CHECK(c.origin.isZero());
  CHECK(c.positions[0] == Vec3(1000.5f, -3.0f, 2.0f));
  const std::string off =
      test::write_text("far.off", "OFF\n3 1 0\n2e6 0 0\n2e6 1 0\n2e6 0 1\n3 0 1 2\n");
  std::vector<std::array<uint32_t, 3>> triangles;
  const PointCloud m = read_off(off, &triangles);
  CHECK(m.origin == Vec3d(2e6, 0, 0));
  CHECK(m.positions[1] == Vec3(0, 1, 0));
}

TEST_CASE("a mesh far from zero is written back where it was", "[io][origin]") {
  TriangleMesh mesh;
  mesh.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  mesh.triangles = {{0, 1, 2}};
  mesh.origin = kShift;
  const std::string path = (test::scratch_dir() / "far_mesh.ply").string();
  write_mesh_ply(path, mesh);
  const TriangleMesh back = read_mesh(path);
  const Vec3d first = mesh.origin;  // vertex 0 in the file's coordinates
  CHECK(back.origin == first.array().round().matrix());
  for (size_t i = 0; i < 3; ++i)
    CHECK(
        (to_world(back.vertices[i], back.origin) - to_world(mesh.vertices[i], mesh.origin)).norm() <
        1e-6);
}

// Every method, the same rays: a cloud read 10^6 away is the cloud near zero, bit for bit, so
// every hit is the same (point, distance, position, normal).
TEST_CASE("every method finds the same hits on a cloud moved by 10^6", "[methods][origin]") {
  Vec3 centre;
  const PointCloud cloud = sphere_from_zero(centre);
  const Dataset near = written_and_read(cloud, Vec3d::Zero(), "sphere_near.ply");
  const Dataset far = written_and_read(cloud, Vec3d(1e6, -1e6, 5e5), "sphere_far_whole.ply");
  REQUIRE(near.cloud.origin.isZero());
  REQUIRE(far.cloud.origin == Vec3d(1e6, -1e6, 5e5));
  require_same_hits(near.cloud, far.cloud, centre);
}

// A shift with fractional parts leaves the local cloud moved by the fractions (to the nearest
// whole number): every method finds on it what it finds on the cloud near zero moved by them in
// float, hit for hit.
TEST_CASE("a cloud moved by 10^6 and a fraction is the cloud moved by the fraction",
          "[methods][origin]") {
  Vec3 centre;
  const PointCloud cloud = sphere_from_zero(centre);
  const Vec3d whole = kShift.array().round().matrix();
  const Vec3 fraction = (kShift - whole).cast<float>();
  REQUIRE(fraction.cast<double>() == kShift - whole);
  const Dataset near = written_and_read(translated(cloud, fraction), Vec3d::Zero(), "near_f.ply");
  const Dataset far = written_and_read(cloud, kShift, "sphere_far.ply");
  REQUIRE(far.cloud.origin == whole);
  require_same_hits(near.cloud, far.cloud, centre + fraction);
}

// The tests above can fail: the same cloud moved by 10^6 in float (what pcrt did before the local
// origin) loses its shape to the float spacing there (6 cm at 10^6).
TEST_CASE("a cloud moved by 10^6 in float finds other hits", "[methods][origin]") {
  const Dataset d = load_dataset("sphere:n=20000,seed=3");
  const Vec3 offset = Vec3d(1e6, -1e6, 5e5).cast<float>();  // exact in float
  const PointCloud in_float = translated(d.cloud, offset);
  OpCounters c;
  const double h = mean_spacing(d.cloud.positions, c);
  const auto rays = accuracy_rays(*d.truth, h, 2000, 5);
  Timings t;
  const PointScene near(d.cloud, SceneOptions{"reference_splat", "kd_tree", {}}, c, t);
  const PointScene moved(in_float, SceneOptions{"reference_splat", "kd_tree", {}}, c, t);
  const HitAgreement g = compare_hits(near, moved, rays, offset);
  INFO(g.one_only << " hit by one only, " << g.differ << " of " << g.hits << " differ");
  CHECK(g.one_only + g.differ > g.rays / 2);
}

}  // namespace pcrt
