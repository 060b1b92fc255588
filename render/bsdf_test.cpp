// The BSDFs against their own pdfs and against the optics they model. The chi-square test
// follows pbrt-v4's bsdfs_test.cpp (itself from Mitsuba): sampled directions are binned over the
// sphere and compared with the pdf integrated over each bin.
#include "render/bsdf.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"

using namespace pcrt;

namespace {

// Uniform floats in [0, 1) from the top 24 bits of a 64-bit Mersenne twister (the standard
// float distributions may round up to 1).
class TestRng {
 public:
  explicit TestRng(uint64_t seed) : engine_(seed) {}
  float uniform() { return float(engine_() >> 40) * 0x1p-24f; }
  Vec2 uniform2() {
    const float x = uniform();
    return Vec2(x, uniform());
  }

 private:
  std::mt19937_64 engine_;
};

Material make(MaterialKind kind, float eta = 1.5f, float alpha = 0.1f) {
  Material m;
  m.kind = kind;
  m.albedo = Vec3::Ones();
  m.eta = eta;
  m.alpha = alpha;
  return m;
}

std::string describe(const Material& m, const Vec3& wo) {
  return fmt::format("{} eta {:.4f} alpha {} wo ({:.4f}, {:.4f}, {:.4f})", material_name(m.kind),
                     m.eta, m.alpha, wo.x(), wo.y(), wo.z());
}

bool two_sided(const Material& m) {
  return m.kind == MaterialKind::kDielectric || m.kind == MaterialKind::kRoughDielectric;
}

// A direction at polar angle acos(cos_theta) with some azimuth, so no test sits on an axis.
Vec3 direction(float cos_theta, float phi = 0.7f) {
  const float s = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
  return Vec3(s * std::cos(phi), s * std::sin(phi), cos_theta);
}

float weight(const BsdfSample& s) { return s.f.x() * std::abs(s.wi.z()) / s.pdf; }

// Relative IOR across the surface from wo's side (what a transmitted sample's f is divided by).
float transmitted_eta(const Material& m, const Vec3& wo) {
  return wo.z() > 0 ? m.eta : 1.0f / m.eta;
}

// ---- Chi-square goodness of fit ----

constexpr double kPiDouble = std::numbers::pi;

constexpr int kThetaRes = 80, kPhiRes = 2 * kThetaRes;
constexpr int kChi2Samples = 1000000;
constexpr int kChi2Runs = 5;            // outgoing directions per material
constexpr double kMinExpected = 5;      // cells expecting fewer are pooled
constexpr double kSignificance = 0.01;  // for the whole test, Sidak-corrected per run

int cell_of(const Vec3& w) {
  const double theta = std::acos(std::clamp(double(w.z()), -1.0, 1.0));
  double phi = std::atan2(double(w.y()), double(w.x()));
  if (phi < 0) phi += 2 * kPiDouble;
  const int i = std::clamp(int(theta * kThetaRes / kPiDouble), 0, kThetaRes - 1);
  const int j = std::clamp(int(phi * kPhiRes / (2 * kPiDouble)), 0, kPhiRes - 1);
  return i * kPhiRes + j;
}

// Counts of non-delta sampled directions per cell.
std::vector<double> sampled_counts(const Material& m, const Vec3& wo, int n, TestRng& rng) {
  std::vector<double> counts(kThetaRes * kPhiRes, 0.0);
  for (int s = 0; s < n; ++s) {
    const float uc = rng.uniform();
    const std::optional<BsdfSample> bs = bsdf_sample(m, wo, uc, rng.uniform2());
    if (bs && !bs->delta) counts[size_t(cell_of(bs->wi))] += 1;
  }
  return counts;
}

// The pdf times sin(theta) integrated over [theta0, theta0 + dtheta] x [phi0, phi0 + dphi] by
// 5 x 5 Gauss-Legendre points: cells are small enough for the pdf to be close to a low-order
// polynomial across each, except where the pdf's support ends inside a cell (GGX transmission
// stops abruptly where the generalised half vector reaches the horizon, D being non-zero
// there). A cell with nodes on both sides of such an edge is split in four, recursively.
double integrate_pdf(const Material& m, const Vec3& wo, double theta0, double phi0, double dtheta,
                     double dphi, int depth) {
  static constexpr double kNode[5] = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                      0.5384693101056831, 0.9061798459386640};
  static constexpr double kWeight[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                        0.4786286704993665, 0.2369268850561891};
  double sum = 0;
  int zeros = 0;
  for (int a = 0; a < 5; ++a) {
    const double theta = theta0 + (0.5 + 0.5 * kNode[a]) * dtheta;
    for (int b = 0; b < 5; ++b) {
      const double phi = phi0 + (0.5 + 0.5 * kNode[b]) * dphi;
      const Vec3 wi(float(std::sin(theta) * std::cos(phi)), float(std::sin(theta) * std::sin(phi)),
                    float(std::cos(theta)));
      const double pdf = bsdf_pdf(m, wo, wi);
      zeros += pdf == 0;
      sum += kWeight[a] * kWeight[b] * pdf * std::sin(theta);
    }
  }
  if (zeros == 0 || zeros == 25 || depth == 0) return sum * 0.25 * dtheta * dphi;
  double split = 0;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      split += integrate_pdf(m, wo, theta0 + a * 0.5 * dtheta, phi0 + b * 0.5 * dphi, 0.5 * dtheta,
                             0.5 * dphi, depth - 1);
  return split;
}

