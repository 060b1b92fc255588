// Reading and writing point clouds: PLY (ascii, binary little/big endian), XYZ and CGAL's PWN
// (3 or 6 columns), OFF (vertices as points). Every reader either returns a valid cloud or throws
// InputError naming the file and the line or element that is wrong.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/point_cloud.hpp"

namespace pcrt {

// A path's extension in lower case, with its dot (".ply"), or empty: what picks a reader.
std::string lowercase_extension(const std::string& path);

// Chooses the reader by extension (.ply, .xyz, .pwn, .off; case-insensitive), validates the
// result and drops exact duplicate points with a note on stderr.
PointCloud read_point_cloud(const std::string& path);

PointCloud read_ply(const std::string& path);
// The same, also collecting the 'face' element's polygons (vertex_indices), fanned into
// triangles; indices are checked against the vertex count.
PointCloud read_ply(const std::string& path, std::vector<std::array<uint32_t, 3>>* triangles);
PointCloud read_xyz(const std::string& path);
PointCloud read_off(const std::string& path);
PointCloud read_off(const std::string& path, std::vector<std::array<uint32_t, 3>>* triangles);
// The readers on text in memory; `name` stands for the file in errors (the fuzz targets).
PointCloud parse_ply(const std::string& text, const std::string& name,
                     std::vector<std::array<uint32_t, 3>>* triangles);
PointCloud parse_xyz(const std::string& text, const std::string& name);
PointCloud parse_off(const std::string& text, const std::string& name,
                     std::vector<std::array<uint32_t, 3>>* triangles);

enum class PlyFormat { kAscii, kBinaryLittleEndian, kBinaryBigEndian };
// Writes x y z as float (double for a georeferenced cloud) plus whichever of nx ny nz, red green
// blue, radius the cloud has; a cloud of Gaussian particles in 3D Gaussian Splatting's layout
// (f_dc_0..2 in place of red green blue, opacity, scale_0..2, rot_0..3), as its trainers write.
void write_ply(const std::string& path, const PointCloud& cloud,
               PlyFormat format = PlyFormat::kBinaryLittleEndian);

// What read_file takes at most from a stream that has no size (a pipe, a character device such
// as /dev/zero): larger than any text input pcrt is given through one, small enough to hold.
inline constexpr size_t kMaxStreamBytes = size_t(1) << 28;

// What read_file does when a regular file grows while it is read: an input must not (an error),
// a log another process appends to may (the bytes it had when reading began are returned).
enum class FileGrowth { kError, kSnapshot };

// Whole file as a string; InputError naming the path if it cannot be read, is a directory, is
// a stream longer than `max_stream_bytes`, or (kError) grew while it was read.
std::string read_file(const std::string& path, size_t max_stream_bytes = kMaxStreamBytes,
                      FileGrowth growth = FileGrowth::kError);

// Shared by the readers: unit-length normals, or none if every normal is zero (as some CGAL
// files store), or an InputError naming the first zero normal among non-zero ones.
void normalize_loaded_normals(PointCloud& cloud);

// A file's normal scaled to unit length, the rule every reader and stream applies to one; false
// where it is not finite or shorter than 1e-12 (and then unchanged).
inline bool to_unit_normal(Vec3& n) {
  if (!n.allFinite()) return false;
  const float len = n.norm();
  if (std::isfinite(len) && len > 1e-12f) {
    n /= len;
    return true;
  }
  // A component beyond about 1e19 squares to infinity in float: that direction, in double.
  const Vec3d d = n.cast<double>();
  const double dlen = d.norm();
  if (!(dlen > 1e-12)) return false;
  n = (d / dlen).cast<float>();
  return true;
}

}  // namespace pcrt
