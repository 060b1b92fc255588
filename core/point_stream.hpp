// Points delivered in chunks, in the same order on every read: what a streaming build takes in
// place of a whole cloud, so that no process holds the float positions and normals of all of them
// (24 bytes a point: 22 GiB at 10^9). A generator re-draws its points on every read; a file is
// read again.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "core/aabb.hpp"
#include "core/geometry.hpp"

namespace pcrt {

struct PointChunk {
  std::span<const Vec3> positions;
  std::span<const Vec3> normals;  // unit length, one per position
  uint64_t first = 0;             // the stream index of positions[0]
};

class PointStream {
 public:
  virtual ~PointStream() = default;
  // The generator spec or file it reads: what its errors name.
  [[nodiscard]] virtual const std::string& name() const = 0;
  // How many points every read delivers, known before reading (a generator's n).
  [[nodiscard]] virtual size_t size() const = 0;
  // What every position is relative to (a georeferenced file's local origin), else zero.
  [[nodiscard]] virtual Vec3d origin() const { return Vec3d::Zero(); }
  // Calls `chunk` on consecutive chunks of at most kChunkPoints points until all size() points
  // are delivered, in the same order and with the same values on every call.
  virtual void read(const std::function<void(const PointChunk&)>& chunk) const = 0;
  // The box of every point, from one read on the first call, which checks every point (finite,
  // within kMaxCoordinate, a finite normal) and the count: InputError naming the stream.
  [[nodiscard]] const Aabb& bounds() const;

  static constexpr size_t kChunkPoints = size_t(1) << 16;

 private:
  mutable std::optional<Aabb> bounds_;
};

// The stream of a surface generator spec (`sphere:n=...`, core/dataset.hpp), in the generator's
// own order: the same points as load_dataset_in_input_order(spec), never all in memory; or of a
// PLY file with normals (open_ply_stream) or an XYZ/PWN file with normals (open_xyz_stream).
// Throws InputError naming the spec for other files (OFF), volume generators (no normals) and
// unknown generators.
std::unique_ptr<PointStream> open_point_stream(const std::string& spec);

// A PLY file's vertices in file order (binary records, or ascii lines read in blocks), relative to
// the local origin read_ply would choose (the same positions and unit normals as read_ply, which
// also drops exact duplicates: a stream keeps them; elements after the vertices are not read).
// InputError naming the file for a vertex element that is not first or holds a list, no normals,
// Gaussian particles, a truncated file, a bad line, coordinate or normal.
std::unique_ptr<PointStream> open_ply_stream(const std::string& path);

// An XYZ or PWN file's points in file order, six columns each (x y z nx ny nz), relative to the
// local origin parse_xyz would choose: the same positions and unit normals as read_xyz (which
// also drops exact duplicates: a stream keeps them), read line by line in blocks, never whole.
// InputError naming the file (and line) for three columns (no normals), other column counts, a
// bad number, coordinate or normal, every normal zero, no points, or a file changed between reads.
std::unique_ptr<PointStream> open_xyz_stream(const std::string& path);

}  // namespace pcrt
