// A point cloud stored structure-of-arrays: hot loops read `positions` alone; the optional
// attributes are empty vectors when absent.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/aabb.hpp"
#include "core/geometry.hpp"

namespace pcrt {

// The largest coordinate magnitude pcrt accepts for a point, a mesh vertex or a ray origin. Areas,
// squared distances and volumes of such coordinates stay finite in float (1e36 < 3.4e38), and
// every ray pcrt makes around such a cloud (cameras a few bounding radii out) stays far inside
// Embree's limit (|origin| <= 1.8e18, beyond which it aborts). Beyond it a bounding box's extent
// or area overflows to infinity and NaN reaches index arithmetic.
inline constexpr float kMaxCoordinate = 1e12f;

inline bool within_coordinate_range(const Vec3& p) {
  return p.allFinite() && p.cwiseAbs().maxCoeff() <= kMaxCoordinate;
}

struct Rgb8 {
  uint8_t r = 0, g = 0, b = 0;
};

struct PointCloud {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  // unit length, or empty
  std::vector<float> radii;   // splat radius per point, or empty
  std::vector<Rgb8> colours;  // or empty
  std::string name;           // file path or dataset spec it came from

  [[nodiscard]] size_t size() const { return positions.size(); }
  [[nodiscard]] bool has_normals() const { return !normals.empty(); }
  [[nodiscard]] bool has_radii() const { return !radii.empty(); }
  [[nodiscard]] bool has_colours() const { return !colours.empty(); }
  [[nodiscard]] Aabb bounds() const;
  [[nodiscard]] std::vector<std::string> attributes() const;

  // Throws InputError naming `name` if the cloud is empty, an attribute array has the wrong
  // length, or any value is NaN/inf, a coordinate lies beyond kMaxCoordinate or a normal is not
  // unit length.
  void validate() const;
  // Drops exact duplicate positions (keeping the first), returns how many were dropped.
  size_t remove_duplicates();
  // Keeps the points at `indices`, in that order (used for subsampling).
  [[nodiscard]] PointCloud subset(const std::vector<uint32_t>& indices) const;
};

}  // namespace pcrt