// n times the pdf integrated over each cell.
std::vector<double> expected_counts(const Material& m, const Vec3& wo, double n) {
  const double dtheta = kPiDouble / kThetaRes, dphi = 2 * kPiDouble / kPhiRes;
  std::vector<double> expected(kThetaRes * kPhiRes, 0.0);
  for (int i = 0; i < kThetaRes; ++i)
    for (int j = 0; j < kPhiRes; ++j)
      expected[size_t(i * kPhiRes + j)] =
          n * integrate_pdf(m, wo, i * dtheta, j * dphi, dtheta, dphi, 5);
  return expected;
}

// Regularised upper incomplete gamma function Q(a, x) = Gamma(a, x) / Gamma(a): the power
// series of P = 1 - Q below x = a + 1, Lentz's continued fraction for Q above.
double gamma_q(double a, double x) {
  if (x <= 0) return 1.0;
  const double prefix = std::exp(a * std::log(x) - x - std::lgamma(a));
  if (x < a + 1) {
    double term = 1.0 / a, sum = term;
    for (int k = 1; k < 100000 && term > sum * 1e-16; ++k) sum += term *= x / (a + k);
    return std::max(0.0, 1.0 - prefix * sum);
  }
  constexpr double kTiny = 1e-300;
  double b = x + 1 - a, c = 1 / kTiny, d = 1 / b, h = d;
  for (int k = 1; k < 100000; ++k) {
    const double an = -k * (k - a);
    b += 2;
    d = an * d + b;
    c = b + an / c;
    d = 1 / (std::abs(d) < kTiny ? kTiny : d);
    c = std::abs(c) < kTiny ? kTiny : c;
    h *= d * c;
    if (std::abs(d * c - 1) < 1e-16) break;
  }
  return prefix * h;
}

struct Chi2Result {
  double p_value = 0;
  int dof = 0;
  std::string failure;  // why the test could not be run or was rejected outright
};

// Pearson's statistic over the cells, pooling those expecting fewer than kMinExpected samples
// (the statistic is only chi-square distributed for large enough expected counts).
Chi2Result chi2_test(const std::vector<double>& observed, const std::vector<double>& expected) {
  std::vector<size_t> order(observed.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return expected[a] < expected[b]; });
  Chi2Result r;
  double chi2 = 0, pooled_obs = 0, pooled_exp = 0;
  for (size_t i : order) {
    if (expected[i] == 0) {
      // A few samples where the pdf is zero can be rounding; more are a bug.
      if (observed[i] > kChi2Samples * 1e-5)
        r.failure = fmt::format("{} samples in cell {} of zero pdf", observed[i], i);
    } else if (expected[i] < kMinExpected || (pooled_exp > 0 && pooled_exp < kMinExpected)) {
      pooled_obs += observed[i], pooled_exp += expected[i];
    } else {
      chi2 += (observed[i] - expected[i]) * (observed[i] - expected[i]) / expected[i];
      ++r.dof;
    }
  }
  if (pooled_exp > 0) {
    chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++r.dof;
  }
  r.dof -= 1;  // the counts' total is fixed
  if (r.dof < 1 && r.failure.empty()) r.failure = "too few degrees of freedom";
  if (r.failure.empty()) r.p_value = gamma_q(0.5 * r.dof, 0.5 * chi2);
  return r;
}

struct Chi2Case {
  Material m;
  bool both_sides;
};

