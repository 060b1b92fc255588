// The materials' BSDFs, after pbrt-v4's DiffuseBxDF, ConductorBxDF and DielectricBxDF (Pharr,
// Jakob and Humphreys, 4th edition, chapters 9 and 10) in radiance transport mode.
#include "render/bsdf.hpp"

#include <array>
#include <complex>
#include <string>
#include <utility>

#include "core/error.hpp"

namespace pcrt {

namespace {

constexpr std::array<std::pair<std::string_view, MaterialKind>, 5> kMaterialNames{{
    {"diffuse", MaterialKind::kDiffuse},
    {"mirror", MaterialKind::kMirror},
    {"dielectric", MaterialKind::kDielectric},
    {"rough_conductor", MaterialKind::kRoughConductor},
    {"rough_dielectric", MaterialKind::kRoughDielectric},
}};

// Below this alpha GGX is narrower than float can sample and evaluate reliably, so rough
// materials behave as their perfectly specular counterparts (pbrt-v4's EffectivelySmooth).
constexpr float kSmoothAlpha = 1e-3f;

bool effectively_smooth(const Material& m) { return m.alpha < kSmoothAlpha; }

// An index-matched dielectric does not bend light; pbrt-v4 treats it as specular too, which
// also avoids the generalised half vector wo + wi vanishing for straight-through pairs.
bool smooth_dielectric(const Material& m) { return effectively_smooth(m) || m.eta == 1.0f; }

Vec3 mirror_direction(const Vec3& wo) { return Vec3(-wo.x(), -wo.y(), wo.z()); }

Vec3 reflect(const Vec3& wo, const Vec3& n) { return 2.0f * wo.dot(n) * n - wo; }

// The isotropic Trowbridge-Reitz (GGX) microfacet distribution with height-correlated Smith
// masking, as pbrt-v4's TrowbridgeReitzDistribution with alpha_x = alpha_y.
struct Ggx {
  float alpha;

