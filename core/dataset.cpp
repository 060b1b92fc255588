#include "core/dataset.hpp"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <functional>
#include <random>

#include "core/error.hpp"
#include "core/memory_budget.hpp"
#include "core/morton.hpp"
#include "core/point_cloud_io.hpp"
#include "core/rng.hpp"

namespace pcrt {
namespace {

constexpr double kMaxPoints = 2e8;  // 4.8 GB of positions and normals

std::vector<ParamSpec> common_params() {
  return {
      {"n", 10000, 1, kMaxPoints, "number of points", true},
      {"seed", 1, 0, 1e18, "random seed", true},
      {"noise", 0, 0, 1e30, "standard deviation of isotropic Gaussian noise added to positions"},
      {"density", 0, 0, 0.99,
       "non-uniformity: density falls linearly along x from 1 to 1-density (0 = uniform)"}};
}

std::vector<ParamSpec> with_common(std::vector<ParamSpec> shape) {
  auto p = common_params();
  p.insert(p.end(), shape.begin(), shape.end());
  return p;
}

std::shared_ptr<const Surface> make_surface(const std::string& name, const ParamValues& p,
                                            const std::string& spec) {
  auto f = [&](const char* k) { return static_cast<float>(p.at(k)); };
  if (name == "sphere" || name == "fibonacci_sphere") {
    auto s = std::make_shared<SphereSurface>();
    s->radius = f("radius");
    return s;
  }
  if (name == "plane") {
    auto s = std::make_shared<PlaneSurface>();
    s->size = f("size");
    return s;
  }
  if (name == "torus") {
    if (p.at("r") >= p.at("R"))
      input_error("dataset '{}': r ({}) must be smaller than R ({})", spec, p.at("r"), p.at("R"));
    auto s = std::make_shared<TorusSurface>();
    s->major = f("R");
    s->minor = f("r");
    return s;
  }
  auto s = std::make_shared<BumpySphereSurface>();
  s->radius = f("radius");
  s->amplitude = f("amplitude");
  s->frequency = f("frequency");
  return s;
}

// Fibonacci (golden-angle) spiral: deterministic, near-uniform.
Vec3 fibonacci_point(size_t i, size_t n) {
  const double golden = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
  const double z = 1.0 - (2.0 * double(i) + 1.0) / double(n);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = golden * double(i);
  return Vec3(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
}

// Draws n points (by `place`, or uniformly by area from the surface, thinned by `density` along
// x), each moved by isotropic Gaussian noise of standard deviation `noise`.
PointCloud sample_points(const Surface& surface, size_t n, uint64_t seed, double noise,
                         double density, const std::string& name,
                         const std::function<Vec3(size_t, Vec3&)>& place) {
  Rng rng(seed, 0x5eed);
  std::mt19937_64 gauss_engine(mix64(seed));
  std::normal_distribution<double> gauss(0.0, noise);
  const Aabb box = surface.bounds();
  const float span = std::max(box.extent().x(), 1e-30f);

  PointCloud cloud;
  cloud.name = name;
  cloud.positions.reserve(n);
  cloud.normals.reserve(n);
  size_t tries = 0;
  while (cloud.positions.size() < n) {
    Vec3 normal;
    Vec3 x;
    if (place) {
      x = place(tries++, normal);
    } else {
      x = surface.sample(rng, normal);
      if (density > 0) {
        const double w = 1.0 - density * (x.x() - box.lo.x()) / span;
        if (rng.uniform_double() >= w) continue;
      }
    }
    if (noise > 0)
      x += Vec3(float(gauss(gauss_engine)), float(gauss(gauss_engine)), float(gauss(gauss_engine)));
    cloud.positions.push_back(x);
    cloud.normals.push_back(normal);
  }
  return cloud;
}

}  // namespace

PointCloud sample_surface(const Surface& surface, size_t n, uint64_t seed, double noise,
                          double density, const std::string& name) {
  return sample_points(surface, n, seed, noise, density, name, nullptr);
}

namespace {

PointCloud generate(const std::string& name, const ParamValues& p, const Surface& surface,
                    const std::string& spec) {
  const auto n = static_cast<size_t>(p.at("n"));
  const auto seed = static_cast<uint64_t>(p.at("seed"));
  const double noise = p.at("noise");
  const double density = p.at("density");
  if (name != "fibonacci_sphere") return sample_surface(surface, n, seed, noise, density, spec);
  // Density thinning would break the spiral's determinism; it is rejected at parse time.
  const auto radius = static_cast<float>(p.at("radius"));
  return sample_points(surface, n, seed, noise, density, spec, [&](size_t i, Vec3& normal) {
    normal = fibonacci_point(i, n);
    return Vec3(radius * normal);
  });
}

bool is_volume_generator(const std::string& name) {
  return name == "ball" || name == "cube" || name == "skew_lines";
}

// Point sets without a surface (no normals, no truth), for the Delaunay experiments: uniform in a
// ball or a cube, or half the points on each of two skew lines (the Delaunay worst case: every
// segment of one line with every segment of the other is a tetrahedron, (N/2 - 1)^2 cells).
PointCloud generate_volume(const std::string& name, const ParamValues& p, const std::string& spec) {
  const auto n = static_cast<size_t>(p.at("n"));
  const auto seed = static_cast<uint64_t>(p.at("seed"));
  const double density = p.at("density");
  Rng rng(seed, 0xb0a1);
  std::mt19937_64 gauss_engine(mix64(seed));
  std::normal_distribution<double> gauss(0.0, p.at("noise"));
  PointCloud cloud;
  cloud.name = spec;
  cloud.positions.reserve(n);
  const float size = static_cast<float>(p.at("size"));
  while (cloud.positions.size() < n) {
    Vec3 x;
    if (name == "skew_lines") {
      const float t = size * (float(rng.uniform_double()) - 0.5f);
      x = cloud.positions.size() % 2 == 0 ? Vec3(t, 0, -0.5f * size) : Vec3(0, t, 0.5f * size);
    } else {
      x = size * Vec3(float(rng.uniform_double()) - 0.5f, float(rng.uniform_double()) - 0.5f,
                      float(rng.uniform_double()) - 0.5f);
      if (name == "ball" && x.squaredNorm() > 0.25f * size * size) continue;
      if (density > 0 && rng.uniform_double() >= 1.0 - density * (x.x() / size + 0.5)) continue;
    }
    if (p.at("noise") > 0)
      x += Vec3(float(gauss(gauss_engine)), float(gauss(gauss_engine)), float(gauss(gauss_engine)));
    cloud.positions.push_back(x);
  }
  return cloud;
}

}  // namespace

const std::vector<GeneratorInfo>& generators() {
  static const std::vector<GeneratorInfo> list = {
      {"sphere", "uniform random points on a sphere at the origin",
       with_common({{"radius", 1, 1e-30, 1e30, "sphere radius"}})},
      {"fibonacci_sphere",
       "Fibonacci-spiral points on a sphere at the origin (near-uniform, seed only affects noise)",
       with_common({{"radius", 1, 1e-30, 1e30, "sphere radius"}})},
      {"plane", "uniform random points on the square z=0, |x|,|y| <= size/2",
       with_common({{"size", 2, 1e-30, 1e30, "side of the square"}})},
      {"torus", "uniform (by area) random points on a torus around the z axis at the origin",
       with_common(
           {{"R", 1, 1e-30, 1e30, "major radius"}, {"r", 0.25, 1e-30, 1e30, "minor radius"}})},
      {"bumpy_sphere",
       "uniform (by area) points on a sphere displaced by a*sin(f x)sin(f y)sin(f z)",
       with_common({{"radius", 1, 1e-30, 1e30, "base radius"},
                    {"amplitude", 0.05, 0, 0.5, "relative displacement"},
                    {"frequency", 6, 0, 100, "angular frequency f"}})},
      {"ball", "uniform random points inside a ball at the origin (no surface: Delaunay tests)",
       with_common({{"size", 2, 1e-30, 1e30, "diameter"}})},
      {"cube", "uniform random points inside a cube at the origin (no surface: Delaunay tests)",
       with_common({{"size", 2, 1e-30, 1e30, "side"}})},
      {"skew_lines",
       "N/2 random points on each of two skew lines (x axis at z=-size/2, y axis at z=+size/2): "
       "the Delaunay worst case, (N/2-1)^2 cells",
       with_common({{"size", 2, 1e-30, 1e30, "length of each segment and distance between them"}})},
  };
  return list;
}

ParamValues parse_generator_spec(const std::string& spec, const GeneratorInfo** info_out) {
  const size_t colon = spec.find(':');
  const std::string name = spec.substr(0, colon);
  const GeneratorInfo* info = nullptr;
  for (const auto& g : generators())
    if (g.name == name) info = &g;
  if (!info) {
    std::string known;
    for (const auto& g : generators()) known += (known.empty() ? "" : ", ") + g.name;
    input_error("dataset '{}': no such file, and '{}' is not a generator ({})", spec, name, known);
  }
  ParamValues given;
  if (colon != std::string::npos) {
    const std::string rest = spec.substr(colon + 1);
    size_t pos = 0;
    while (pos < rest.size() || (pos == rest.size() && !rest.empty() && rest.back() == ',')) {
      size_t comma = rest.find(',', pos);
      if (comma == std::string::npos) comma = rest.size();
      const std::string item = rest.substr(pos, comma - pos);
      pos = comma + 1;
      const size_t eq = item.find('=');
      if (eq == std::string::npos || eq == 0)
        input_error("dataset '{}': '{}' is not key=value", spec, item);
      const std::string key = item.substr(0, eq);
      if (given.count(key)) input_error("dataset '{}': '{}' given twice", spec, key);
      given[key] = parse_number(item.substr(eq + 1), fmt::format("dataset '{}': {}", spec, key));
    }
  }
  ParamValues values = resolve_params(info->params, given, fmt::format("dataset '{}'", spec));
  if ((name == "fibonacci_sphere" || name == "skew_lines") && values["density"] != 0)
    input_error("dataset '{}': density does not apply to {}", spec, name);
  if (info_out) *info_out = info;
  return values;
}

Dataset load_dataset(const std::string& spec) {
  Dataset d = load_dataset_in_input_order(spec);
  require_memory(morton_sort_bytes(d.cloud.size()), spec);
  morton_sort(d.cloud);
  return d;
}

Dataset load_dataset_in_input_order(const std::string& spec) {
  if (spec.empty()) input_error("dataset '': empty name");
  std::error_code ec;
  if (std::filesystem::exists(spec, ec)) return Dataset{read_point_cloud(spec), nullptr};
  const bool looks_like_path =
      spec.find('/') != std::string::npos ||
      (spec.find(':') == std::string::npos && spec.find('.') != std::string::npos);
  if (looks_like_path) input_error("{}: no such file", spec);
  const GeneratorInfo* info = nullptr;
  const auto values = parse_generator_spec(spec, &info);
  // Positions (and normals for surfaces), then the Morton sort's scratch: checked before any work.
  const auto n = size_t(values.at("n"));
  const size_t per_point = sizeof(Vec3) * (is_volume_generator(info->name) ? 1 : 2);
  require_memory(n * per_point + morton_sort_bytes(n), spec);
  Dataset d;
  if (is_volume_generator(info->name)) {
    d.cloud = generate_volume(info->name, values, spec);
    d.cloud.validate();
    return d;
  }
  d.truth = make_surface(info->name, values, spec);
  d.cloud = generate(info->name, values, *d.truth, spec);
  d.cloud.validate();
  return d;
}

}  // namespace pcrt