std::vector<Chi2Case> chi2_cases() {
  std::vector<Chi2Case> cases{{make(MaterialKind::kDiffuse), false}};
  for (float alpha : {0.2f, 0.5f})
    cases.push_back({make(MaterialKind::kRoughConductor, 1.5f, alpha), false});
  for (float eta : {1.5f, 1 / 1.5f})
    for (float alpha : {0.2f, 0.5f})
      cases.push_back({make(MaterialKind::kRoughDielectric, eta, alpha), true});
  return cases;
}

// ---- Sampling the materials ----

struct Estimate {
  double mean = 0;        // of the weight f |cos| / pdf, failed samples counting 0
  double importance = 0;  // the same with transmitted weights times eta'^2 (see the energy test)
};

Estimate estimate(const Material& m, const Vec3& wo, int n, TestRng& rng) {
  Estimate e;
  const float etap = transmitted_eta(m, wo);
  for (int s = 0; s < n; ++s) {
    const float uc = rng.uniform();
    const std::optional<BsdfSample> bs = bsdf_sample(m, wo, uc, rng.uniform2());
    if (!bs) continue;
    const double w = weight(*bs);
    e.mean += w;
    e.importance += bs->transmitted ? w * etap * etap : w;
  }
  e.mean /= n, e.importance /= n;
  return e;
}

double relative_error(double a, double b) {
  return std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-30});
}

}  // namespace

TEST_CASE("bsdf_sample draws directions with the density bsdf_pdf reports (chi-square)", "[bsdf]") {
  // The p-value routine itself: Q(1, x) = exp(-x) and Q(1/2, x) = erfc(sqrt(x)).
  REQUIRE(gamma_q(1.0, 3.0) == Approx(std::exp(-3.0)).epsilon(1e-12));
  REQUIRE(gamma_q(0.5, 0.3) == Approx(std::erfc(std::sqrt(0.3))).epsilon(1e-12));
  REQUIRE(gamma_q(0.5, 9.0) == Approx(std::erfc(3.0)).epsilon(1e-10));

  const std::vector<Chi2Case> cases = chi2_cases();
  const int runs = int(cases.size()) * kChi2Runs;
  const double alpha = 1 - std::pow(1 - kSignificance, 1.0 / runs);
  TestRng rng(7);
  for (const Chi2Case& c : cases)
    for (int k = 0; k < kChi2Runs; ++k) {
      Vec3 wo = cosine_hemisphere(rng.uniform2());
      if (c.both_sides && k % 2 == 1) wo.z() = -wo.z();
      const std::vector<double> observed = sampled_counts(c.m, wo, kChi2Samples, rng);
      const std::vector<double> expected = expected_counts(c.m, wo, kChi2Samples);
      const Chi2Result r = chi2_test(observed, expected);
      INFO(describe(c.m, wo) << ": p = " << r.p_value << " (dof " << r.dof << ", alpha " << alpha
                             << ") " << r.failure);
      CHECK(r.failure.empty());
      CHECK(r.p_value >= alpha);
    }
}

namespace {

// Every non-delta lobe at the roughnesses and IORs the tests cover.
std::vector<Material> non_delta_materials() {
  std::vector<Material> materials{make(MaterialKind::kDiffuse)};
  for (float alpha : {0.2f, 0.5f})
    materials.push_back(make(MaterialKind::kRoughConductor, 1.5f, alpha));
  for (float eta : {1.5f, 1 / 1.5f})
    for (float alpha : {0.2f, 0.5f})
      materials.push_back(make(MaterialKind::kRoughDielectric, eta, alpha));
  return materials;
}

}  // namespace

