#include "render/light.hpp"

#include <tinyexr.h>

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace pcrt {
namespace {

float luminance(const Vec3& c) { return 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z(); }

// The index i with cdf[i] <= u < cdf[i + 1] (cdf ascending from 0 to 1), and u's place in it.
size_t sample_cdf(std::span<const float> cdf, float u, float& within) {
  const auto it = std::upper_bound(cdf.begin() + 1, cdf.end() - 1, u);
  const size_t i = size_t(it - cdf.begin()) - 1;
  const float width = cdf[i + 1] - cdf[i];
  within = width > 0 ? std::clamp((u - cdf[i]) / width, 0.0f, 0.99999994f) : 0.5f;
  return i;
}

// Normalises a running sum into a cdf in place; false (and left as it was) when the sum is 0.
bool normalise_cdf(std::span<float> cdf) {
  const float total = cdf.back();
  if (!(total > 0)) return false;
  for (float& c : cdf) c /= total;
  cdf.back() = 1.0f;
  return true;
}

// The two distances along a unit-direction ray to a sphere's surface (t0 <= t1), or false.
bool sphere_roots(const Vec3& o, const Vec3& d, const Vec3& centre, float radius, float& t0,
                  float& t1) {
  const Vec3 oc = o - centre;
  const float b = oc.dot(d);
  const float c = (oc - b * d).squaredNorm() - radius * radius;  // stable for distant origins
  if (c > 0) return false;
  const float h = std::sqrt(-c);
  t0 = -b - h, t1 = -b + h;
  return true;
}

// Area sampling of the sphere from a point inside it: pdf over solid angle = d^2 / (A |cos|).
std::optional<LightSample> sample_sphere_inside(const Light& l, const Vec3& p, const Vec2& u) {
  const Vec3 n = uniform_sphere(u);
  const Vec3 q = l.position + l.radius * n;
  const Vec3 to_q = q - p;
  const float dist = to_q.norm();
  if (!(dist > 0)) return std::nullopt;
  const Vec3 wi = to_q / dist;
  const float cos_q = std::abs(n.dot(wi));
  if (cos_q <= 0) return std::nullopt;
  const float pdf = dist * dist / (4.0f * kPi * l.radius * l.radius * cos_q);
  return LightSample{wi, l.power, pdf, dist, false};
}

// 1 - cos of the half-angle the sphere subtends from a point at distance dc > r (stable form).
float cone_one_minus_cos(float dc, float radius) {
  const float sin2 = std::min(1.0f, (radius * radius) / (dc * dc));
  return sin2 / (1.0f + std::sqrt(std::max(0.0f, 1.0f - sin2)));
}

// Uniform sampling of the cone the sphere subtends (pbrt-v4's Sphere::Sample from a point).
std::optional<LightSample> sample_sphere(const Light& l, const Vec3& p, const Vec2& u) {
  const Vec3 to_c = l.position - p;
  const float dc = to_c.norm();
  if (dc <= l.radius) return sample_sphere_inside(l, p, u);
  const float one_minus = cone_one_minus_cos(dc, l.radius);
  if (!(one_minus > 0)) return std::nullopt;  // too far (or too small) to subtend a float angle
  const float cos_t = 1.0f - u.x() * one_minus;
  const float sin_t = std::sqrt(std::max(0.0f, 1.0f - cos_t * cos_t));
  const float phi = 2.0f * kPi * u.y();
  const Frame3 frame(to_c / dc);
  const Vec3 wi =
      frame.to_world(Vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t)).normalized();
  float t0, t1;
  const float dist = sphere_roots(p, wi, l.position, l.radius, t0, t1) ? t0 : dc * cos_t;
  return LightSample{wi, l.power, 1.0f / (2.0f * kPi * one_minus), dist, false};
}

Vec3 sky_gradient(const Vec3& d) {
  const float a = 0.5f * (d.z() + 1.0f);
  return (1.0f - a) * Vec3(0.35f, 0.33f, 0.30f) + a * Vec3(0.45f, 0.55f, 0.70f);
}

}  // namespace

