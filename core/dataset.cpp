#include "core/dataset.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <functional>
#include <random>

#include "core/error.hpp"
#include "core/memory_budget.hpp"
#include "core/morton.hpp"
#include "core/point_cloud_io.hpp"
#include "core/point_stream.hpp"
#include "core/rng.hpp"

namespace pcrt {
namespace {

// Point indices are 32-bit; what fits in memory is checked when a cloud is made (10^9 points
// fit only as a stream, core/point_stream.hpp).
constexpr double kMaxPoints = 4294967295.0;

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

using Placement = std::function<Vec3(size_t, Vec3&)>;

// Draws points one at a time (by `place`, or uniformly by area from the surface, thinned by
// `density` along x), each moved by isotropic Gaussian noise of standard deviation `noise`: the
// one sequence a generated cloud and its stream (core/point_stream.hpp) both deliver.
class SurfaceSampler {
 public:
  SurfaceSampler(const Surface& surface, uint64_t seed, double noise, double density,
                 Placement place)
      : surface_(surface),
        rng_(seed, 0x5eed),
        gauss_engine_(mix64(seed)),
        gauss_(0.0, noise),
        noise_(noise),
        density_(density),
        box_(surface.bounds()),
        span_(std::max(box_.extent().x(), 1e-30f)),
        place_(std::move(place)) {}

  void next(Vec3& x, Vec3& normal) {
    for (;;) {
      if (place_) {
        x = place_(tries_++, normal);
        break;
      }
      x = surface_.sample(rng_, normal);
      if (density_ <= 0) break;
      const double w = 1.0 - density_ * (x.x() - box_.lo.x()) / span_;
      if (rng_.uniform_double() < w) break;
    }
    if (noise_ > 0)
      x += Vec3(float(gauss_(gauss_engine_)), float(gauss_(gauss_engine_)),
                float(gauss_(gauss_engine_)));
  }

 private:
  const Surface& surface_;
  Rng rng_;
  std::mt19937_64 gauss_engine_;
  std::normal_distribution<double> gauss_;
  double noise_, density_;
  Aabb box_;
  float span_;
  Placement place_;
  size_t tries_ = 0;
};

PointCloud sample_points(const Surface& surface, size_t n, uint64_t seed, double noise,
                         double density, const std::string& name, Placement place) {
  SurfaceSampler sampler(surface, seed, noise, density, std::move(place));
  PointCloud cloud;
  cloud.name = name;
  cloud.positions.resize(n);
  cloud.normals.resize(n);
  for (size_t i = 0; i < n; ++i) sampler.next(cloud.positions[i], cloud.normals[i]);
  return cloud;
}

// The fibonacci spiral's placement of point i of n on a sphere of `radius`; others place none.
Placement placement_of(const std::string& name, const ParamValues& p) {
  if (name != "fibonacci_sphere") return nullptr;
  // Density thinning would break the spiral's determinism; it is rejected at parse time.
  const auto n = static_cast<size_t>(p.at("n"));
  const auto radius = static_cast<float>(p.at("radius"));
  return [n, radius](size_t i, Vec3& normal) {
    normal = fibonacci_point(i, n);
    return Vec3(radius * normal);
  };
}

SurfaceSampler sampler_for(const std::string& name, const ParamValues& p, const Surface& surface) {
  return SurfaceSampler(surface, static_cast<uint64_t>(p.at("seed")), p.at("noise"),
                        p.at("density"), placement_of(name, p));
}

}  // namespace

PointCloud sample_surface(const Surface& surface, size_t n, uint64_t seed, double noise,
                          double density, const std::string& name) {
  return sample_points(surface, n, seed, noise, density, name, nullptr);
}

namespace {

PointCloud generate(const std::string& name, const ParamValues& p, const Surface& surface,
                    const std::string& spec) {
  return sample_points(surface, static_cast<size_t>(p.at("n")), static_cast<uint64_t>(p.at("seed")),
                       p.at("noise"), p.at("density"), spec, placement_of(name, p));
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
       with_common({{"radius", 1, 1e-6, 1e12, "sphere radius"}})},
      {"fibonacci_sphere",
       "Fibonacci-spiral points on a sphere at the origin (near-uniform, seed only affects noise)",
       with_common({{"radius", 1, 1e-6, 1e12, "sphere radius"}})},
      {"plane", "uniform random points on the square z=0, |x|,|y| <= size/2",
       with_common({{"size", 2, 1e-6, 1e12, "side of the square"}})},
      {"torus", "uniform (by area) random points on a torus around the z axis at the origin",
       with_common(
           {{"R", 1, 1e-6, 1e12, "major radius"}, {"r", 0.25, 1e-6, 1e12, "minor radius"}})},
      {"bumpy_sphere",
       "uniform (by area) points on a sphere displaced by a*sin(f x)sin(f y)sin(f z)",
       with_common({{"radius", 1, 1e-6, 1e12, "base radius"},
                    {"amplitude", 0.05, 0, 0.5, "relative displacement"},
                    {"frequency", 6, 0, 100, "angular frequency f"}})},
      {"ball", "uniform random points inside a ball at the origin (no surface: Delaunay tests)",
       with_common({{"size", 2, 1e-6, 1e12, "diameter"}})},
      {"cube", "uniform random points inside a cube at the origin (no surface: Delaunay tests)",
       with_common({{"size", 2, 1e-6, 1e12, "side"}})},
      {"skew_lines",
       "N/2 random points on each of two skew lines (x axis at z=-size/2, y axis at z=+size/2): "
       "the Delaunay worst case, (N/2-1)^2 cells",
       with_common({{"size", 2, 1e-6, 1e12, "length of each segment and distance between them"}})},
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

namespace pcrt {
namespace {

// A surface generator re-run on every read: its sampler is made afresh, so every read delivers
// the same points, kChunkPoints at a time.
class GeneratorStream final : public PointStream {
 public:
  GeneratorStream(std::string spec, std::string generator, ParamValues values)
      : spec_(std::move(spec)),
        generator_(std::move(generator)),
        values_(std::move(values)),
        surface_(make_surface(generator_, values_, spec_)) {}