TEST_CASE("the pdf integrates to the fraction of samples drawn; samples agree with f and pdf",
          "[bsdf]") {
  const std::vector<Material> materials = non_delta_materials();
  TestRng rng(11);
  constexpr int kSamples = 200000;
  for (const Material& m : materials)
    for (float cos_o : {0.95f, 0.6f, 0.2f, -0.9f, -0.4f}) {
      if (cos_o < 0 && !two_sided(m)) continue;
      const Vec3 wo = direction(cos_o);
      INFO(describe(m, wo));
      double integral = 0;
      for (double e : expected_counts(m, wo, 1.0)) integral += e;
      double drawn = 0, worst_weight = 0, worst_pdf = 0, worst_f = 0;
      int delta = 0;
      for (int s = 0; s < kSamples; ++s) {
        const float uc = rng.uniform();
        const std::optional<BsdfSample> bs = bsdf_sample(m, wo, uc, rng.uniform2());
        if (!bs) continue;
        drawn += 1;
        delta += bs->delta;
        const Vec3 f = bsdf_f(m, wo, bs->wi);
        const float pdf = bsdf_pdf(m, wo, bs->wi);
        worst_weight =
            std::max(worst_weight, relative_error(weight(*bs), f.x() * std::abs(bs->wi.z()) / pdf));
        worst_pdf = std::max(worst_pdf, relative_error(bs->pdf, pdf));
        for (int c = 0; c < 3; ++c) worst_f = std::max(worst_f, relative_error(bs->f[c], f[c]));
      }
      drawn /= kSamples;
      INFO("integral " << integral << ", fraction drawn " << drawn);
      CHECK(delta == 0);
      CHECK(integral <= 1.001);
      if (m.kind == MaterialKind::kDiffuse) CHECK(integral == Approx(1).epsilon(1e-4));
      // The samples lost (masked, reflected below the horizon) are exactly the missing mass.
      CHECK(std::abs(integral - drawn) <= 5 * std::sqrt(drawn * (1 - drawn) / kSamples) + 1e-3);
      CHECK(worst_weight < 1e-3);
      CHECK(worst_pdf < 1e-3);
      CHECK(worst_f < 1e-3);
    }
}

TEST_CASE("no material reflects or transmits more energy than arrives (white furnace)", "[bsdf]") {
  std::vector<Material> materials{make(MaterialKind::kDiffuse), make(MaterialKind::kMirror),
                                  make(MaterialKind::kDielectric, 1.5f),
                                  make(MaterialKind::kDielectric, 1 / 1.5f)};
  for (float alpha : {1e-4f, 0.2f, 0.5f, 1.0f})
    materials.push_back(make(MaterialKind::kRoughConductor, 1.5f, alpha));
  for (float eta : {1.5f, 1 / 1.5f})
    for (float alpha : {1e-4f, 0.05f, 0.2f, 0.5f})
      materials.push_back(make(MaterialKind::kRoughDielectric, eta, alpha));
  TestRng rng(13);
  constexpr int kSamples = 100000;
  for (const Material& m : materials)
    for (float cos_o : {0.95f, 0.5f, 0.1f, -0.95f, -0.5f, -0.1f}) {
      if (cos_o < 0 && !two_sided(m)) continue;
      const Vec3 wo = direction(cos_o);
      const Estimate e = estimate(m, wo, kSamples, rng);
      INFO(describe(m, wo) << ": mean weight " << e.mean << ", importance " << e.importance);
      if (!two_sided(m)) {
        CHECK(e.mean < 1.01);
        if (m.kind != MaterialKind::kRoughConductor) CHECK(e.mean == Approx(1).epsilon(1e-5));
        continue;
      }
      // Radiance crossing into a denser medium is compressed into a narrower cone, so the mean
      // radiance weight is R + T / eta'^2, not 1; what is conserved is power, which is the
      // importance-transport weight (transmitted samples times eta'^2).
      CHECK(e.importance < 1.01);
      if (is_delta(m)) {
        CHECK(e.importance == Approx(1).epsilon(1e-4));
        const float r = fresnel_dielectric(wo.z(), m.eta), etap = transmitted_eta(m, wo);
        const double expected = r + (1 - r) / (etap * etap);
        const double spread = std::abs(1 - 1 / (etap * etap)) * std::sqrt(r * (1 - r) / kSamples);
        CHECK(std::abs(e.mean - expected) <= 5 * spread + 1e-6);
      } else {
        CHECK(e.importance > 0.6);  // single scattering loses energy (to 34% here), not most
      }
    }
}