EnvironmentMap::EnvironmentMap(int width, int height, std::vector<Vec3> texels)
    : width_(width), height_(height), texels_(std::move(texels)) {
  texel_cdf_.assign(size_t(height_) * size_t(width_ + 1), 0.0f);
  texel_pdf_.assign(texels_.size(), 0.0f);
  row_cdf_.assign(size_t(height_) + 1, 0.0f);
  for (int y = 0; y < height_; ++y) {
    const float sin_t = std::sin(kPi * (float(y) + 0.5f) / float(height_));
    std::span<float> cdf(texel_cdf_.data() + size_t(y) * size_t(width_ + 1), size_t(width_ + 1));
    for (int x = 0; x < width_; ++x)
      cdf[size_t(x) + 1] = cdf[size_t(x)] + luminance(texels_[size_t(y) * width_ + x]) * sin_t;
    row_cdf_[size_t(y) + 1] = row_cdf_[size_t(y)] + cdf.back();
    normalise_cdf(cdf);
  }
  const float total = row_cdf_.back();
  if (!normalise_cdf(row_cdf_)) return;  // black: nothing to sample, pdf 0 everywhere
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const size_t i = size_t(y) * width_ + x;
      const float sin_t = std::sin(kPi * (float(y) + 0.5f) / float(height_));
      texel_pdf_[i] = luminance(texels_[i]) * sin_t / total * float(width_) * float(height_);
    }
}

std::shared_ptr<const EnvironmentMap> EnvironmentMap::load(const std::string& path) {
  float* rgba = nullptr;
  int w = 0, h = 0;
  const char* err = nullptr;
  if (LoadEXR(&rgba, &w, &h, path.c_str(), &err) != TINYEXR_SUCCESS) {
    const std::string why = err ? err : "unreadable";
    if (err) FreeEXRErrorMessage(err);
    input_error("{}: not a readable EXR environment map ({})", path, why);
  }
  if (w <= 0 || h <= 0) {
    std::free(rgba);
    input_error("{}: an environment map of {}x{} texels", path, w, h);
  }
  std::vector<Vec3> texels(size_t(w) * size_t(h));
  for (size_t i = 0; i < texels.size(); ++i)
    texels[i] = Vec3(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]);
  std::free(rgba);
  for (size_t i = 0; i < texels.size(); ++i)
    if (!texels[i].allFinite() || texels[i].minCoeff() < 0)
      input_error("{}: texel {} is negative or not finite", path, i);
  return std::make_shared<const EnvironmentMap>(w, h, std::move(texels));
}

int EnvironmentMap::texel_of(const Vec3& d) const {
  if (!d.allFinite()) return 0;  // a NaN normal upstream must not index out of the map
  const float theta = std::acos(std::clamp(d.z(), -1.0f, 1.0f));
  float phi = std::atan2(d.y(), d.x());
  if (phi < 0) phi += 2.0f * kPi;
  const int x = std::min(width_ - 1, int(phi * (0.5f * kInvPi) * float(width_)));
  const int y = std::min(height_ - 1, int(theta * kInvPi * float(height_)));
  return y * width_ + x;
}

Vec3 EnvironmentMap::radiance(const Vec3& d) const { return texels_[size_t(texel_of(d))]; }

float EnvironmentMap::pdf(const Vec3& d) const {
  const float sin_t = std::sqrt(std::max(0.0f, 1.0f - d.z() * d.z()));
  if (sin_t <= 0) return 0;
  return texel_pdf_[size_t(texel_of(d))] / (2.0f * kPi * kPi * sin_t);
}

