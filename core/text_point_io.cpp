// XYZ/PWN and OFF readers, file loading and the extension dispatch.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "core/memory_budget.hpp"
#include "core/point_cloud_io.hpp"
#include "core/point_stream.hpp"
#include "core/text_scanner.hpp"

namespace pcrt {

std::string read_file(const std::string& path, size_t max_stream_bytes, FileGrowth growth) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) input_error("{}: is a directory, not a file", path);
  const bool regular = std::filesystem::is_regular_file(path, ec);
  const auto file_size = regular ? std::filesystem::file_size(path, ec) : 0;
  // A regular file is read to its size; a stream without one (a pipe, /dev/zero) up to the cap.
  const size_t limit = regular && !ec && file_size > 0 ? size_t(file_size) : max_stream_bytes;
  // The text and what is parsed from it are held together (an XYZ file's cloud is a third of its
  // text, a binary PLY's about its size): refused before the first byte, not killed halfway.
  if (regular && !ec)
    require_memory(2 * size_t(file_size),
                   fmt::format("{} ({} bytes, read whole)", path, file_size));
  std::ifstream in(path, std::ios::binary);
  if (!in) input_error("{}: cannot open: {}", path, std::strerror(errno));
  std::string text;
  std::vector<char> chunk(1 << 16);
  while (in && text.size() <= limit) {
    in.read(chunk.data(), std::streamsize(std::min(chunk.size(), limit + 1 - text.size())));
    text.append(chunk.data(), size_t(in.gcount()));
  }
  if (in.bad()) input_error("{}: read error", path);
  if (text.size() > limit) {
    if (regular && growth == FileGrowth::kSnapshot) {
      text.resize(limit);
      return text;
    }
    if (regular) input_error("{}: the file grew while it was read", path);
    input_error("{}: more than {} bytes from a stream without a size; pcrt reads at most that",
                path, max_stream_bytes);
  }
  return text;
}

void normalize_loaded_normals(PointCloud& cloud) {
  if (!cloud.has_normals()) return;
  const bool all_zero = std::all_of(cloud.normals.begin(), cloud.normals.end(),
                                    [](const Vec3& n) { return n.squaredNorm() == 0.0f; });
  if (all_zero) {
    note("pcrt: {}: every normal is zero; treating the cloud as having no normals", cloud.name);
    cloud.normals.clear();
    return;
  }
  for (size_t i = 0; i < cloud.normals.size(); ++i) {
    Vec3& n = cloud.normals[i];
    if (!n.allFinite()) input_error("{}: point {} has a non-finite normal", cloud.name, i);
    if (!to_unit_normal(n))
      input_error("{}: point {} has a zero normal while others do not", cloud.name, i);
  }
}

namespace {

// Columns 0-2 of the line in the file's coordinates; the frame's origin is chosen at the first
// line. Files near zero are parsed straight to float, as they always were; a georeferenced one
// in double.
Vec3d scan_world(const TextScanner& scan, LocalFrame& frame) {
  auto in_double = [&] {
    return Vec3d(scan.number<double>(0), scan.number<double>(1), scan.number<double>(2));
  };
  if (!frame.chosen) frame.choose(in_double());
  if (frame.origin.isZero())
    return Vec3(scan.number<float>(0), scan.number<float>(1), scan.number<float>(2)).cast<double>();
  return in_double();
}

}  // namespace

PointCloud read_xyz(const std::string& path) { return parse_xyz(read_file(path), path); }