TEST_CASE("the albedo tints every lobe but the conductor's, coloured by eta and k alone",
          "[bsdf]") {
  const Vec3 tint(0.25f, 0.5f, 0.75f);
  std::vector<Material> materials{make(MaterialKind::kDiffuse), make(MaterialKind::kMirror),
                                  make(MaterialKind::kDielectric),
                                  make(MaterialKind::kRoughConductor, 1.5f, 0.3f)};
  for (float alpha : {1e-4f, 0.3f})
    materials.push_back(make(MaterialKind::kRoughDielectric, 1.5f, alpha));
  for (const Material& white : materials)
    for (float cos_o : {0.8f, -0.8f}) {  // inside within the critical angle
      if (cos_o < 0 && !two_sided(white)) continue;
      Material tinted = white;
      tinted.albedo = tint;
      const Vec3 wo = direction(cos_o);
      INFO(describe(white, wo));
      const Vec3 scale = white.kind == MaterialKind::kRoughConductor ? Vec3::Ones() : tint;
      TestRng rng(19);
      int reflected = 0, transmitted = 0, mismatched = 0;
      for (int s = 0; s < 2000; ++s) {
        const float uc = rng.uniform();
        const Vec2 u = rng.uniform2();
        const std::optional<BsdfSample> a = bsdf_sample(white, wo, uc, u);
        const std::optional<BsdfSample> b = bsdf_sample(tinted, wo, uc, u);
        if (!a || !b) {
          mismatched += bool(a) != bool(b);
          continue;
        }
        (a->transmitted ? transmitted : reflected) += 1;
        mismatched += !b->f.isApprox(scale.cwiseProduct(a->f), 1e-6f);
        if (!a->delta)
          mismatched += !bsdf_f(tinted, wo, a->wi)
                             .isApprox(scale.cwiseProduct(bsdf_f(white, wo, a->wi)), 1e-6f);
      }
      CHECK(mismatched == 0);
      CHECK(reflected > 0);
      if (two_sided(white)) CHECK(transmitted > 0);
    }
}

TEST_CASE("one-sided materials neither scatter from below nor into it", "[bsdf]") {
  TestRng rng(23);
  for (const Material& m : {make(MaterialKind::kDiffuse), make(MaterialKind::kMirror),
                            make(MaterialKind::kRoughConductor, 1.5f, 0.3f),
                            make(MaterialKind::kRoughConductor, 1.5f, 1e-4f)}) {
    INFO(describe(m, Vec3::Zero()));
    int scattered = 0;
    for (int s = 0; s < 1000; ++s) {
      const Vec3 a = uniform_sphere(rng.uniform2()), b = uniform_sphere(rng.uniform2());
      const Vec3 above(a.x(), a.y(), std::abs(a.z())), below(b.x(), b.y(), -std::abs(b.z()));
      const float uc = rng.uniform();
      scattered += bsdf_sample(m, below, uc, rng.uniform2()).has_value();
      for (const auto& [wo, wi] : {std::pair(below, above), std::pair(above, below)})
        scattered += !bsdf_f(m, wo, wi).isZero() || bsdf_pdf(m, wo, wi) != 0;
    }
    CHECK(scattered == 0);
  }
}

TEST_CASE("BSDFs are reciprocal; transmission in the generalised form f / eta_o^2", "[bsdf]") {
  // With radiance scaling, f(wo, wi) / eta_o^2 == f(wi, wo) / eta_i^2, where eta_o and eta_i
  // are the absolute IORs on wo's and wi's side (Veach 1997, eq. 5.14 with the roles of the
  // arguments as in pbrt: light arrives along wi). Reflection is plainly symmetric.
  const std::vector<Material> materials = non_delta_materials();
  TestRng rng(17);
  for (const Material& m : materials) {
    INFO(describe(m, Vec3::Zero()));
    int nonzero = 0;
    double worst = 0;
    for (int s = 0; s < 20000; ++s) {
      const Vec3 wo = uniform_sphere(rng.uniform2()), wi = uniform_sphere(rng.uniform2());
      if (!two_sided(m) && (wo.z() <= 0 || wi.z() <= 0)) continue;
      const auto ior = [&](const Vec3& w) { return w.z() > 0 ? 1.0 : double(m.eta); };
      const double forward = bsdf_f(m, wo, wi).x() / (ior(wo) * ior(wo));
      const double backward = bsdf_f(m, wi, wo).x() / (ior(wi) * ior(wi));
      // Far in the tails (f < 1e-6 where it peaks at 0.1 to 10) rounding dominates.
      if (std::max(forward, backward) < 1e-6) continue;
      ++nonzero;
      worst = std::max(worst, relative_error(forward, backward));
    }
    INFO(nonzero << " pairs with f >= 1e-6");
    CHECK(nonzero > 5000);
    CHECK(worst < 1e-3);
  }
}

