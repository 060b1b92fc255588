// Rays given by a user: a CSV with the header ox,oy,oz,dx,dy,dz, one ray per line.
#pragma once

#include <string>
#include <vector>

#include "core/geometry.hpp"

namespace pcrt {

// Directions are normalised. Throws InputError naming the file and line for a wrong header, a
// malformed or non-finite value, a zero direction or an origin beyond kMaxCoordinate.
std::vector<Ray> read_rays_csv(const std::string& path);
// The same on text in memory; `name` stands for the file in errors (the fuzz targets).
std::vector<Ray> parse_rays_csv(const std::string& text, const std::string& name);

}  // namespace pcrt
