// Float images as OpenEXR (tinyexr; 32-bit float channels, ZIP compressed): what an 8-bit PNG
// loses, radiance above 1, depth in scene units, signed normals. Read back for image metrics
// (scripts comparing frames with a converged reference read them through the Python module).
#pragma once

#include <string>
#include <vector>

#include "core/file_output.hpp"
#include "core/image.hpp"

namespace pcrt {

// One channel of width x height values, row-major from the top row.
struct FloatChannel {
  std::string name;  // "R", "G", "B", "Z", ...
  std::vector<float> values;
};

// Whether `path` names an EXR file (".exr", any case): render writes EXR there, PNG elsewhere.
bool is_exr_path(const std::string& path);

// The file's bytes; InputError if tinyexr refuses (a channel of the wrong size, a name too long).
std::string encode_exr(int width, int height, const std::vector<FloatChannel>& channels);
// The same as a writer for OutputFiles::stage (binary).
StreamWriter exr_writer(int width, int height, std::vector<FloatChannel> channels);

// A decoded EXR: its size and every channel as 32-bit floats (half channels widened).
struct ExrImage {
  int width = 0, height = 0;
  std::vector<FloatChannel> channels;
};

// The image in `bytes` (scanline or tiled, any compression tinyexr reads); InputError naming
// `source` for anything tinyexr refuses, a multi-part or deep file, or an empty image.
ExrImage decode_exr(const std::string& bytes, const std::string& source);
// The file at `path`; InputError naming it if it cannot be read or decoded.
ExrImage read_exr(const std::string& path);

// An image's R, G, B channels as they are (linear radiance, not clamped).
std::vector<FloatChannel> rgb_channels(const Image& image);

}  // namespace pcrt