  // D(wm) = 1 / (pi a^2 cos^4 (1 + tan^2 / a^2)^2), rewritten so that it needs no tangent.
  [[nodiscard]] float d(const Vec3& wm) const {
    const float a2 = alpha * alpha;
    const float t = (a2 - 1.0f) * wm.z() * wm.z() + 1.0f;
    return a2 / (kPi * t * t);
  }
  // Smith's Lambda; w must not be grazing (callers reject cos = 0 first).
  [[nodiscard]] float lambda(const Vec3& w) const {
    const float cos2 = w.z() * w.z();
    const float tan2 = std::max(0.0f, 1.0f - cos2) / cos2;
    return 0.5f * (std::sqrt(1.0f + alpha * alpha * tan2) - 1.0f);
  }
  [[nodiscard]] float g1(const Vec3& w) const { return 1.0f / (1.0f + lambda(w)); }
  [[nodiscard]] float g(const Vec3& wo, const Vec3& wi) const {
    return 1.0f / (1.0f + lambda(wo) + lambda(wi));
  }
  // Density of the normals visible from w (w.z > 0): G1(w) max(0, w.wm) D(wm) / cos w.
  [[nodiscard]] float d_visible(const Vec3& w, const Vec3& wm) const {
    return g1(w) * std::max(0.0f, w.dot(wm)) * d(wm) / w.z();
  }
  [[nodiscard]] Vec3 sample_visible(const Vec3& w, const Vec2& u) const;
};

// Heitz (2018), "Sampling the GGX distribution of visible normals", in pbrt-v4's form: stretch w
// to the unit-roughness configuration, sample the projected hemisphere there, stretch back.
Vec3 Ggx::sample_visible(const Vec3& w, const Vec2& u) const {
  Vec3 wh = Vec3(alpha * w.x(), alpha * w.y(), w.z()).normalized();
  if (wh.z() < 0) wh = -wh;
  const Vec3 t1 = wh.z() < 0.99999f ? Vec3(-wh.y(), wh.x(), 0).normalized() : Vec3::UnitX();
  const Vec3 t2 = wh.cross(t1);
  const float r = std::sqrt(u.x()), phi = 2.0f * kPi * u.y();
  const float px = r * std::cos(phi);
  // Squeeze the disk's far half onto the part of the hemisphere's projection w can see.
  const float s = 0.5f * (1.0f + wh.z()), h = std::sqrt(1.0f - px * px);
  const float py = (1.0f - s) * h + s * r * std::sin(phi);
  const float pz = std::sqrt(std::max(0.0f, 1.0f - px * px - py * py));
  const Vec3 nh = px * t1 + py * t2 + pz * wh;
  return Vec3(alpha * nh.x(), alpha * nh.y(), std::max(1e-6f, nh.z())).normalized();
}

// ---- Lambertian ----

Vec3 diffuse_f(const Material& m, const Vec3& wo, const Vec3& wi) {
  return wo.z() > 0 && wi.z() > 0 ? Vec3(m.albedo * kInvPi) : Vec3::Zero();
}

float diffuse_pdf(const Vec3& wo, const Vec3& wi) {
  return wo.z() > 0 && wi.z() > 0 ? wi.z() * kInvPi : 0.0f;
}

std::optional<BsdfSample> diffuse_sample(const Material& m, const Vec3& wo, const Vec2& u) {
  if (wo.z() <= 0) return std::nullopt;
  const Vec3 wi = cosine_hemisphere(u);
  if (wi.z() <= 0) return std::nullopt;
  return BsdfSample{wi, m.albedo * kInvPi, wi.z() * kInvPi, false, false};
}

// ---- Perfect specular reflection and refraction ----

std::optional<BsdfSample> mirror_sample(const Vec3& wo, const Vec3& weight) {
  if (wo.z() <= 0) return std::nullopt;
  const Vec3 wi = mirror_direction(wo);
  return BsdfSample{wi, weight / wi.z(), 1.0f, true, false};
}

// Reflect with probability R, refract with probability T = 1 - R; both weights are then the
// tint alone, the refracted one divided by eta'^2 for radiance.
std::optional<BsdfSample> smooth_dielectric_sample(const Material& m, const Vec3& wo, float uc) {
  if (wo.z() == 0) return std::nullopt;
  const float r = fresnel_dielectric(wo.z(), m.eta);
  if (uc < r) {
    const Vec3 wi = mirror_direction(wo);
    return BsdfSample{wi, m.albedo * (r / std::abs(wi.z())), r, true, false};
  }
  const bool entering = wo.z() > 0;
  const float etap = entering ? m.eta : 1.0f / m.eta;
  const std::optional<Vec3> wi = refract(wo, Vec3(0, 0, entering ? 1.0f : -1.0f), etap);
  if (!wi || wi->z() == 0) return std::nullopt;  // R < 1 rules out TIR but for rounding
  const float t = 1.0f - r;
  return BsdfSample{*wi, m.albedo * (t / (std::abs(wi->z()) * etap * etap)), t, true, true};
}

// ---- GGX conductor ----

Vec3 conductor_f_at(const Material& m, const Ggx& ggx, const Vec3& wo, const Vec3& wi,
                    const Vec3& wm) {
  const Vec3 fresnel = fresnel_conductor(wo.dot(wm), m.conductor_eta, m.conductor_k);
  return fresnel * (ggx.d(wm) * ggx.g(wo, wi) / (4.0f * wo.z() * wi.z()));
}

float conductor_pdf_at(const Ggx& ggx, const Vec3& wo, const Vec3& wm) {
  return ggx.d_visible(wo, wm) / (4.0f * wo.dot(wm));
}

// The half vector of a pair both above the surface; empty otherwise.
std::optional<Vec3> half_vector(const Vec3& wo, const Vec3& wi) {
  if (wo.z() <= 0 || wi.z() <= 0) return std::nullopt;
  const Vec3 wm = wo + wi;
  if (wm.squaredNorm() == 0) return std::nullopt;
  return wm.normalized();
}

Vec3 conductor_f(const Material& m, const Vec3& wo, const Vec3& wi) {
  const std::optional<Vec3> wm = half_vector(wo, wi);
  if (effectively_smooth(m) || !wm) return Vec3::Zero();
  return conductor_f_at(m, Ggx{m.alpha}, wo, wi, *wm);
}

float conductor_pdf(const Material& m, const Vec3& wo, const Vec3& wi) {
  const std::optional<Vec3> wm = half_vector(wo, wi);
  if (effectively_smooth(m) || !wm) return 0.0f;
  return conductor_pdf_at(Ggx{m.alpha}, wo, *wm);
}

std::optional<BsdfSample> conductor_sample(const Material& m, const Vec3& wo, const Vec2& u) {
  if (wo.z() <= 0) return std::nullopt;
  if (effectively_smooth(m))
    return mirror_sample(wo, fresnel_conductor(wo.z(), m.conductor_eta, m.conductor_k));
  const Ggx ggx{m.alpha};
  const Vec3 wm = ggx.sample_visible(wo, u);
  const Vec3 wi = reflect(wo, wm);
  if (wi.z() <= 0) return std::nullopt;  // reflected below the horizon: masked, lost
  const float pdf = conductor_pdf_at(ggx, wo, wm);
  if (!(pdf > 0)) return std::nullopt;
  return BsdfSample{wi, conductor_f_at(m, ggx, wo, wi, wm), pdf, false, false};
}

// ---- GGX dielectric ----

// 1 - R for a refraction pair given both cosines (each on its own side) and eta' = transmitted
// over incident IOR. Equal to 1 - fresnel_dielectric(cos_i, eta') but without Snell's square
// root and the cancellation in 1 - R, so it stays accurate near the critical angle, where
// cos_t -> 0, and is symmetric in the pair (reciprocity holds to rounding).
float fresnel_transmittance(float cos_i, float cos_t, float etap) {
  const float parallel = etap * cos_i + cos_t, perpendicular = cos_i + etap * cos_t;
  return 2.0f * etap * cos_i * cos_t *
         (1.0f / (parallel * parallel) + 1.0f / (perpendicular * perpendicular));
}

// A rough dielectric lobe's scalar f (before the tint) and pdf for wo and wi scattered by the
// microfacet wm (wm.z > 0), with eta' = etap for transmission and 1 for reflection.
struct LobeValue {
  float f = 0;
  float pdf = 0;
};

LobeValue dielectric_lobe(const Material& m, const Ggx& ggx, const Vec3& wo, const Vec3& wi,
                          const Vec3& wm, float etap) {
  const float cos_o = wo.z(), cos_i = wi.z();
  const float wo_m = wo.dot(wm), wi_m = wi.dot(wm);
  const float d_times_g = ggx.d(wm) * ggx.g(wo, wi);
  // Normals are drawn as seen from wo flipped above the surface (so wm.z > 0 either way).
  const float visible = ggx.d_visible(cos_o > 0 ? wo : Vec3(-wo), wm);
  if (cos_o * cos_i > 0) {
    const float r = fresnel_dielectric(wo_m, m.eta);
    return {d_times_g * r / std::abs(4.0f * cos_i * cos_o), visible * r / (4.0f * std::abs(wo_m))};
  }
  // Transmission: dwm/dwi = |wi.wm| / (wi.wm + wo.wm / eta')^2 (Walter et al. 2007).
  const float denom = (wi_m + wo_m / etap) * (wi_m + wo_m / etap);
  const float t = fresnel_transmittance(std::abs(wo_m), std::abs(wi_m), etap);
  const float f = t * d_times_g * std::abs(wi_m * wo_m / (cos_i * cos_o * denom)) / (etap * etap);
  return {f, visible * std::abs(wi_m) / denom * t};
}

// Relative IOR of the side opposite wo over wo's side.
float transmitted_eta(const Material& m, const Vec3& wo) {
  return wo.z() > 0 ? m.eta : 1.0f / m.eta;
}

// The generalised half vector wm ~ wo + eta' wi of a pair, facing +z; empty when no microfacet
// facing both directions from their own sides scatters one into the other.
std::optional<Vec3> dielectric_half_vector(const Material& m, const Vec3& wo, const Vec3& wi) {
  const float cos_o = wo.z(), cos_i = wi.z();
  if (cos_o == 0 || cos_i == 0) return std::nullopt;
  const float etap = cos_o * cos_i > 0 ? 1.0f : transmitted_eta(m, wo);
  Vec3 wm = wo + etap * wi;
  if (wm.squaredNorm() == 0) return std::nullopt;
  wm.normalize();
  if (wm.z() < 0) wm = -wm;
  if (wm.dot(wi) * cos_i < 0 || wm.dot(wo) * cos_o < 0) return std::nullopt;  // back-facing
  return wm;
}

LobeValue rough_dielectric_value(const Material& m, const Vec3& wo, const Vec3& wi) {
  const std::optional<Vec3> wm = dielectric_half_vector(m, wo, wi);
  if (smooth_dielectric(m) || !wm) return {};
  return dielectric_lobe(m, Ggx{m.alpha}, wo, wi, *wm, transmitted_eta(m, wo));
}

std::optional<BsdfSample> rough_dielectric_sample(const Material& m, const Vec3& wo, float uc,
                                                  const Vec2& u) {
  if (smooth_dielectric(m)) return smooth_dielectric_sample(m, wo, uc);
  if (wo.z() == 0) return std::nullopt;
  // Sample about the side wo is on, as pbrt-v4 does: wm faces +z, wo.wm has wo.z's sign.
  const Ggx ggx{m.alpha};
  const bool outside = wo.z() > 0;
  const Vec3 wm = ggx.sample_visible(outside ? wo : Vec3(-wo), u);
  const float etap = transmitted_eta(m, wo);
  const bool reflected = uc < fresnel_dielectric(wo.dot(wm), m.eta);
  const std::optional<Vec3> wi = reflected ? std::optional<Vec3>(reflect(wo, wm))
                                           : refract(wo, outside ? wm : Vec3(-wm), etap);
  // A reflection below, or a refraction staying on wo's side, is masked by the surface.
  if (!wi || wi->z() == 0 || (wi->z() * wo.z() > 0) != reflected) return std::nullopt;
  const LobeValue v = dielectric_lobe(m, ggx, wo, *wi, wm, etap);
  if (!(v.pdf > 0)) return std::nullopt;
  return BsdfSample{*wi, m.albedo * v.f, v.pdf, false, !reflected};
}

}  // namespace

MaterialKind material_kind(std::string_view name) {
  for (const auto& [n, kind] : kMaterialNames)
    if (n == name) return kind;
  std::string known;
  for (const auto& [n, kind] : kMaterialNames) {
    if (!known.empty()) known += ", ";
    known += n;
  }
  input_error("unknown material '{}' (known: {})", name, known);
}

std::string_view material_name(MaterialKind kind) {
  for (const auto& [n, k] : kMaterialNames)
    if (k == kind) return n;
  return "unknown";
}

bool is_delta(const Material& m) {
  switch (m.kind) {
    case MaterialKind::kDiffuse:
      return false;
    case MaterialKind::kMirror:
    case MaterialKind::kDielectric:
      return true;
    case MaterialKind::kRoughConductor:
      return effectively_smooth(m);
    case MaterialKind::kRoughDielectric:
      return smooth_dielectric(m);
  }
  return false;
}

Vec3 bsdf_f(const Material& m, const Vec3& wo, const Vec3& wi) {
  switch (m.kind) {
    case MaterialKind::kDiffuse:
      return diffuse_f(m, wo, wi);
    case MaterialKind::kMirror:
    case MaterialKind::kDielectric:
      return Vec3::Zero();
    case MaterialKind::kRoughConductor:
      return conductor_f(m, wo, wi);
    case MaterialKind::kRoughDielectric:
      return m.albedo * rough_dielectric_value(m, wo, wi).f;
  }
  return Vec3::Zero();
}

float bsdf_pdf(const Material& m, const Vec3& wo, const Vec3& wi) {
  switch (m.kind) {
    case MaterialKind::kDiffuse:
      return diffuse_pdf(wo, wi);
    case MaterialKind::kMirror:
    case MaterialKind::kDielectric:
      return 0.0f;
    case MaterialKind::kRoughConductor:
      return conductor_pdf(m, wo, wi);
    case MaterialKind::kRoughDielectric:
      return rough_dielectric_value(m, wo, wi).pdf;
  }
  return 0.0f;
}

std::optional<BsdfSample> bsdf_sample(const Material& m, const Vec3& wo, float uc, const Vec2& u) {
  switch (m.kind) {
    case MaterialKind::kDiffuse:
      return diffuse_sample(m, wo, u);
    case MaterialKind::kMirror:
      return mirror_sample(wo, m.albedo);
    case MaterialKind::kDielectric:
      return smooth_dielectric_sample(m, wo, uc);
    case MaterialKind::kRoughConductor:
      return conductor_sample(m, wo, u);
    case MaterialKind::kRoughDielectric:
      return rough_dielectric_sample(m, wo, uc, u);
  }
  return std::nullopt;
}

float fresnel_dielectric(float cos_i, float eta) {
  cos_i = std::clamp(cos_i, -1.0f, 1.0f);
  if (cos_i < 0) {  // arriving from inside: the interface seen the other way round
    eta = 1.0f / eta;
    cos_i = -cos_i;
  }
  const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return 1.0f;  // total internal reflection
  const float cos_t = std::sqrt(std::max(0.0f, 1.0f - sin2_t));
  const float r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const float r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (r_parallel * r_parallel + r_perpendicular * r_perpendicular);
}

namespace {

// The Fresnel equations with a complex IOR: the refracted "angle" is complex too (pbrt-v4's
// FrComplex), and the reflectance is the mean of the two polarisations' |r|^2.
float fresnel_complex(float cos_i, std::complex<float> eta) {
  cos_i = std::clamp(cos_i, 0.0f, 1.0f);
  const std::complex<float> sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
  const std::complex<float> cos_t = std::sqrt(1.0f - sin2_t);
  const std::complex<float> r_parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const std::complex<float> r_perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return 0.5f * (std::norm(r_parallel) + std::norm(r_perpendicular));
}

}  // namespace

Vec3 fresnel_conductor(float cos_i, const Vec3& eta, const Vec3& k) {
  return Vec3(fresnel_complex(cos_i, {eta.x(), k.x()}), fresnel_complex(cos_i, {eta.y(), k.y()}),
              fresnel_complex(cos_i, {eta.z(), k.z()}));
}

std::optional<Vec3> refract(const Vec3& wi, const Vec3& n, float eta) {
  const float cos_i = n.dot(wi);
  const float sin2_t = std::max(0.0f, 1.0f - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1.0f) return std::nullopt;  // total internal reflection
  const float cos_t = std::sqrt(1.0f - sin2_t);
  return Vec3(-wi / eta + (cos_i / eta - cos_t) * n);
}

}  // namespace pcrt