PointCloud parse_xyz(const std::string& text, const std::string& path) {
  TextScanner scan(text, path);
  PointCloud cloud;
  cloud.name = path;
  LocalFrame frame;
  size_t columns = 0;
  while (scan.next_line()) {
    const auto& tok = scan.tokens();
    if (columns == 0) {
      columns = tok.size();
      if (columns != 3 && columns != 6)
        input_error("{}: line {}: {} columns; XYZ needs 3 (x y z) or 6 (x y z nx ny nz)", path,
                    scan.line(), columns);
    } else if (tok.size() != columns) {
      input_error("{}: line {}: {} columns where earlier lines have {}", path, scan.line(),
                  tok.size(), columns);
    }
    const Vec3d p = scan_world(scan, frame);
    if (!p.allFinite()) input_error("{}: line {}: non-finite coordinate", path, scan.line());
    if (!within_coordinate_range(p))
      input_error("{}: line {}: a coordinate beyond +-{:g}", path, scan.line(), kMaxCoordinate);
    cloud.positions.push_back(frame.place(p));
    if (columns == 6)
      cloud.normals.emplace_back(scan.number<float>(3), scan.number<float>(4),
                                 scan.number<float>(5));
  }
  cloud.origin = frame.origin;
  if (cloud.positions.empty()) input_error("{}: no points", path);
  normalize_loaded_normals(cloud);
  return cloud;
}

void for_each_line_block(const std::string& path, uint64_t offset, size_t first_line,
                         const std::function<bool(std::string_view, size_t)>& block) {
  constexpr size_t kBlockBytes = size_t(1) << 22;
  std::ifstream in(path, std::ios::binary);
  if (!in || !in.seekg(std::streamoff(offset)))
    input_error("{}: cannot open: {}", path, std::strerror(errno));
  std::string buffer;
  std::vector<char> chunk(kBlockBytes);
  size_t lines = first_line;
  while (true) {
    in.read(chunk.data(), std::streamsize(chunk.size()));
    buffer.append(chunk.data(), size_t(in.gcount()));
    if (in.bad()) input_error("{}: read error", path);
    const bool end = !in;
    const size_t cut = end ? buffer.size() : buffer.rfind('\n') + 1;  // npos + 1 = 0: no end yet
    if (cut == 0 && !end) {
      if (buffer.size() > kBlockBytes)
        input_error("{}: line {}: longer than 4 MiB", path, lines + 1);
      continue;
    }
    const std::string_view text(buffer.data(), cut);
    if (!block(text, lines)) return;
    lines += size_t(std::count(text.begin(), text.end(), '\n'));
    buffer.erase(0, cut);
    if (end) return;
  }
}

namespace {

// An XYZ or PWN file with normals (six columns), line by line (core/point_stream.hpp): the
// positions, origin and unit normals parse_xyz gives, never the whole file. The constructor reads
// the file once for the count and the columns; every read() parses it again.
class XyzStream final : public PointStream {
 public:
  explicit XyzStream(std::string path) : path_(std::move(path)) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path_, ec))
      input_error("{}: not a regular file (only files are streamed)", path_);
    bool any_normal = false;
    scan_lines([&](const TextScanner& scan) {
      if (count_ == 0) scan_world(scan, frame_);         // chooses the origin as parse_xyz does
      any_normal |= normal(scan).squaredNorm() != 0.0f;  // parses every normal
      ++count_;
    });
    if (count_ == 0) input_error("{}: no points", path_);
    if (!any_normal) input_error("{}: every normal is zero: has no normals to stream", path_);
  }

  [[nodiscard]] const std::string& name() const override { return path_; }
  [[nodiscard]] size_t size() const override { return count_; }
  [[nodiscard]] Vec3d origin() const override { return frame_.origin; }

  void read(const std::function<void(const PointChunk&)>& chunk) const override {
    std::vector<Vec3> positions, normals;
    positions.reserve(kChunkPoints);
    normals.reserve(kChunkPoints);
    size_t first = 0;
    auto flush = [&] {
      chunk(PointChunk{positions, normals, first});
      first += positions.size();
      positions.clear();
      normals.clear();
    };
    LocalFrame frame = frame_;
    scan_lines([&](const TextScanner& scan) {
      if (first + positions.size() == count_)
        input_error("{}: line {}: more points than when it was opened", path_, scan.line());
      const Vec3d p = scan_world(scan, frame);
      if (!within_coordinate_range(p))
        input_error("{}: line {}: a coordinate that is not finite or beyond +-{:g}", path_,
                    scan.line(), kMaxCoordinate);
      positions.push_back(frame.place(p));
      normals.push_back(unit_normal(scan));
      if (positions.size() == kChunkPoints) flush();
    });
    if (first + positions.size() != count_)
      input_error("{}: {} points where there were {} when it was opened", path_,
                  first + positions.size(), count_);
    if (!positions.empty()) flush();
  }

 private:
  // Every line with tokens, six columns each (parse_xyz's rule, with normals).
  template <class F>
  void scan_lines(F&& line) const {
    bool first = true;
    for_each_line_block(path_, 0, 0, [&](std::string_view text, size_t lines_before) {
      TextScanner scan(text, path_, lines_before);
      while (scan.next_line()) {
        const size_t columns = scan.tokens().size();
        if (first && columns == 3)
          input_error("{}: has no normals (x y z only): only clouds with normals stream", path_);
        if (first && columns != 6)
          input_error("{}: line {}: {} columns; XYZ needs 3 (x y z) or 6 (x y z nx ny nz)", path_,
                      scan.line(), columns);
        if (columns != 6)
          input_error("{}: line {}: {} columns where earlier lines have 6", path_, scan.line(),
                      columns);
        first = false;
        line(scan);
      }
      return true;
    });
  }
  static Vec3 normal(const TextScanner& scan) {
    return {scan.number<float>(3), scan.number<float>(4), scan.number<float>(5)};
  }
  [[nodiscard]] Vec3 unit_normal(const TextScanner& scan) const {
    Vec3 n = normal(scan);
    if (!to_unit_normal(n))
      input_error("{}: line {}: a zero or non-finite normal", path_, scan.line());
    return n;
  }

  std::string path_;
  size_t count_ = 0;
  LocalFrame frame_;
};

}  // namespace

