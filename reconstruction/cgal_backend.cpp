// Everything pcrt takes from CGAL, in one translation unit (CGAL costs 15-60 s per unit to
// compile): the Delaunay triangulation, advancing-front surface reconstruction, and the AABB tree
// as a triangle engine. Nothing CGAL appears in a header.
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Advancing_front_surface_reconstruction.h>
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <chrono>

#include "core/error.hpp"
#include "reconstruction/mesh_engine.hpp"
#include "reconstruction/reconstruction.hpp"
#include "reconstruction/triangle_distance.hpp"

namespace pcrt {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
// The work of incremental Delaunay insertion, counted: every orientation and in-sphere predicate
// the triangulation evaluates (point location walks on orientations, the conflict region on
// in-sphere tests). Exact and machine independent, unlike its time.
thread_local uint64_t g_predicates = 0;

template <class Base>
struct Counting : Base {
  template <class... A>
  auto operator()(const A&... a) const {
    ++g_predicates;
    return Base::operator()(a...);
  }
};

struct CountingKernel : Kernel {
  using Orientation_3 = Counting<Kernel::Orientation_3>;
  using Side_of_oriented_sphere_3 = Counting<Kernel::Side_of_oriented_sphere_3>;
  [[nodiscard]] Orientation_3 orientation_3_object() const { return {}; }
  [[nodiscard]] Side_of_oriented_sphere_3 side_of_oriented_sphere_3_object() const { return {}; }
};

using Delaunay = CGAL::Delaunay_triangulation_3<Kernel>;
using CountedDelaunay = CGAL::Delaunay_triangulation_3<CountingKernel>;

std::vector<Point> cgal_points(const PointCloud& cloud) {
  std::vector<Point> pts;
  pts.reserve(cloud.size());
  for (const Vec3& p : cloud.positions) pts.emplace_back(p.x(), p.y(), p.z());
  return pts;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void require_points(const PointCloud& cloud, const char* id) {
  if (cloud.size() < 4)
    input_error("{}: {} needs at least 4 points for a 3D triangulation, got {}", cloud.name, id,
                cloud.size());
}

ReconstructionReport run_delaunay(const PointCloud& cloud) {
  require_points(cloud, "delaunay");
  const std::vector<Point> pts = cgal_points(cloud);
  g_predicates = 0;
  const auto start = std::chrono::steady_clock::now();
  const CountedDelaunay dt(pts.begin(), pts.end());  // range insertion sorts spatially (Hilbert)
  ReconstructionReport r;
  r.seconds = seconds_since(start);
  r.predicates = g_predicates;
  r.method = "delaunay";
  r.points = cloud.size();
  r.vertices = dt.number_of_vertices();
  if (dt.dimension() < 3)
    input_error("{}: delaunay: all {} points are {} (triangulation dimension {}): no tetrahedra",
                cloud.name, cloud.size(), dt.dimension() == 2 ? "coplanar" : "collinear",
                dt.dimension());
  r.cells = dt.number_of_finite_cells();
  r.facets = dt.number_of_finite_facets();
  r.memory_bytes = dt.number_of_cells() * sizeof(CountedDelaunay::Cell) +
                   dt.number_of_vertices() * sizeof(CountedDelaunay::Vertex);
  return r;
}

ReconstructionReport run_afsr(const PointCloud& cloud) {
  require_points(cloud, "afsr");
  const std::vector<Point> pts = cgal_points(cloud);
  {
    // Advancing front needs a 3D Delaunay; it asserts on coplanar input, so check first (cheap
    // next to the reconstruction itself, and outside the timed region).
    const Delaunay dt(pts.begin(), pts.end());
    if (dt.dimension() < 3)
      input_error("{}: afsr: all {} points are {}: no surface to reconstruct", cloud.name,
                  cloud.size(), dt.dimension() == 2 ? "coplanar" : "collinear");
  }
  std::vector<std::array<std::size_t, 3>> facets;
  const auto start = std::chrono::steady_clock::now();
  CGAL::advancing_front_surface_reconstruction(pts.begin(), pts.end(), std::back_inserter(facets));
  ReconstructionReport r;
  r.seconds = seconds_since(start);
  r.method = "afsr";
  r.points = cloud.size();
  r.vertices = cloud.size();
  r.mesh.vertices = cloud.positions;
  r.mesh.triangles.reserve(facets.size());
  for (const auto& f : facets)
    r.mesh.triangles.push_back({uint32_t(f[0]), uint32_t(f[1]), uint32_t(f[2])});
  r.triangles = r.mesh.triangles.size();
  r.boundary_edges = r.mesh.boundary_edges();
  return r;
}

// A mesh's triangles in CGAL's kernel and the AABB tree over them: the cgal_aabb engine's and the
// distance tree's.
struct TriangleTree {
  using Triangle = Kernel::Triangle_3;
  using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;

  explicit TriangleTree(const TriangleMesh& mesh) {
    auto p = [&](uint32_t v) {
      const Vec3& x = mesh.vertices[v];
      return Point(x.x(), x.y(), x.z());
    };
    triangles.reserve(mesh.triangles.size());
    for (const auto& t : mesh.triangles) triangles.emplace_back(p(t[0]), p(t[1]), p(t[2]));
    tree.insert(triangles.begin(), triangles.end());
    tree.build();
  }
  [[nodiscard]] uint32_t index(Primitive::Id id) const { return uint32_t(id - triangles.begin()); }

  std::vector<Triangle> triangles;
  CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>> tree;
};

// CGAL's AABB tree over the triangles, queried with first_intersection.
class CgalAabbEngine final : public MeshEngine {
 public:
  explicit CgalAabbEngine(const TriangleMesh& mesh) : mesh_(mesh), tris_(mesh) {}

  bool closest_hit(const Ray& ray, Hit& hit, OpCounters& counters) const override {
    counters.add(kCgalRays);
    const Vec3 o = ray.at(ray.tmin);
    const Kernel::Ray_3 r(Point(o.x(), o.y(), o.z()),
                          Kernel::Direction_3(ray.d.x(), ray.d.y(), ray.d.z()));
    const auto found = tris_.tree.first_intersection(r);
    if (!found) return false;
    const Point* x = boost::get<Point>(&found->first);
    if (!x) return false;  // the ray runs inside a triangle's plane: a segment, no single point
    const float t =
        ray.tmin + float((Vec3(float(x->x()), float(x->y()), float(x->z())) - o).dot(ray.d));
    if (!(t < std::min(ray.tmax, hit.t))) return false;
    hit.t = t;
    hit.prim = tris_.index(found->second);
    hit.p = ray.at(t);
    hit.n = mesh_.normal(hit.prim);
    hit.footprint = 0;
    return true;
  }
  [[nodiscard]] size_t memory_bytes() const override {
    // An estimate from element sizes (CGAL reports none): our CGAL triangle copy, the primitive,
    // and a tree node per primitive (a box of 6 doubles, 48 bytes, and two child pointers).
    return tris_.triangles.size() * (sizeof(TriangleTree::Triangle) +
                                     sizeof(TriangleTree::Primitive) + 2 * sizeof(void*) + 48);
  }

 private:
  static inline const Counter kCgalRays{
      "cgal_aabb_rays", "rays traced by CGAL's AABB tree (internal work uncounted)"};
  const TriangleMesh& mesh_;
  TriangleTree tris_;
};

}  // namespace

void register_cgal_backend_reconstructions(ReconstructionRegistry& registry) {
  registry.add(ReconstructionInfo{
      "delaunay",
      "CGAL Delaunay_triangulation_3 of all N points (range insertion, spatially sorted)",
      "O(N log N) expected for uniform points, O(N^2) worst case (thesis 5.1.1)", run_delaunay});
  registry.add(ReconstructionInfo{
      "afsr",
      "CGAL advancing front surface reconstruction (Cohen-Steiner and Da 2004) to a triangle mesh; "
      "builds a full 3D Delaunay first",
      "O(N log N) expected, O(N^2) worst case (its Delaunay, thesis 5.1.1)", run_afsr});
}

void register_cgal_backend_engine(MeshEngineRegistry& registry) {
  registry.add(
      MeshEngineInfo{"cgal_aabb", "CGAL AABB_tree over the triangles, first_intersection per ray",
                     [](const TriangleMesh& mesh, OpCounters&, Timings& timings) {
                       ScopedTimer t(timings, "build");
                       return std::unique_ptr<MeshEngine>(std::make_unique<CgalAabbEngine>(mesh));
                     }});
}

// TriangleDistanceTree: the same tree, for nearest points and box queries.
struct TriangleDistanceTree::Impl : TriangleTree {
  using TriangleTree::TriangleTree;
};

TriangleDistanceTree::TriangleDistanceTree(const TriangleMesh& mesh)
    : impl_(std::make_unique<Impl>(mesh)) {
  impl_->tree.accelerate_distance_queries();
}

TriangleDistanceTree::~TriangleDistanceTree() = default;

TriangleDistanceTree::Closest TriangleDistanceTree::closest(const Vec3& x) const {
  const auto [p, id] = impl_->tree.closest_point_and_primitive(Point(x.x(), x.y(), x.z()));
  return {Vec3(float(p.x()), float(p.y()), float(p.z())), impl_->index(id)};
}

// The box query finds every triangle meeting the cube of half side r, which reaches r sqrt(3) at
// its corners; the exact point-triangle distance keeps those of the ball (issue 30). A Sphere_3
// query would not do: CGAL 5.5's sphere-triangle test is against the sphere's surface and misses a
// triangle lying wholly inside it.
void TriangleDistanceTree::triangles_near(const Vec3& x, float r,
                                          std::vector<uint32_t>& out) const {
  const CGAL::Bbox_3 box(x.x() - r, x.y() - r, x.z() - r, x.x() + r, x.y() + r, x.z() + r);
  std::vector<TriangleTree::Primitive::Id> ids;
  impl_->tree.all_intersected_primitives(box, std::back_inserter(ids));
  const Point c(x.x(), x.y(), x.z());
  const double r2 = double(r) * double(r);
  for (const auto id : ids)
    if (CGAL::squared_distance(c, *id) <= r2) out.push_back(impl_->index(id));
}

}  // namespace pcrt
