#include "core/point_cloud.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.hpp"

namespace pcrt {

Aabb PointCloud::bounds() const {
  Aabb b;
  for (const Vec3& p : positions) b.extend(p);
  return b;
}

void require_extent(const Aabb& box, const std::string& name, const char* what) {
  const float extent = box.empty() ? 0.0f : box.diagonal();
  if (extent > 0 && extent < kMinExtent)
    input_error("{}: the {} spans {:.3g} units across, less than the {:g} pcrt takes (scale it)",
                name, what, extent, kMinExtent);
}

std::vector<std::string> PointCloud::attributes() const {
  std::vector<std::string> a{"position"};
  if (has_normals()) a.emplace_back("normal");
  if (has_radii()) a.emplace_back("radius");
  if (has_colours()) a.emplace_back("colour");
  if (has_gaussians()) a.emplace_back("gaussian");
  return a;
}

void PointCloud::validate() const {
  const size_t n = size();
  if (n == 0) input_error("{}: the point cloud has no points", name);
  if (has_normals() && normals.size() != n)
    input_error("{}: {} normals for {} points", name, normals.size(), n);
  if (has_radii() && radii.size() != n)
    input_error("{}: {} radii for {} points", name, radii.size(), n);
  if (has_colours() && colours.size() != n)
    input_error("{}: {} colours for {} points", name, colours.size(), n);
  if (has_gaussians()) validate_gaussians();
  for (size_t i = 0; i < n; ++i) {
    if (!positions[i].allFinite()) input_error("{}: point {} has a non-finite coordinate", name, i);
    if (!within_coordinate_range(to_world(positions[i], origin)))
      input_error("{}: point {} has a coordinate beyond +-{:g}", name, i, kMaxCoordinate);
    if (has_normals()) {
      if (!normals[i].allFinite()) input_error("{}: point {} has a non-finite normal", name, i);
      if (std::abs(normals[i].squaredNorm() - 1.0f) > 1e-3f)
        input_error("{}: point {} has a normal of length {:.4g}, not 1", name, i,
                    normals[i].norm());
    }
    if (has_radii() && !(radii[i] >= 0.0f && radii[i] <= kMaxCoordinate))
      input_error("{}: point {} has radius {}, not a value in [0, {:g}]", name, i, radii[i],
                  kMaxCoordinate);
  }
  require_extent(bounds(), name);
}

void PointCloud::validate_gaussians() const {
  const GaussianParticles& g = gaussians;
  if (g.scales.size() != size() || g.rotations.size() != size() || g.opacities.size() != size())
    input_error("{}: {} Gaussian scales, {} rotations and {} opacities for {} points", name,
                g.scales.size(), g.rotations.size(), g.opacities.size(), size());
  for (size_t i = 0; i < size(); ++i) {
    const Vec3& s = g.scales[i];
    if (!(s.allFinite() && s.minCoeff() > 0.0f && s.maxCoeff() <= kMaxCoordinate))
      input_error("{}: point {} has Gaussian scales ({:g}, {:g}, {:g}), not in (0, {:g}]", name, i,
                  s.x(), s.y(), s.z(), kMaxCoordinate);
    if (!(g.opacities[i] >= 0.0f && g.opacities[i] <= 1.0f))
      input_error("{}: point {} has opacity {}, not a value in [0, 1]", name, i, g.opacities[i]);
    const Vec4& q = g.rotations[i];
    if (!q.allFinite() || std::abs(q.squaredNorm() - 1.0f) > 1e-3f)
      input_error("{}: point {} has a rotation of length {:.4g}, not a unit quaternion", name, i,
                  q.norm());
  }
}

size_t PointCloud::remove_duplicates() {
  std::vector<uint32_t> order(size());
  std::iota(order.begin(), order.end(), 0u);
  auto less = [&](uint32_t a, uint32_t b) {
    const Vec3& p = positions[a];
    const Vec3& q = positions[b];
    if (p.x() != q.x()) return p.x() < q.x();
    if (p.y() != q.y()) return p.y() < q.y();
    if (p.z() != q.z()) return p.z() < q.z();
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<char> keep(size(), 1);
  size_t dropped = 0;
  for (size_t i = 1; i < order.size(); ++i) {
    if (positions[order[i]] == positions[order[i - 1]]) {
      keep[order[i]] = 0;
      ++dropped;
    }
  }
  if (dropped == 0) return 0;
  std::vector<uint32_t> kept;
  kept.reserve(size() - dropped);
  for (uint32_t i = 0; i < size(); ++i)
    if (keep[i]) kept.push_back(i);
  *this = subset(kept);
  return dropped;
}

PointCloud PointCloud::subset(const std::vector<uint32_t>& indices) const {
  PointCloud out;
  out.name = name;
  out.origin = origin;
  auto pick = [&](const auto& src, auto& dst) {
    if (src.empty()) return;
    dst.reserve(indices.size());
    for (uint32_t i : indices) dst.push_back(src[i]);
  };
  pick(positions, out.positions);
  pick(normals, out.normals);
  pick(radii, out.radii);
  pick(colours, out.colours);
  pick(gaussians.scales, out.gaussians.scales);
  pick(gaussians.rotations, out.gaussians.rotations);
  pick(gaussians.opacities, out.gaussians.opacities);
  return out;
}

}  // namespace pcrt