  [[nodiscard]] const std::string& name() const override { return spec_; }
  [[nodiscard]] size_t size() const override { return size_t(values_.at("n")); }
  void read(const std::function<void(const PointChunk&)>& chunk) const override {
    SurfaceSampler sampler = sampler_for(generator_, values_, *surface_);
    std::vector<Vec3> positions(kChunkPoints), normals(kChunkPoints);
    for (size_t first = 0; first < size(); first += kChunkPoints) {
      const size_t count = std::min(kChunkPoints, size() - first);
      for (size_t i = 0; i < count; ++i) sampler.next(positions[i], normals[i]);
      chunk(PointChunk{{positions.data(), count}, {normals.data(), count}, first});
    }
  }

 private:
  std::string spec_, generator_;
  ParamValues values_;
  std::shared_ptr<const Surface> surface_;
};

}  // namespace

const Aabb& PointStream::bounds() const {
  if (bounds_) return *bounds_;
  Aabb box;
  size_t count = 0;
  read([&](const PointChunk& c) {
    for (size_t i = 0; i < c.positions.size(); ++i) {
      if (!within_coordinate_range(c.positions[i]) || !c.normals[i].allFinite())
        input_error("{}: point {} is not finite or lies beyond {:g}", name(), c.first + i,
                    double(kMaxCoordinate));
      box.extend(c.positions[i]);
    }
    count += c.positions.size();
  });
  if (count != size()) input_error("{}: delivered {} points, announced {}", name(), count, size());
  if (count == 0) input_error("{}: no points", name());
  require_extent(box, name());
  return bounds_.emplace(box);
}

std::unique_ptr<PointStream> open_point_stream(const std::string& spec) {
  std::error_code ec;
  if (spec.empty()) input_error("dataset '': empty name");
  if (std::filesystem::exists(spec, ec)) {
    const std::string ext = lowercase_extension(spec);
    if (ext == ".xyz" || ext == ".pwn") return open_xyz_stream(spec);
    if (ext != ".ply")
      input_error("{}: only PLY, XYZ and PWN files and generator specs (sphere:n=...) are streamed",
                  spec);
    return open_ply_stream(spec);
  }
  const GeneratorInfo* info = nullptr;
  ParamValues values = parse_generator_spec(spec, &info);
  if (is_volume_generator(info->name))
    input_error("dataset '{}': {} has no normals; only surface generators stream", spec,
                info->name);
  return std::make_unique<GeneratorStream>(spec, info->name, std::move(values));
}

}  // namespace pcrt
