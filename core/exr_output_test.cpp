#include <tinyexr.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <map>

#include "core/error.hpp"
#include "core/exr_output.hpp"

using namespace pcrt;

namespace {

// The channels of an EXR file in memory, read back with tinyexr's own reader.
std::map<std::string, std::vector<float>> decode(const std::string& bytes, int& w, int& h) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  EXRVersion version;
  REQUIRE(ParseEXRVersionFromMemory(&version, data, bytes.size()) == TINYEXR_SUCCESS);
  EXRHeader header;
  InitEXRHeader(&header);
  const char* err = nullptr;
  REQUIRE(ParseEXRHeaderFromMemory(&header, &version, data, bytes.size(), &err) == TINYEXR_SUCCESS);
  EXRImage image;
  InitEXRImage(&image);
  REQUIRE(LoadEXRImageFromMemory(&image, &header, data, bytes.size(), &err) == TINYEXR_SUCCESS);
  w = image.width;
  h = image.height;
  std::map<std::string, std::vector<float>> out;
  for (int c = 0; c < header.num_channels; ++c) {
    REQUIRE(header.pixel_types[c] == TINYEXR_PIXELTYPE_FLOAT);
    const auto* p = reinterpret_cast<const float*>(image.images[c]);
    out[header.channels[c].name].assign(p, p + size_t(w) * size_t(h));
  }
  FreeEXRImage(&image);
  FreeEXRHeader(&header);
  return out;
}

}  // namespace

TEST_CASE("EXR output keeps 32-bit floats: radiance above 1, infinite depth, signed values") {
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> z = {0.5f, 123456.78f, inf, 1e-30f, 3.0f, -2.5f};
  Image rgb(3, 2);
  rgb.at(2, 1) = Vec3(7.25f, -0.125f, 1e6f);
  std::vector<FloatChannel> channels = rgb_channels(rgb);
  channels.push_back({"Z", z});
  int w = 0, h = 0;
  const auto back = decode(encode_exr(3, 2, channels), w, h);
  CHECK((w == 3 && h == 2));
  REQUIRE(back.size() == 4);
  CHECK(back.at("Z") == z);
  CHECK(back.at("R")[5] == 7.25f);
  CHECK(back.at("G")[5] == -0.125f);
  CHECK(back.at("B")[5] == 1e6f);
  CHECK(back.at("R")[0] == 0.0f);
}

TEST_CASE("EXR output: paths and malformed channels") {
  CHECK(is_exr_path("a/b.exr"));
  CHECK(is_exr_path("B.EXR"));
  CHECK_FALSE(is_exr_path("b.png"));
  CHECK_FALSE(is_exr_path("exr"));
  CHECK_THROWS_AS(encode_exr(2, 2, {{"Z", {1, 2, 3}}}), InputError);
}