Vec3 EnvironmentMap::sample(const Vec2& u, float& pdf) const {
  pdf = 0;
  if (!(row_cdf_.back() > 0)) return Vec3::UnitZ();
  float fy, fx;
  const size_t y = sample_cdf(row_cdf_, u.y(), fy);
  const size_t x = sample_cdf(
      std::span<const float>(texel_cdf_.data() + y * size_t(width_ + 1), size_t(width_ + 1)), u.x(),
      fx);
  const float theta = kPi * (float(y) + fy) / float(height_);
  const float phi = 2.0f * kPi * (float(x) + fx) / float(width_);
  const float sin_t = std::sin(theta);
  const Vec3 d(sin_t * std::cos(phi), sin_t * std::sin(phi), std::cos(theta));
  if (sin_t > 0) pdf = texel_pdf_[y * size_t(width_) + x] / (2.0f * kPi * kPi * sin_t);
  return d;
}

bool is_environment(const Light& light) {
  return light.kind == LightKind::kEnvironment || light.kind == LightKind::kSky;
}

std::optional<LightSample> sample_light(const Light& l, const Vec3& p, const Vec2& u) {
  switch (l.kind) {
    case LightKind::kPoint: {
      const Vec3 to = l.position - p;
      const float d2 = to.squaredNorm();
      if (!(d2 > 0)) return std::nullopt;
      const float d = std::sqrt(d2);
      return LightSample{to / d, l.power / d2, 1.0f, d, true};
    }
    case LightKind::kSphere:
      return sample_sphere(l, p, u);
    case LightKind::kEnvironment:
      if (l.map) {
        LightSample s;
        s.wi = l.map->sample(u, s.pdf);
        if (!(s.pdf > 0)) return std::nullopt;
        s.radiance = l.power.cwiseProduct(l.map->radiance(s.wi));
        return s;
      }
      [[fallthrough]];
    case LightKind::kSky: {
      const Vec3 wi = uniform_sphere(u);
      return LightSample{wi, light_radiance(l, wi), 0.25f * kInvPi, kInfinity, false};
    }
  }
  return std::nullopt;
}

float light_pdf(const Light& l, const Vec3& p, const Vec3& wi) {
  switch (l.kind) {
    case LightKind::kPoint:
      return 0;
    case LightKind::kSphere: {
      float t0, t1;
      if (!sphere_roots(p, wi, l.position, l.radius, t0, t1) || t1 <= 0) return 0;
      const float dc = (l.position - p).norm();
      if (dc > l.radius) {
        const float one_minus = cone_one_minus_cos(dc, l.radius);
        return one_minus > 0 ? 1.0f / (2.0f * kPi * one_minus) : 0.0f;
      }
      const Vec3 q = p + t1 * wi;  // from inside, the far root is the surface seen
      const float cos_q = std::abs((q - l.position).normalized().dot(wi));
      return cos_q > 0 ? t1 * t1 / (4.0f * kPi * l.radius * l.radius * cos_q) : 0;
    }
    case LightKind::kEnvironment:
      if (l.map) return l.map->pdf(wi);
      [[fallthrough]];
    case LightKind::kSky:
      return 0.25f * kInvPi;
  }
  return 0;
}

float intersect_light(const Light& l, const Ray& ray) {
  if (l.kind != LightKind::kSphere) return kInfinity;
  float t0, t1;
  if (!sphere_roots(ray.o, ray.d, l.position, l.radius, t0, t1)) return kInfinity;
  if (t0 >= ray.tmin && t0 < ray.tmax) return t0;
  if (t1 >= ray.tmin && t1 < ray.tmax) return t1;
  return kInfinity;
}

Vec3 light_radiance(const Light& l, const Vec3& d) {
  switch (l.kind) {
    case LightKind::kPoint:
      return Vec3::Zero();
    case LightKind::kSphere:
      return l.power;
    case LightKind::kEnvironment:
      return l.map ? Vec3(l.power.cwiseProduct(l.map->radiance(d))) : l.power;
    case LightKind::kSky:
      return l.power.cwiseProduct(sky_gradient(d));
  }
  return Vec3::Zero();
}

}  // namespace pcrt
