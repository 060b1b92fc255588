#include "render/light.hpp"

#include <catch2/catch.hpp>
#include <cmath>

#include "core/rng.hpp"

using namespace pcrt;

namespace {

// A map brighter in one patch, so that its sampling is far from uniform.
EnvironmentMap patchy_map() {
  const int w = 32, h = 16;
  std::vector<Vec3> texels(size_t(w * h), Vec3::Constant(0.1f));
  for (int y = 3; y < 6; ++y)
    for (int x = 20; x < 24; ++x) texels[size_t(y * w + x)] = Vec3(8, 6, 4);
  return EnvironmentMap(w, h, std::move(texels));
}

Vec2 draw(Rng& rng) {
  const float a = rng.uniform();
  return {a, rng.uniform()};
}

}  // namespace

TEST_CASE("an environment map's pdf integrates to 1 and matches what it samples", "[light]") {
  const EnvironmentMap map = patchy_map();
  // The pdf over the sphere, by uniform directions: E[pdf / (1 / 4 pi)] = 1.
  Rng rng(3);
  double integral = 0;
  constexpr int kN = 400000;
  for (int i = 0; i < kN; ++i) integral += double(map.pdf(uniform_sphere(draw(rng)))) * 4 * kPi;
  CHECK(integral / kN == Approx(1.0).epsilon(0.01));
  // Every sampled direction's pdf is the pdf evaluated there; radiance over pdf averages to the
  // map's integral over the sphere (the estimator the renderer uses), which uniform sampling gives.
  // (A direction drawn on a texel's edge may be looked up in its neighbour by rounding.)
  double by_map = 0, by_uniform = 0;
  int mismatched = 0;
  for (int i = 0; i < kN; ++i) {
    float pdf = 0;
    const Vec3 d = map.sample(draw(rng), pdf);
    REQUIRE(pdf > 0);
    mismatched += std::abs(pdf - map.pdf(d)) > 1e-3f * pdf;
    by_map += double(map.radiance(d).x()) / pdf;
    by_uniform += double(map.radiance(uniform_sphere(draw(rng))).x()) * 4 * kPi;
  }
  CHECK(mismatched < kN / 1000);
  CHECK(by_map / kN == Approx(by_uniform / kN).epsilon(0.02));
}

TEST_CASE("a sphere light's pdf is what its sampling draws, from outside and inside", "[light]") {
  Light l;
  l.kind = LightKind::kSphere;
  l.position = Vec3(0.3f, -0.2f, 2.0f);
  l.radius = 0.5f;
  Rng rng(5);
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(0.4f, -0.1f, 2.1f)}) {  // outside, inside
    INFO("from " << p.transpose());
    double solid_angle = 0;
    for (int i = 0; i < 20000; ++i) {
      const auto s = sample_light(l, p, draw(rng));
      REQUIRE(s);
      CHECK(s->pdf == Approx(light_pdf(l, p, s->wi)).epsilon(2e-3));
      // The sampled point lies on the sphere.
      CHECK((p + s->distance * s->wi - l.position).norm() == Approx(l.radius).epsilon(1e-3));
      solid_angle += 1.0 / double(s->pdf);
    }
    // E[1 / pdf] is the solid angle the sphere covers: 4 pi from inside, the cone's from outside.
    const double dc = (l.position - p).norm();
    const double expected = dc > l.radius ? 2 * M_PI * (1 - std::sqrt(1 - l.radius * l.radius / (dc * dc)))
                                          : 4 * M_PI;
    CHECK(solid_angle / 20000 == Approx(expected).epsilon(0.03));
  }
}
