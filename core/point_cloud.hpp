// A point cloud stored structure-of-arrays: hot loops read `positions` alone; the optional
// attributes are empty vectors when absent.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/aabb.hpp"
#include "core/gaussians.hpp"
#include "core/geometry.hpp"

namespace pcrt {

// The largest coordinate magnitude pcrt accepts for a point, a mesh vertex or a ray origin, in the
// file's coordinates (local positions, kLocalOriginReach below, then lie within twice it). Areas,
// squared distances and volumes of such coordinates stay finite in float (1e36 < 3.4e38), and
// every ray pcrt makes around such a cloud (cameras a few bounding radii out) stays far inside
// Embree's limit (|origin| <= 1.8e18, beyond which it aborts). Beyond it a bounding box's extent
// or area overflows to infinity and NaN reaches index arithmetic.
inline constexpr float kMaxCoordinate = 1e12f;

// The smallest extent (bounding-box diagonal) of a cloud of distinct points or a mesh pcrt takes.
// Every method finds the same hits at every scale from a cloud spanning about 3 10^-12 up to
// kMaxCoordinate, and renders the same frame from about 2 10^-9 (render/scale_test.cpp); much
// below, squared distances between neighbours near float's smallest normal numbers.
inline constexpr float kMinExtent = 1e-9f;

// InputError naming `name` for a box of positive diagonal below kMinExtent (`what`: a cloud's
// or a mesh's).
void require_extent(const Aabb& box, const std::string& name, const char* what = "cloud");

inline bool within_coordinate_range(const Vec3& p) {
  return p.allFinite() && p.cwiseAbs().maxCoeff() <= kMaxCoordinate;
}
inline bool within_coordinate_range(const Vec3d& p) {
  return p.allFinite() && p.cwiseAbs().maxCoeff() <= double(kMaxCoordinate);
}

// Georeferenced scans arrive at coordinates near 10^5-10^7, where a float's spacing is centimetres
// to metres. pcrt keeps positions in float relative to a local origin, chosen at load in double
// and recorded: a file whose first point lies farther than kLocalOriginReach from zero in some
// coordinate is read relative to that point rounded to integers, so its float positions are
// within its own extent of zero wherever it sits. Closer files keep their coordinates as written
// (below 1024 a float's spacing is at most 1.2e-4), and so do generated clouds.
inline constexpr double kLocalOriginReach = 1024;

// The origin a file is read relative to, given its first point (in the file's coordinates).
inline Vec3d local_origin_for(const Vec3d& first) {
  if (first.cwiseAbs().maxCoeff() <= kLocalOriginReach) return Vec3d::Zero();
  return first.array().round().matrix();
}
inline Vec3 to_local(const Vec3d& world, const Vec3d& origin) {
  return (world - origin).cast<float>();
}
inline Vec3d to_world(const Vec3& local, const Vec3d& origin) {
  return local.cast<double>() + origin;
}

// What a reader keeps while it turns a file's coordinates into local ones: the origin, chosen at
// the first point.
struct LocalFrame {
  Vec3d origin = Vec3d::Zero();
  bool chosen = false;

  void choose(const Vec3d& first) {
    // A first point beyond the range is refused by the caller; zero keeps its error as it was.
    origin = within_coordinate_range(first) ? local_origin_for(first) : Vec3d::Zero();
    chosen = true;
  }
  Vec3 place(const Vec3d& world) {
    if (!chosen) choose(world);
    return to_local(world, origin);
  }
};

struct Rgb8 {
  uint8_t r = 0, g = 0, b = 0;
};

struct PointCloud {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;    // unit length, or empty
  std::vector<float> radii;     // splat radius per point, or empty
  std::vector<Rgb8> colours;    // or empty
  GaussianParticles gaussians;  // one particle per point, or empty (core/gaussians.hpp)
  std::string name;             // file path or dataset spec it came from
  // Where the positions' zero lies in the file's coordinates (see kLocalOriginReach); every
  // position pcrt writes out is positions[i] + origin, in double.
  Vec3d origin = Vec3d::Zero();

  [[nodiscard]] size_t size() const { return positions.size(); }
  [[nodiscard]] bool has_normals() const { return !normals.empty(); }
  [[nodiscard]] bool has_radii() const { return !radii.empty(); }
  [[nodiscard]] bool has_colours() const { return !colours.empty(); }
  [[nodiscard]] bool has_gaussians() const { return !gaussians.empty(); }
  [[nodiscard]] Aabb bounds() const;
  [[nodiscard]] std::vector<std::string> attributes() const;

  // Throws InputError naming `name` if the cloud is empty, an attribute array has the wrong
  // length, or any value is NaN/inf, a coordinate (positions + origin) lies beyond kMaxCoordinate
  // or a normal is not unit length, or a Gaussian particle has a scale that is not positive and
  // finite, an opacity outside [0, 1] or a rotation that is not a unit quaternion, or distinct
  // points span less than kMinExtent.
  void validate() const;
  void validate_gaussians() const;
  // Drops exact duplicate positions (keeping the first), returns how many were dropped.
  size_t remove_duplicates();
  // Keeps the points at `indices`, in that order (used for subsampling).
  [[nodiscard]] PointCloud subset(const std::vector<uint32_t>& indices) const;
};

}  // namespace pcrt
