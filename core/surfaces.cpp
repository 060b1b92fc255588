#include "core/surfaces.hpp"

#include <fmt/format.h>

#include <cmath>

namespace pcrt {
namespace {

constexpr float kPi = 3.14159265358979f;

Vec3 uniform_direction(Rng& rng) {
  const float z = 1.0f - 2.0f * rng.uniform();
  const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * kPi * rng.uniform();
  return Vec3(s * std::cos(phi), s * std::sin(phi), z);
}

}  // namespace

bool Surface::intersect(const Ray& ray, float& t, Vec3& n) const {
  float t0 = 0, t1 = 0;
  const Vec3 inv_d = ray.d.cwiseInverse();
  Aabb box = bounds();
  box.extend(box.lo - Vec3::Constant(1e-3f * box.diagonal()));
  box.extend(box.hi + Vec3::Constant(1e-3f * box.diagonal()));
  if (!box.intersect(ray, inv_d, t0, t1)) return false;
  // Relative to the shape's size: a floor of 10^-6 units was the whole of a shape that small.
  const float eps = 1e-6f * box.diagonal();
  const float inv_l = 1.0f / lipschitz();
  float tc = t0;
  const float start_side = signed_distance(ray.at(tc)) >= 0 ? 1.0f : -1.0f;
  for (int i = 0; i < 100000 && tc <= t1; ++i) {
    const float d = signed_distance(ray.at(tc)) * start_side;
    if (d < eps) {
      t = tc;
      n = normal(ray.at(tc));
      return true;
    }
    tc += std::max(d * inv_l, 0.25f * eps);
  }
  return false;
}

std::string SphereSurface::describe() const {
  return fmt::format("sphere radius {} at ({}, {}, {})", radius, center.x(), center.y(),
                     center.z());
}
Aabb SphereSurface::bounds() const {
  return Aabb{center - Vec3::Constant(radius), center + Vec3::Constant(radius)};
}
Vec3 SphereSurface::sample(Rng& rng, Vec3& normal) const {
  normal = uniform_direction(rng);
  return center + radius * normal;
}
bool SphereSurface::intersect(const Ray& ray, float& t, Vec3& n) const {
  // Solve |o + t d - c|^2 = r^2 in double: rays from far away lose the root in float.
  const Vec3d oc = (ray.o - center).cast<double>();
  const Vec3d d = ray.d.cast<double>();
  const double b = oc.dot(d);
  const double c = oc.squaredNorm() - double(radius) * radius;
  const double disc = b * b - d.squaredNorm() * c;
  if (disc < 0) return false;
  const double q = -b - std::copysign(std::sqrt(disc), b);
  double r0 = q / d.squaredNorm();
  double r1 = c / q;
  if (r0 > r1) std::swap(r0, r1);
  for (double r : {r0, r1}) {
    if (r >= ray.tmin && r <= ray.tmax) {
      t = static_cast<float>(r);
      n = normal(ray.at(t));
      return true;
    }
  }
  return false;
}

std::string PlaneSurface::describe() const { return fmt::format("square z=0 of side {}", size); }
float PlaneSurface::signed_distance(const Vec3& x) const {
  const float h = 0.5f * size;
  const float dx = std::max(std::abs(x.x()) - h, 0.0f);
  const float dy = std::max(std::abs(x.y()) - h, 0.0f);
  if (dx == 0 && dy == 0) return x.z();
  const float d = std::sqrt(dx * dx + dy * dy + x.z() * x.z());
  return x.z() < 0 ? -d : d;
}
Aabb PlaneSurface::bounds() const {
  const float h = 0.5f * size;
  return Aabb{Vec3(-h, -h, 0), Vec3(h, h, 0)};
}
Vec3 PlaneSurface::sample(Rng& rng, Vec3& normal) const {
  normal = Vec3::UnitZ();
  return Vec3((rng.uniform() - 0.5f) * size, (rng.uniform() - 0.5f) * size, 0.0f);
}
bool PlaneSurface::intersect(const Ray& ray, float& t, Vec3& n) const {
  if (ray.d.z() == 0) return false;
  const float tc = -ray.o.z() / ray.d.z();
  if (!(tc >= ray.tmin && tc <= ray.tmax)) return false;
  const Vec3 p = ray.at(tc);
  if (std::abs(p.x()) > 0.5f * size || std::abs(p.y()) > 0.5f * size) return false;
  t = tc;
  n = Vec3::UnitZ();
  return true;
}

std::string TorusSurface::describe() const {
  return fmt::format("torus R={} r={} around z", major, minor);
}
float TorusSurface::signed_distance(const Vec3& x) const {
  const float q = std::hypot(x.x(), x.y()) - major;
  return std::hypot(q, x.z()) - minor;
}
Vec3 TorusSurface::normal(const Vec3& x) const {
  const float rho = std::hypot(x.x(), x.y());
  const Vec3 ring = rho > 0 ? Vec3(x.x() / rho * major, x.y() / rho * major, 0) : Vec3(major, 0, 0);
  return (x - ring).normalized();
}
Aabb TorusSurface::bounds() const {
  const float e = major + minor;
  return Aabb{Vec3(-e, -e, -minor), Vec3(e, e, minor)};
}
Vec3 TorusSurface::sample(Rng& rng, Vec3& normal) const {
  // Area element is r (R + r cos theta) dtheta dphi: reject on the theta factor.
  while (true) {
    const float theta = 2.0f * kPi * rng.uniform();
    const float phi = 2.0f * kPi * rng.uniform();
    if (rng.uniform() * (major + minor) > major + minor * std::cos(theta)) continue;
    normal =
        Vec3(std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi), std::sin(theta));
    const float ring = major + minor * std::cos(theta);
    return Vec3(ring * std::cos(phi), ring * std::sin(phi), minor * std::sin(theta));
  }
}

