// Linear RGB images and PNG output through libpng.
#pragma once

#include <string>
#include <vector>

#include "core/file_output.hpp"
#include "core/geometry.hpp"

namespace pcrt {

class Image {
 public:
  Image(int width, int height)
      : width_(width), height_(height), pixels_(size_t(width) * height, Vec3::Zero()) {}
  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }
  Vec3& at(int x, int y) { return pixels_[size_t(y) * width_ + x]; }
  [[nodiscard]] const Vec3& at(int x, int y) const { return pixels_[size_t(y) * width_ + x]; }
  [[nodiscard]] const std::vector<Vec3>& pixels() const { return pixels_; }

 private:
  int width_, height_;
  std::vector<Vec3> pixels_;
};

enum class PngEncoding { kSrgb, kLinear };

// 8-bit RGB PNG; kSrgb applies the sRGB transfer curve to linear radiance, kLinear stores
// values in [0,1] as they are (for normal and depth images). Written atomically.
void write_png(const std::string& path, const Image& image,
               PngEncoding encoding = PngEncoding::kSrgb);
// The same PNG as a writer for OutputFiles::stage (binary); `image` must outlive the call.
StreamWriter png_writer(const Image& image, PngEncoding encoding = PngEncoding::kSrgb);

}  // namespace pcrt
