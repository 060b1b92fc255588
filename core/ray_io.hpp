// Rays given by a user: a CSV with the header ox,oy,oz,dx,dy,dz, one ray per line.
#pragma once

#include <string>
#include <vector>

#include "core/geometry.hpp"

namespace pcrt {

// A ray a user gave (a CSV line, a row of a numpy array): its direction normalised. Throws
// InputError "<where>: ..." for a non-finite value, an origin beyond kMaxCoordinate or a zero
// direction.
Ray make_user_ray(const Vec3& o, const Vec3& d, const std::string& where);

// Directions are normalised. Throws InputError naming the file and line for a wrong header, a
// malformed or non-finite value, a zero direction or an origin beyond kMaxCoordinate.
std::vector<Ray> read_rays_csv(const std::string& path);
// The same on text in memory; `name` stands for the file in errors (the fuzz targets).
std::vector<Ray> parse_rays_csv(const std::string& text, const std::string& name);

}  // namespace pcrt
