// Rays given by a user: a CSV with the header ox,oy,oz,dx,dy,dz, one ray per line.
#pragma once

#include <string>
#include <vector>

#include "core/geometry.hpp"

namespace pcrt {

// A ray a user gave (a CSV line, a row of a numpy array): why pcrt cannot take it (a non-finite
// value, an origin beyond kMaxCoordinate, a zero direction), or nullptr. The caller names the
// place; nothing is formatted per ray.
const char* user_ray_problem(const Vec3& o, const Vec3& d);
// The ray from o along d normalised; (o, d) must have no user_ray_problem.
Ray user_ray(const Vec3& o, const Vec3& d);

// Directions are normalised; origins are in the file's coordinates and come back relative to
// `origin` (the cloud's local origin, core/point_cloud.hpp). Throws InputError naming the file and
// line for a wrong header, a malformed or non-finite value, a zero direction or an origin beyond
// kMaxCoordinate.
std::vector<Ray> read_rays_csv(const std::string& path, const Vec3d& origin = Vec3d::Zero());
// The same on text in memory; `name` stands for the file in errors (the fuzz targets).
std::vector<Ray> parse_rays_csv(const std::string& text, const std::string& name,
                                const Vec3d& origin = Vec3d::Zero());

}  // namespace pcrt
