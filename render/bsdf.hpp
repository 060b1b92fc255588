// Materials and their BSDFs (thesis chapter 4), in the shape pbrt-v4 and Mitsuba 3 give them: a
// BSDF evaluates f, samples a direction with its pdf and reports the pdf. A Material is a small
// tagged value dispatched by a switch, so shading allocates nothing and calls nothing virtual.
//
// Every direction is in the local shading frame: z is the shading normal on the side the
// outgoing direction wo lies (the integrator flips the frame so that wo.z >= 0, except for
// dielectrics, which have two sides and see wo.z < 0 from inside). wo and wi both point away
// from the surface. f is the BSDF alone (no cosine); the estimator's weight is f |cos wi| / pdf.
// Transmission scales radiance by 1/eta^2 (radiance, not importance, is transported).
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "core/geometry.hpp"
#include "render/sampling.hpp"

namespace pcrt {

enum class MaterialKind : uint8_t {
  kDiffuse,          // Lambertian, reflectance `albedo`
  kMirror,           // perfect specular reflection tinted by `albedo` (delta)
  kDielectric,       // smooth glass: Fresnel, Snell, total internal reflection (delta)
  kRoughConductor,   // GGX microfacets with the conductor Fresnel of (eta, k) per channel
  kRoughDielectric,  // GGX microfacets, dielectric Fresnel, reflection and transmission
};

// The names scene files and --material use; unknown names are an InputError naming the value.
MaterialKind material_kind(std::string_view name);
std::string_view material_name(MaterialKind kind);

struct Material {
  MaterialKind kind = MaterialKind::kDiffuse;
  Vec3 albedo = Vec3::Constant(0.75f);  // diffuse reflectance; tint of mirror and glass lobes
  float eta = 1.5f;    // dielectrics: index of refraction inside over outside (> 0, != 1 ok)
  float alpha = 0.1f;  // GGX roughness alpha (isotropic), in [1e-3, 1]
  Vec3 conductor_eta = Vec3(0.2f, 0.92f, 1.1f);  // conductor IOR per channel (gold-like)
  Vec3 conductor_k = Vec3(3.9f, 2.45f, 2.14f);   // conductor absorption per channel
  Vec3 emission = Vec3::Zero();                  // radiance emitted from either side (area lights)
};

// Whether every lobe of the material is a delta distribution (mirror, smooth glass): light
// sampling is then useless and the sampled direction is followed with weight f |cos| / pdf.
[[nodiscard]] bool is_delta(const Material& m);

struct BsdfSample {
  Vec3 wi = Vec3::UnitZ();
  Vec3 f = Vec3::Zero();  // for delta lobes: the lobe's weight times pdf / |cos wi|, so that
                          // f |cos wi| / pdf is the path weight as for every other lobe
  float pdf = 0;          // solid-angle density; for delta lobes the discrete lobe probability
  bool delta = false;
  bool transmitted = false;
};

// f(wo, wi): zero for delta materials and for directions their lobes cannot reach.
[[nodiscard]] Vec3 bsdf_f(const Material& m, const Vec3& wo, const Vec3& wi);
// The solid-angle pdf bsdf_sample draws wi with; zero for delta materials.
[[nodiscard]] float bsdf_pdf(const Material& m, const Vec3& wo, const Vec3& wi);
// A direction drawn from the material's lobes: u picks the direction, uc the lobe (reflection or
// transmission); materials with one lobe ignore uc. Empty when no direction is drawn (below the
// horizon, a masked microfacet, zero pdf).
[[nodiscard]] std::optional<BsdfSample> bsdf_sample(const Material& m, const Vec3& wo, float uc,
                                                    const Vec2& u);

// Fresnel reflectance of a smooth dielectric interface; cos_i is measured on the side of the
// incident direction's medium when positive, from inside (eta inverted) when negative.
[[nodiscard]] float fresnel_dielectric(float cos_i, float eta);
// Fresnel reflectance of a conductor with complex IOR eta + i k, for unpolarised light.
[[nodiscard]] Vec3 fresnel_conductor(float cos_i, const Vec3& eta, const Vec3& k);
// The direction refracted from wi about n (both on the same side, unit) with relative IOR eta
// (transmitted side over incident side); empty on total internal reflection.
[[nodiscard]] std::optional<Vec3> refract(const Vec3& wi, const Vec3& n, float eta);

}  // namespace pcrt
