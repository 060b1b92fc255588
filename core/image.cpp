#include "core/image.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/error.hpp"
#include "core/file_output.hpp"

namespace pcrt {
namespace {

uint8_t to_byte(float v, PngEncoding enc) {
  v = std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f);
  if (enc == PngEncoding::kSrgb)
    v = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
  return static_cast<uint8_t>(std::lround(v * 255.0f));
}

void png_write_to_stream(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::ostream*>(png_get_io_ptr(png));
  out->write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(length));
}
void png_flush_stream(png_structp png) { static_cast<std::ostream*>(png_get_io_ptr(png))->flush(); }

}  // namespace

StreamWriter png_writer(const Image& image, PngEncoding encoding) {
  return [&image, encoding](std::ostream& out) {
    const int w = image.width();
    const int h = image.height();
    std::vector<uint8_t> rgb(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c)
          rgb[(size_t(y) * w + x) * 3 + c] = to_byte(image.at(x, y)[c], encoding);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info) {
      png_destroy_write_struct(&png, &info);
      input_error("libpng could not start");
    }
    if (setjmp(png_jmpbuf(png))) {
      png_destroy_write_struct(&png, &info);
      input_error("libpng failed while encoding");
    }
    png_set_write_fn(png, &out, png_write_to_stream, png_flush_stream);
    png_set_IHDR(png, info, static_cast<png_uint_32>(w), static_cast<png_uint_32>(h), 8,
                 PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < h; ++y) png_write_row(png, rgb.data() + size_t(y) * w * 3);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
  };
}

void write_png(const std::string& path, const Image& image, PngEncoding encoding) {
  write_file_atomically(path, png_writer(image, encoding), /*binary=*/true);
}

}  // namespace pcrt
