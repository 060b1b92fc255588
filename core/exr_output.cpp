#include "core/exr_output.hpp"

#include <tinyexr.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <ostream>
#include <sstream>

#include "core/error.hpp"
#include "core/memory_budget.hpp"
#include "core/point_cloud_io.hpp"

namespace pcrt {

bool is_exr_path(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".exr";
}

std::string encode_exr(int width, int height, const std::vector<FloatChannel>& channels) {
  // EXR readers expect channels sorted by name (tinyexr's own writer stores B, G, R).
  std::vector<const FloatChannel*> sorted;
  for (const FloatChannel& c : channels) {
    if (c.values.size() != size_t(width) * size_t(height) || c.name.empty() || c.name.size() > 255)
      input_error("EXR channel '{}': {} values for {} x {} pixels", c.name, c.values.size(), width,
                  height);
    sorted.push_back(&c);
  }
  std::sort(sorted.begin(), sorted.end(), [](auto* a, auto* b) { return a->name < b->name; });
  const int n = int(sorted.size());
  std::vector<EXRChannelInfo> info(static_cast<size_t>(n));
  std::vector<int> types(static_cast<size_t>(n), TINYEXR_PIXELTYPE_FLOAT);
  std::vector<unsigned char*> planes(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    std::memset(&info[size_t(i)], 0, sizeof(EXRChannelInfo));
    std::strncpy(info[size_t(i)].name, sorted[size_t(i)]->name.c_str(), 255);
    // tinyexr reads the planes and never writes them.
    planes[size_t(i)] =
        reinterpret_cast<unsigned char*>(const_cast<float*>(sorted[size_t(i)]->values.data()));
  }
  EXRImage image;
  InitEXRImage(&image);
  image.num_channels = n;
  image.images = planes.data();
  image.width = width;
  image.height = height;
  EXRHeader header;
  InitEXRHeader(&header);
  header.num_channels = n;
  header.channels = info.data();
  header.pixel_types = types.data();
  header.requested_pixel_types = types.data();
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
  unsigned char* memory = nullptr;
  const char* err = nullptr;
  const size_t size = SaveEXRImageToMemory(&image, &header, &memory, &err);
  std::unique_ptr<unsigned char, decltype(&std::free)> owned(memory, &std::free);
  if (size == 0) {
    const std::string why = err ? err : "unknown error";
    FreeEXRErrorMessage(err);
    input_error("EXR encoding failed: {}", why);
  }
  return std::string(reinterpret_cast<const char*>(memory), size);
}

StreamWriter exr_writer(int width, int height, std::vector<FloatChannel> channels) {
  return [=, channels = std::move(channels)](std::ostream& out) {
    const std::string bytes = encode_exr(width, height, channels);
    out.write(bytes.data(), std::streamsize(bytes.size()));
  };
}

namespace {

// tinyexr's C structures, freed however decoding ends: a header that failed to parse may hold
// allocations already (FreeEXRHeader accepts it), an image that failed to load was freed by
// tinyexr itself.
struct ExrParts {
  EXRHeader header;
  EXRImage image;
  bool image_loaded = false;
  ExrParts() {
    InitEXRHeader(&header);
    InitEXRImage(&image);
  }
  ~ExrParts() {
    if (image_loaded) FreeEXRImage(&image);
    FreeEXRHeader(&header);
  }
  ExrParts(const ExrParts&) = delete;
  ExrParts& operator=(const ExrParts&) = delete;
};

[[noreturn]] void exr_refused(const std::string& source, const char* err) {
  const std::string why = err ? err : "not an EXR file";
  if (err) FreeEXRErrorMessage(err);
  input_error("{}: not a readable EXR image ({})", source, why);
}

// One channel's values, row-major from the top row: scanline images hold one plane per channel,
// tiled ones a plane per tile, of the header's tile size (a tile at the right or bottom edge is
// cut to the image, its width and height, but keeps that stride and place).
std::vector<float> channel_values(const EXRImage& image, const EXRHeader& header, int c) {
  std::vector<float> v(size_t(image.width) * size_t(image.height));
  if (!image.tiles) {
    const auto* p = reinterpret_cast<const float*>(image.images[c]);
    std::copy(p, p + v.size(), v.begin());
    return v;
  }
  const auto tile_w = size_t(header.tile_size_x), tile_h = size_t(header.tile_size_y);
  for (int t = 0; t < image.num_tiles; ++t) {
    const EXRTile& tile = image.tiles[t];
    const auto* p = reinterpret_cast<const float*>(tile.images[c]);
    for (int y = 0; y < tile.height; ++y)
      for (int x = 0; x < tile.width; ++x) {
        const size_t gx = size_t(tile.offset_x) * tile_w + size_t(x);
        const size_t gy = size_t(tile.offset_y) * tile_h + size_t(y);
        if (gx < size_t(image.width) && gy < size_t(image.height))
          v[gy * size_t(image.width) + gx] = p[size_t(y) * tile_w + size_t(x)];
      }
  }
  return v;
}

// A header's promises checked before tinyexr allocates for them: its chunk offset table (one 8-byte
// offset per chunk of the first level; a scanline chunk holds at most 256 rows) must lie within
// the file, and its pixels, as floats, once in tinyexr's planes and once in ours, must fit.
void check_exr_size(const EXRHeader& header, size_t file_bytes, const std::string& source) {
  const EXRBox2i& box = header.data_window;
  const int64_t w = int64_t(box.max_x) - box.min_x + 1, h = int64_t(box.max_y) - box.min_y + 1;
  if (w <= 0 || h <= 0 || header.num_channels <= 0)
    input_error("{}: an EXR image of {}x{} pixels and {} channels", source, w, h,
                header.num_channels);
  auto blocks = [](int64_t n, int64_t per) { return (n + per - 1) / per; };
  const bool tiled = header.tiled && header.tile_size_x > 0 && header.tile_size_y > 0;
  const double chunks =
      tiled ? double(blocks(w, header.tile_size_x)) * double(blocks(h, header.tile_size_y))
            : double(blocks(h, 256));
  if (chunks * 8 > double(file_bytes))
    input_error(
        "{}: truncated EXR file: its header promises {:.0f} chunks of {}x{} pixels, whose "
        "offsets alone take more than its {} bytes",
        source, chunks, w, h, file_bytes);
  const double pixel_bytes = double(w) * double(h) * double(header.num_channels) * sizeof(float);
  const double bytes = 2 * pixel_bytes + chunks * 64 + double(file_bytes);
  require_memory(bytes >= 1e19 ? size_t(-1) : size_t(bytes),
                 fmt::format("{} ({}x{} pixels, {} channels)", source, w, h, header.num_channels));
}

}  // namespace

ExrImage decode_exr(const std::string& bytes, const std::string& source) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  EXRVersion version;
  if (ParseEXRVersionFromMemory(&version, data, bytes.size()) != TINYEXR_SUCCESS)
    exr_refused(source, nullptr);
  if (version.multipart || version.non_image)
    input_error("{}: a multi-part or deep EXR file (one flat image is read)", source);
  ExrParts parts;
  const char* err = nullptr;
  if (ParseEXRHeaderFromMemory(&parts.header, &version, data, bytes.size(), &err) !=
      TINYEXR_SUCCESS)
    exr_refused(source, err);
  check_exr_size(parts.header, bytes.size(), source);
  for (int c = 0; c < parts.header.num_channels; ++c)
    parts.header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
  if (LoadEXRImageFromMemory(&parts.image, &parts.header, data, bytes.size(), &err) !=
      TINYEXR_SUCCESS)
    exr_refused(source, err);
  parts.image_loaded = true;
  if (parts.image.width <= 0 || parts.image.height <= 0 || parts.header.num_channels <= 0)
    input_error("{}: an EXR image of {}x{} pixels and {} channels", source, parts.image.width,
                parts.image.height, parts.header.num_channels);
  ExrImage out{parts.image.width, parts.image.height, {}};
  for (int c = 0; c < parts.header.num_channels; ++c)
    out.channels.push_back(
        {parts.header.channels[c].name, channel_values(parts.image, parts.header, c)});
  return out;
}

// Read as the point readers read (core/point_cloud_io.hpp, read_file): a device or a FIFO is
// read up to their limit for a stream without a size, not until memory runs out.
ExrImage read_exr(const std::string& path) { return decode_exr(read_file(path), path); }

std::vector<FloatChannel> rgb_channels(const Image& image) {
  std::vector<FloatChannel> rgb = {{"R", {}}, {"G", {}}, {"B", {}}};
  for (const Vec3& p : image.pixels())
    for (int k = 0; k < 3; ++k) rgb[size_t(k)].values.push_back(p[k]);
  return rgb;
}

}  // namespace pcrt
