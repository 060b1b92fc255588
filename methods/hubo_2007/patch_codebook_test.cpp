#include "methods/hubo_2007/patch_codebook.hpp"

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>

#include "core/dataset.hpp"
#include "preprocess/point_attributes.hpp"
#include "render/accuracy.hpp"
#include "render/scene.hpp"
#include "tests/variant_hits.hpp"

namespace pcrt {
namespace {

// The cloud cut into patches: the points of each voxel of side `side`, as PackedSplats with their
// cloud index.
struct Patches {
  std::vector<PackedSplat> points;
  std::vector<PatchInput> patches;
};
Patches cut(const PointCloud& cloud, float side) {
  std::map<std::array<int, 3>, std::vector<uint32_t>> voxels;
  for (uint32_t i = 0; i < cloud.size(); ++i) {
    const Vec3 v = cloud.positions[i] / side;
    voxels[{int(std::floor(v.x())), int(std::floor(v.y())), int(std::floor(v.z()))}].push_back(i);
  }
  Patches out;
  for (const auto& [key, ids] : voxels) {
    PatchInput p{uint32_t(out.points.size()), 0, Vec3::Zero(), Vec3::Zero()};
    for (uint32_t i : ids) {
      out.points.push_back({cloud.positions[i], 0.0f, cloud.normals[i], i});
      p.centre += cloud.positions[i], p.normal += cloud.normals[i];
    }
    p.end = uint32_t(out.points.size());
    p.centre /= float(ids.size());
    p.normal.normalize();
    out.patches.push_back(p);
  }
  return out;
}

}  // namespace

TEST_CASE("patch codebook: a patch that is its own representative decodes to its points",
          "[patch_codebook]") {
  const PointCloud cloud = load_dataset("torus:n=4000,seed=2").cloud;
  const Patches in = cut(cloud, 0.1f);
  PatchCodebook book;
  OpCounters c;
  book.build(in.points, in.patches, in.patches.size(), 4, c);
  const double h = mean_spacing(cloud.positions, c);
  std::vector<PackedSplat> out;
  size_t own = 0;
  for (uint32_t k = 0; k < in.patches.size(); ++k) {
    out.clear();
    book.decode(k, in.patches[k].centre, out, c);
    const PatchInput& p = in.patches[k];
    if (out.size() != p.end - p.begin) continue;  // another patch's representative
    float worst = 0;
    for (size_t i = 0; i < out.size(); ++i)
      worst = std::max(worst, (out[i].c - in.points[p.begin + i].c).norm());
    own += worst < 1e-3 * h;
  }
  // With as many clusters as patches, most patches are their own representative.
  CHECK(own > in.patches.size() / 2);
  CHECK(c.get(kCodebookPointsDecoded) > 0);
}

TEST_CASE("patch codebook: instances of few representatives stay on the surface",
          "[patch_codebook]") {
  const PointCloud cloud = load_dataset("sphere:n=20000,seed=2").cloud;
  const Patches in = cut(cloud, 0.05f);  // about 4 spacings
  PatchCodebook book;
  OpCounters c;
  book.build(in.points, in.patches, 16, 8, c);
  CHECK(book.representatives() <= 16);
  const double h = mean_spacing(cloud.positions, c);
  std::vector<PackedSplat> out;
  double worst = 0;
  for (uint32_t k = 0; k < in.patches.size(); ++k) book.decode(k, in.patches[k].centre, out, c);
  for (const PackedSplat& p : out) worst = std::max(worst, std::abs(double(p.c.norm()) - 1.0));
  // The unit sphere: decoded points within a fraction of the spacing from it.
  CHECK(worst < 0.5 * h);
}

TEST_CASE("hubo_2007 compressed finds the uncompressed method's hits", "[patch_codebook]") {
  const auto v = test::compare_variant_hits("sphere:n=20000,seed=3", "hubo_2007",
                                            {{"compressed", 1}}, 0.25, 3000);
  INFO("apart " << v.far << " of " << v.both);
  CHECK(v.both > 1000);
  CHECK(v.one <= 3000 / 200);
  CHECK(v.far <= v.both / 100);
}

}  // namespace pcrt