std::string BumpySphereSurface::describe() const {
  return fmt::format("bumpy sphere radius {} amplitude {} frequency {}", radius, amplitude,
                     frequency);
}
float BumpySphereSurface::implicit(const Vec3& x, Vec3* gradient) const {
  const float len = x.norm();
  const Vec3 u = len > 0 ? Vec3(x / len) : Vec3::UnitZ();
  const float f = frequency;
  const float sx = std::sin(f * u.x()), sy = std::sin(f * u.y()), sz = std::sin(f * u.z());
  const float value = len - radius * (1.0f + amplitude * sx * sy * sz);
  if (gradient) {
    const Vec3 ds(f * std::cos(f * u.x()) * sy * sz, f * sx * std::cos(f * u.y()) * sz,
                  f * sx * sy * std::cos(f * u.z()));
    const Vec3 tangential = ds - u * u.dot(ds);
    *gradient = u - radius * amplitude * tangential / std::max(len, 1e-12f);
  }
  return value;
}
float BumpySphereSurface::signed_distance(const Vec3& x) const {
  Vec3 g;
  const float v = implicit(x, &g);
  return v / g.norm();
}
Vec3 BumpySphereSurface::normal(const Vec3& x) const {
  Vec3 g;
  (void)implicit(x, &g);
  return g.normalized();
}
float BumpySphereSurface::lipschitz() const {
  const float rmin = radius * (1.0f - amplitude);
  const float slope = radius * amplitude * frequency * std::sqrt(3.0f) / rmin;
  return std::sqrt(1.0f + slope * slope);
}
Aabb BumpySphereSurface::bounds() const {
  const float e = radius * (1.0f + amplitude);
  return Aabb{Vec3::Constant(-e), Vec3::Constant(e)};
}
Vec3 BumpySphereSurface::sample(Rng& rng, Vec3& normal) const {
  // Radial graph x = r(u) u: dA = r^2 / (n.u) dOmega = r^2 |grad F| dOmega (grad F . u = 1).
  const float rmax = radius * (1.0f + amplitude);
  const float bound = rmax * rmax * lipschitz();
  while (true) {
    const Vec3 u = uniform_direction(rng);
    const float f = frequency;
    const float r = radius * (1.0f + amplitude * std::sin(f * u.x()) * std::sin(f * u.y()) *
                                         std::sin(f * u.z()));
    Vec3 g;
    (void)implicit(r * u, &g);
    if (rng.uniform() * bound > r * r * g.norm()) continue;
    normal = g.normalized();
    return r * u;
  }
}

}  // namespace pcrt
