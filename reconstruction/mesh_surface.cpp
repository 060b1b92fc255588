#include "reconstruction/mesh_surface.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace pcrt {
namespace {

double triangle_area(const TriangleMesh& m, const std::array<uint32_t, 3>& t) {
  const Vec3d a = m.vertices[t[0]].cast<double>();
  return 0.5 *
         (m.vertices[t[1]].cast<double>() - a).cross(m.vertices[t[2]].cast<double>() - a).norm();
}

float angle_deg(const Vec3& a, const Vec3& b) {
  return float(std::atan2(double(a.cross(b).norm()), double(a.dot(b))) * 180.0 / M_PI);
}

}  // namespace

MeshSurface::MeshSurface(TriangleMesh mesh, std::string name, const std::string& engine)
    : mesh_(std::move(mesh)), name_(std::move(name)) {
  // Sampled points take their normals from the faces: an inward-facing mesh would hand every
  // method normals pointing in.
  orient_outward(mesh_);
  bounds_ = mesh_.bounds();
  cumulative_area_.reserve(mesh_.triangles.size());
  vertex_normals_.assign(mesh_.vertices.size(), Vec3::Zero());
  double total = 0;
  for (uint32_t i = 0; i < mesh_.triangles.size(); ++i) {
    const double a = triangle_area(mesh_, mesh_.triangles[i]);
    total += a;
    cumulative_area_.push_back(total);
    for (uint32_t v : mesh_.triangles[i]) vertex_normals_[v] += float(a) * mesh_.normal(i);
  }
  if (!(total > 0)) input_error("{}: the mesh has zero area", name_);
  for (Vec3& n : vertex_normals_) n = n.norm() > 0 ? Vec3(n.normalized()) : Vec3::UnitZ();

  tree_ = std::make_unique<TriangleDistanceTree>(mesh_);

  OpCounters build_counters;
  Timings build_timings;
  engine_ = MeshEngineRegistry::instance()
                .get(engine, "mesh engine")
                .create(mesh_, build_counters, build_timings);
}

MeshSurface::~MeshSurface() = default;

std::string MeshSurface::describe() const {
  return fmt::format("mesh {} ({} triangles, area {:.6g})", name_, mesh_.triangles.size(), area());
}

TriangleDistanceTree::Closest MeshSurface::closest(const Vec3& x) const {
  return tree_->closest(x);
}

float MeshSurface::signed_distance(const Vec3& x) const {
  const TriangleDistanceTree::Closest c = closest(x);
  const float d = (x - c.point).norm();
  return mesh_.normal(c.triangle).dot(x - c.point) < 0 ? -d : d;
}

Vec3 MeshSurface::normal(const Vec3& x) const { return mesh_.normal(closest(x).triangle); }

Vec3 MeshSurface::sample(Rng& rng, Vec3& normal) const {
  const double u = rng.uniform_double() * area();
  const auto it = std::upper_bound(cumulative_area_.begin(), cumulative_area_.end(), u);
  const auto i = uint32_t(
      std::min<size_t>(size_t(it - cumulative_area_.begin()), cumulative_area_.size() - 1));
  const auto& t = mesh_.triangles[i];
  // Uniform in the triangle: the square root keeps the density flat (Osada et al. 2002).
  const float r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
  normal = mesh_.normal(i);
  return (1 - r1) * mesh_.vertices[t[0]] + r1 * (1 - r2) * mesh_.vertices[t[1]] +
         r1 * r2 * mesh_.vertices[t[2]];
}

bool MeshSurface::intersect(const Ray& ray, float& t, Vec3& n) const {
  OpCounters uncounted;  // the truth's work is not a method's work
  Hit hit;
  if (!engine_->closest_hit(ray, hit, uncounted)) return false;
  t = hit.t;
  n = hit.n;
  return true;
}

// The ball is centred on the surface point nearest x, as Surface says: around a point off the
// surface (a phantom hit) it would otherwise judge the shape at the wrong place. Every pair of
// faces counts, not only the nearest face against the others: "faces more than 15 degrees apart"
// (a ridge between two faces each 10 degrees off the nearest one is 20 degrees wide).
float MeshSurface::normal_spread_deg(const Vec3& x, float radius) const {
  const TriangleDistanceTree::Closest c = closest(x);
  std::vector<uint32_t> near;
  tree_->triangles_near(c.point, radius, near);
  // The widest pair has the smallest dot product; a ball of a few h holds a few dozen faces.
  Vec3 a = mesh_.normal(c.triangle), b = a;
  float lowest = 1;
  for (size_t i = 0; i < near.size(); ++i)
    for (size_t j = i + 1; j < near.size(); ++j) {
      const Vec3 u = mesh_.normal(near[i]), v = mesh_.normal(near[j]);
      if (const float d = u.dot(v); d < lowest) lowest = d, a = u, b = v;
    }
  return angle_deg(a, b);
}

Vec3 MeshSurface::smooth_normal(const Vec3& x) const {
  const TriangleDistanceTree::Closest c = closest(x);
  const auto& t = mesh_.triangles[c.triangle];
  const Vec3d a = mesh_.vertices[t[0]].cast<double>(), b = mesh_.vertices[t[1]].cast<double>(),
              d = mesh_.vertices[t[2]].cast<double>(), p = c.point.cast<double>();
  // Barycentric coordinates of the closest point, by sub-triangle areas; in double, where the
  // areas' squares of a triangle with edges of 1e9 stay finite.
  const Vec3d full = (b - a).cross(d - a);
  const double area2 = full.squaredNorm();
  const double wb = area2 > 0 ? (p - a).cross(d - a).dot(full) / area2 : 0;
  const double wd = area2 > 0 ? (b - a).cross(p - a).dot(full) / area2 : 0;
  const Vec3 n = float(1 - wb - wd) * vertex_normals_[t[0]] + float(wb) * vertex_normals_[t[1]] +
                 float(wd) * vertex_normals_[t[2]];
  return n.norm() > 0 ? Vec3(n.normalized()) : mesh_.normal(c.triangle);
}

}  // namespace pcrt