std::unique_ptr<PointStream> open_xyz_stream(const std::string& path) {
  return std::make_unique<XyzStream>(path);
}

PointCloud read_off(const std::string& path) { return read_off(path, nullptr); }

PointCloud read_off(const std::string& path, std::vector<std::array<uint32_t, 3>>* triangles) {
  return parse_off(read_file(path), path, triangles);
}

namespace {

// What an OFF header says: the attribute prefixes of its keyword and the counts.
struct OffHeader {
  bool has_normals = false, has_colour = false;
  long long vertices = 0, faces = 0;
};

// The header keyword may carry C (colour) and N (normal) prefixes, and the counts may follow on
// the same line.
OffHeader parse_off_header(TextScanner& scan, const std::string& path) {
  if (!scan.next_line()) input_error("{}: empty file", path);
  const std::string_view kw = scan.tokens()[0];
  OffHeader h;
  h.has_normals = kw.find('N') != std::string_view::npos && kw.find('N') < kw.find("OFF");
  h.has_colour = kw.find('C') != std::string_view::npos && kw.find('C') < kw.find("OFF");
  if (kw.size() < 3 || kw.substr(kw.size() - 3) != "OFF" || kw.size() > 5)
    input_error("{}: line {}: not an OFF file (expected 'OFF')", path, scan.line());
  size_t first = 1;
  if (scan.tokens().size() == 1) {
    if (!scan.next_line()) input_error("{}: truncated: no vertex/face counts", path);
    first = 0;
  }
  if (scan.tokens().size() < first + 2)
    input_error("{}: line {}: expected 'vertices faces [edges]'", path, scan.line());
  h.vertices = scan.number<long long>(first);
  h.faces = scan.number<long long>(first + 1);
  if (h.vertices < 0 || h.faces < 0) input_error("{}: line {}: negative counts", path, scan.line());
  return h;
}

void read_off_vertices(TextScanner& scan, const OffHeader& h, const std::string& path,
                       PointCloud& cloud) {
  const size_t min_cols = 3 + (h.has_normals ? 3 : 0);
  cloud.positions.reserve(static_cast<size_t>(h.vertices));
  LocalFrame frame;
  for (long long i = 0; i < h.vertices; ++i) {
    if (!scan.next_line())
      input_error("{}: truncated: file ends at vertex {} of {}", path, i, h.vertices);
    const auto& tok = scan.tokens();
    if (tok.size() < min_cols || (!h.has_colour && tok.size() != min_cols))
      input_error("{}: line {}: vertex {} has {} values, expected {}", path, scan.line(), i,
                  tok.size(), min_cols);
    const Vec3d p = scan_world(scan, frame);
    if (!p.allFinite())
      input_error("{}: line {}: vertex {} has a non-finite coordinate", path, scan.line(), i);
    if (!within_coordinate_range(p))
      input_error("{}: line {}: vertex {} has a coordinate beyond +-{:g}", path, scan.line(), i,
                  kMaxCoordinate);
    cloud.positions.push_back(frame.place(p));
    if (h.has_normals)
      cloud.normals.emplace_back(scan.number<float>(3), scan.number<float>(4),
                                 scan.number<float>(5));
  }
  cloud.origin = frame.origin;
}

// Faces are checked (their vertices exist) and, when asked for, fanned into triangles.
void read_off_faces(TextScanner& scan, const OffHeader& h, const std::string& path,
                    std::vector<std::array<uint32_t, 3>>* triangles) {
  for (long long f = 0; f < h.faces; ++f) {
    if (!scan.next_line())
      input_error("{}: truncated: file ends at face {} of {}", path, f, h.faces);
    const auto n = scan.number<long long>(0);
    if (n < 1 || scan.tokens().size() < size_t(n) + 1)
      input_error("{}: line {}: face {} is malformed", path, scan.line(), f);
    for (long long k = 1; k <= n; ++k) {
      const auto v = scan.number<long long>(size_t(k));
      if (v < 0 || v >= h.vertices)
        input_error("{}: line {}: face {} names vertex {} of {}", path, scan.line(), f, v,
                    h.vertices);
    }
    if (!triangles) continue;
    if (n < 3) input_error("{}: line {}: face {} has {} vertices", path, scan.line(), f, n);
    for (long long k = 2; k < n; ++k)
      triangles->push_back({uint32_t(scan.number<long long>(1)),
                            uint32_t(scan.number<long long>(size_t(k))),
                            uint32_t(scan.number<long long>(size_t(k + 1)))});
  }
}

}  // namespace

