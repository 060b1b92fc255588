#include "core/ray_io.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "core/point_cloud.hpp"
#include "core/point_cloud_io.hpp"
#include "core/text_scanner.hpp"

namespace pcrt {

const char* user_ray_problem(const Vec3& o, const Vec3& d) {
  static const std::string beyond = fmt::format("origin coordinate beyond +-{:g}", kMaxCoordinate);
  if (!o.allFinite() || !d.allFinite()) return "non-finite value";
  // Embree aborts on origins beyond 1.8e18; every structure loses the ray's t long before.
  if (!within_coordinate_range(o)) return beyond.c_str();
  if (!(d.cast<double>().norm() > 0)) return "zero direction";
  return nullptr;
}

Ray user_ray(const Vec3& o, const Vec3& d) {
  Ray r;
  r.o = o;
  // In double: the float norm of a direction near 1e38 (or 1e-38) overflows (or underflows).
  r.d = d.cast<double>().normalized().cast<float>();
  return r;
}

std::vector<Ray> read_rays_csv(const std::string& path, const Vec3d& origin) {
  return parse_rays_csv(read_file(path), path, origin);
}

namespace {

// The origin columns in the file's coordinates: straight to float near zero, as always; in
// double for a georeferenced cloud's rays.
Vec3d scan_ray_origin(const TextScanner& lines, const Vec3d& origin) {
  if (origin.isZero())
    return Vec3(lines.number<float>(0), lines.number<float>(1), lines.number<float>(2))
        .cast<double>();
  return Vec3d(lines.number<double>(0), lines.number<double>(1), lines.number<double>(2));
}

}  // namespace

std::vector<Ray> parse_rays_csv(const std::string& text, const std::string& path,
                                const Vec3d& origin) {
  std::vector<Ray> rays;
  bool header = false;
  // CSV: split on commas by turning them into blanks for the scanner; the header is checked first.
  std::string blanked = text;
  std::replace(blanked.begin(), blanked.end(), ',', ' ');
  TextScanner lines(blanked, path);
  while (lines.next_line(false)) {
    const auto& tok = lines.tokens();
    if (!header) {
      const std::vector<std::string_view> want{"ox", "oy", "oz", "dx", "dy", "dz"};
      if (tok != want)
        input_error("{}: line {}: header must be 'ox,oy,oz,dx,dy,dz'", path, lines.line());
      header = true;
      continue;
    }
    if (tok.size() != 6)
      input_error("{}: line {}: {} values, expected 6", path, lines.line(), tok.size());
    const Vec3d o = scan_ray_origin(lines, origin);
    const Vec3 d(lines.number<float>(3), lines.number<float>(4), lines.number<float>(5));
    if (const char* why = user_ray_problem(o.cast<float>(), d))  // in the file's coordinates
      input_error("{}: line {}: {}", path, lines.line(), why);
    const Ray r = user_ray(to_local(o, origin), d);
    rays.push_back(r);
  }
  if (!header) input_error("{}: empty; expected the header 'ox,oy,oz,dx,dy,dz'", path);
  return rays;
}

}  // namespace pcrt