TEST_CASE("Fresnel reflectance and refraction at known angles", "[bsdf]") {
  const float deg = kPi / 180;
  CHECK(fresnel_dielectric(1.0f, 1.5f) == Approx(0.04).margin(1e-4));
  CHECK(fresnel_dielectric(-1.0f, 1.5f) == Approx(0.04).margin(1e-4));  // from inside
  CHECK(fresnel_dielectric(std::cos(80 * deg), 1.5f) == Approx(0.3877).margin(1e-3));
  const Vec3 wi = direction(std::cos(80 * deg));
  const std::optional<Vec3> wt = refract(wi, Vec3::UnitZ(), 1.5f);
  REQUIRE(wt);
  CHECK(std::acos(-wt->z()) / deg == Approx(41.04).margin(0.01));
  CHECK(wt->norm() == Approx(1).epsilon(1e-6));
  // From inside, towards the surface: total internal reflection beyond asin(1 / 1.5) = 41.81.
  const float critical = std::asin(1 / 1.5f) / deg;
  CHECK(critical == Approx(41.81).margin(0.01));
  for (float theta : {critical + 0.05f, 60.0f, 89.0f}) {
    const Vec3 inside = -direction(std::cos(theta * deg));
    CHECK_FALSE(refract(inside, -Vec3::UnitZ(), 1 / 1.5f));
    CHECK(fresnel_dielectric(inside.z(), 1.5f) == 1.0f);
  }
  const Vec3 below_critical = -direction(std::cos((critical - 0.05f) * deg));
  CHECK(refract(below_critical, -Vec3::UnitZ(), 1 / 1.5f));
  CHECK(fresnel_dielectric(below_critical.z(), 1.5f) < 1.0f);

  const Vec3 eta(0.2f, 0.92f, 1.1f), k(3.9f, 2.45f, 2.14f);
  const Vec3 r0 = fresnel_conductor(1.0f, eta, k);
  for (int c = 0; c < 3; ++c) {
    const float expected =
        ((eta[c] - 1) * (eta[c] - 1) + k[c] * k[c]) / ((eta[c] + 1) * (eta[c] + 1) + k[c] * k[c]);
    CHECK(r0[c] == Approx(expected).epsilon(1e-5));
  }
  // A conductor with k = 0 is a dielectric.
  CHECK(fresnel_conductor(0.3f, Vec3::Constant(1.5f), Vec3::Zero()).x() ==
        Approx(fresnel_dielectric(0.3f, 1.5f)).epsilon(1e-5));
}

TEST_CASE("a ray through a glass slab leaves parallel, displaced by d sin(t - t') / cos t'",
          "[bsdf]") {
  const double thickness = 2.0;
  for (float theta_deg : {10.0f, 30.0f, 45.0f, 70.0f, 85.0f}) {
    const float theta = theta_deg * kPi / 180;
    const Vec3 d = -direction(std::cos(theta), 0.3f);  // travelling down onto the top face z = 0
    const std::optional<Vec3> inside = refract(-d, Vec3::UnitZ(), 1.5f);
    REQUIRE(inside);
    // At the bottom face z = -thickness the ray arrives from the glass above it.
    const Vec3d exit_point = inside->cast<double>() * (thickness / std::abs(inside->z()));
    const std::optional<Vec3> out = refract(-*inside, Vec3::UnitZ(), 1 / 1.5f);
    REQUIRE(out);
    INFO("incidence " << theta_deg << " degrees");
    CHECK((*out - d).norm() < 1e-6f);
    // Distance of the exit point from the line the ray would have followed without the slab.
    const Vec3d dd = d.cast<double>();
    const double displacement = (exit_point - exit_point.dot(dd) * dd).norm();
    const double theta_t = std::asin(std::sin(double(theta)) / 1.5);
    const double expected = thickness * std::sin(double(theta) - theta_t) / std::cos(theta_t);
    CHECK(displacement == Approx(expected).epsilon(1e-5));
  }
}

TEST_CASE("material names round-trip and an unknown one is an input error naming it", "[bsdf]") {
  for (MaterialKind k : {MaterialKind::kDiffuse, MaterialKind::kMirror, MaterialKind::kDielectric,
                         MaterialKind::kRoughConductor, MaterialKind::kRoughDielectric})
    CHECK(material_kind(material_name(k)) == k);
  CHECK(material_kind("rough_dielectric") == MaterialKind::kRoughDielectric);
  CHECK_THROWS_AS(material_kind("velvet"), InputError);
  CHECK_THROWS_WITH(material_kind("velvet"),
                    Catch::Contains("'velvet'") && Catch::Contains("rough_conductor"));
  CHECK_THROWS_AS(material_kind(""), InputError);
}