PointCloud parse_off(const std::string& text, const std::string& path,
                     std::vector<std::array<uint32_t, 3>>* triangles) {
  TextScanner scan(text, path);
  const OffHeader h = parse_off_header(scan, path);
  const size_t lines_left = static_cast<size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
  if (static_cast<size_t>(h.vertices) > lines_left)
    input_error("{}: header promises {} vertices but the file has {} lines", path, h.vertices,
                lines_left);
  PointCloud cloud;
  cloud.name = path;
  read_off_vertices(scan, h, path, cloud);
  read_off_faces(scan, h, path, triangles);
  if (scan.next_line())
    input_error("{}: line {}: data after the last face; the header's counts are wrong", path,
                scan.line());
  if (cloud.positions.empty()) input_error("{}: no vertices", path);
  normalize_loaded_normals(cloud);
  return cloud;
}

std::string lowercase_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

PointCloud read_point_cloud(const std::string& path) {
  const std::string ext = lowercase_extension(path);
  PointCloud cloud;
  if (ext == ".ply")
    cloud = read_ply(path);
  else if (ext == ".xyz" || ext == ".pwn")
    cloud = read_xyz(path);
  else if (ext == ".off")
    cloud = read_off(path);
  else
    input_error("{}: unknown point cloud format '{}' (use .ply, .xyz, .pwn or .off)", path, ext);
  cloud.validate();
  if (const size_t dropped = cloud.remove_duplicates())
    note("pcrt: {}: dropped {} exact duplicate points ({} remain)", path, dropped, cloud.size());
  return cloud;
}

}  // namespace pcrt
