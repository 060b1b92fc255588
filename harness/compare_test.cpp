// The frame comparison on hand-made frames, and end to end: a mesh against itself agrees.
#include "harness/compare.hpp"

#include <catch2/catch.hpp>

using namespace pcrt;

namespace {

RenderResult frame(int w, int h) {
  RenderResult r{Image(w, h), Image(w, h), Image(w, h), {}, 0, {}, {}};
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
