// The frame comparison on hand-made frames, and end to end: a mesh against itself agrees.
#include "render/compare.hpp"

#include <catch2/catch.hpp>

using namespace pcrt;

namespace {

RenderResult frame(int w, int h) {
  RenderResult r{Image(w, h), Image(w, h), Image(w, h), {}, 0, 0, {}, {}};
  r.primary_t.assign(size_t(w) * size_t(h), kInfinity);
  r.primary_n.assign(r.primary_t.size(), Vec3::Zero());
  return r;
}

}  // namespace

TEST_CASE("Frame comparison counts missing, extra and normal-off pixels", "[compare]") {
  RenderResult truth = frame(4, 1), method = frame(4, 1);
  // Pixel 0: both hit, same normal. 1: truth only. 2: method only. 3: both, normals 45 deg apart.
  for (size_t i : {0u, 1u, 3u}) truth.primary_t[i] = 1, truth.primary_n[i] = Vec3::UnitZ();
  for (size_t i : {0u, 2u}) method.primary_t[i] = 1, method.primary_n[i] = Vec3::UnitZ();
  method.primary_t[3] = 1, method.primary_n[3] = Vec3(1, 0, 1).normalized();
  truth.image.at(1, 0) = Vec3::Ones();
  const FrameComparison c = compare_frames(truth, method);
  CHECK(c.object_pixels == 3);
  CHECK(c.missing == 1);
  CHECK(c.extra == 1);
  CHECK(c.normal_off == 1);
  CHECK(c.missing_rate() == Approx(1.0 / 3));
  CHECK(c.rmse == Approx(std::sqrt(1.0 / 4)));
  const Image d = difference_image(truth, method);
  CHECK(d.at(1, 0).isApprox(Vec3(1, 0, 0)));  // missing: red
  CHECK(d.at(0, 0).isZero());                 // agreeing, same radiance: black
}

TEST_CASE("Missing pixels at silhouettes and contours are told from interior ones", "[compare]") {
  RenderResult truth = frame(12, 12), method = frame(12, 12);
  // Truth: a 10x10 square at depth 1 with a 3x3 patch at depth 2 in its corner (a contour).
  for (int y = 1; y <= 10; ++y)
    for (int x = 1; x <= 10; ++x) {
      const size_t i = size_t(y) * 12 + size_t(x);
      truth.primary_t[i] = x >= 8 && y >= 8 ? 2.0f : 1.0f;
      truth.primary_n[i] = Vec3::UnitZ();
      method.primary_t[i] = truth.primary_t[i], method.primary_n[i] = Vec3::UnitZ();
    }
  for (size_t i : {size_t(1 * 12 + 5), size_t(5 * 12 + 5), size_t(6 * 12 + 7)})
    method.primary_t[i] = kInfinity;  // at the silhouette, interior, next to the contour
  const FrameComparison c = compare_frames(truth, method);
  CHECK(c.missing == 3);
  CHECK(c.missing_at_edges == 2);
  // Not at an edge: x, y in 3..8 (2 from the background), less 6..8 x 6..8 (near the patch).
  CHECK(c.edge_pixels == 100 - (36 - 9));
}

TEST_CASE("False shadows: lit truth pixels the method hits alike but leaves dark", "[compare]") {
  RenderResult truth = frame(5, 1), method = frame(5, 1);
  for (size_t i = 0; i < 5; ++i) {
    truth.primary_t[i] = method.primary_t[i] = 1;
    truth.primary_n[i] = method.primary_n[i] = Vec3::UnitZ();
  }
  // Truth radiance 1, 1, 0.05 (below a tenth of the brightest: not lit), 1, 1. The method: dark
  // on a lit pixel (0: a false shadow), dim but above a quarter (1), dark where the truth is dim
  // too (2), the same (3), dark but with its normal 45 degrees off (4: a normal error).
  const float t[5] = {1, 1, 0.05f, 1, 1}, m[5] = {0, 0.3f, 0, 1, 0};
  for (int x = 0; x < 5; ++x)
    truth.image.at(x, 0) = Vec3::Constant(t[x]), method.image.at(x, 0) = Vec3::Constant(m[x]);
  method.primary_n[4] = Vec3(1, 0, 1).normalized();
  const FrameComparison c = compare_frames(truth, method);
  CHECK(c.lit_pixels == 4);
  CHECK(c.false_shadow == 1);
  CHECK(c.normal_off == 1);
  CHECK(c.false_shadow_rate() == Approx(0.25));
}
