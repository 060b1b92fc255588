#include "core/exr_output.hpp"

#include <tinyexr.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <ostream>

#include "core/error.hpp"

namespace pcrt {

bool is_exr_path(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
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
    planes[size_t(i)] = reinterpret_cast<unsigned char*>(
        const_cast<float*>(sorted[size_t(i)]->values.data()));
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

std::vector<FloatChannel> rgb_channels(const Image& image) {
  std::vector<FloatChannel> rgb = {{"R", {}}, {"G", {}}, {"B", {}}};
  for (const Vec3& p : image.pixels())
    for (int k = 0; k < 3; ++k) rgb[size_t(k)].values.push_back(p[k]);
  return rgb;
}

}  // namespace pcrt
