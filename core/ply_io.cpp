// PLY reader and writer (Turk's format: header, then elements in header order).
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include "core/error.hpp"
#include "core/file_output.hpp"
#include "core/point_cloud_io.hpp"
#include "core/point_stream.hpp"
#include "core/text_scanner.hpp"

namespace pcrt {
namespace {

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

std::optional<PlyType> parse_type(std::string_view s) {
  if (s == "char" || s == "int8") return PlyType::kInt8;
  if (s == "uchar" || s == "uint8") return PlyType::kUint8;
  if (s == "short" || s == "int16") return PlyType::kInt16;
  if (s == "ushort" || s == "uint16") return PlyType::kUint16;
  if (s == "int" || s == "int32") return PlyType::kInt32;
  if (s == "uint" || s == "uint32") return PlyType::kUint32;
  if (s == "float" || s == "float32") return PlyType::kFloat32;
  if (s == "double" || s == "float64") return PlyType::kFloat64;
  return std::nullopt;
}

size_t type_size(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 0;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;
  bool is_list = false;
  PlyType count_type = PlyType::kUint8;
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  size_t data_offset = 0;  // byte offset of the first element
  size_t header_lines = 0;
};

// One header line's place for its errors: "FILE: header line N".
struct HeaderLine {
  const std::string& path;
  size_t number;
  const std::vector<std::string>& tok;
};

PlyFormat parse_format_line(const HeaderLine& l) {
  const auto& tok = l.tok;
  if (tok.size() != 3) input_error("{}: header line {}: malformed format line", l.path, l.number);
  if (tok[1] == "ascii") return PlyFormat::kAscii;
  if (tok[1] == "binary_little_endian") return PlyFormat::kBinaryLittleEndian;
  if (tok[1] == "binary_big_endian") return PlyFormat::kBinaryBigEndian;
  input_error("{}: header line {}: unknown format '{}'", l.path, l.number, tok[1]);
}

PlyElement parse_element_line(const HeaderLine& l) {
  const auto& tok = l.tok;
  if (tok.size() != 3) input_error("{}: header line {}: malformed element line", l.path, l.number);
  PlyElement e;
  e.name = tok[1];
  auto [p, ec] = std::from_chars(tok[2].data(), tok[2].data() + tok[2].size(), e.count);
  if (ec != std::errc() || p != tok[2].data() + tok[2].size())
    input_error("{}: header line {}: element count '{}' is not a non-negative integer", l.path,
                l.number, tok[2]);
  return e;
}

PlyProperty parse_property_line(const HeaderLine& l) {
  const auto& tok = l.tok;
  if (tok.size() == 5 && tok[1] == "list") {
    auto ct = parse_type(tok[2]);
    auto it = parse_type(tok[3]);
    if (!ct || !it) input_error("{}: header line {}: unknown list types", l.path, l.number);
    if (*ct == PlyType::kFloat32 || *ct == PlyType::kFloat64)
      input_error("{}: header line {}: a list count cannot be a float", l.path, l.number);
    return PlyProperty{tok[4], *it, true, *ct};
  }
  if (tok.size() == 3) {
    auto t = parse_type(tok[1]);
    if (!t) input_error("{}: header line {}: unknown property type '{}'", l.path, l.number, tok[1]);
    return PlyProperty{tok[2], *t, false, PlyType::kUint8};
  }
  input_error("{}: header line {}: malformed property line", l.path, l.number);
}

std::vector<std::string> tokens_of(std::string line) {
  if (!line.empty() && line.back() == '\r') line.pop_back();
  std::istringstream in(line);
  std::vector<std::string> tok;
  for (std::string t; in >> t;) tok.push_back(t);
  return tok;
}

void check_header(const PlyHeader& h, bool have_format, const std::string& path) {
  if (!have_format) input_error("{}: PLY header has no format line", path);
  // A record without properties takes no bytes, so no file length could bound its count.
  for (const PlyElement& e : h.elements)
    if (e.count > 0 && e.properties.empty())
      input_error("{}: element '{}' has {} records but no properties", path, e.name, e.count);
}

PlyHeader parse_header(const std::string& text, const std::string& path) {
  PlyHeader h;
  size_t pos = 0;
  size_t line_no = 0;
  bool have_format = false;
  while (true) {
    const size_t end = text.find('\n', pos);
    if (end == std::string::npos) input_error("{}: PLY header has no end_header line", path);
    const std::vector<std::string> tok = tokens_of(text.substr(pos, end - pos));
    pos = end + 1;
    const HeaderLine line{path, ++line_no, tok};
    if (line_no == 1) {
      if (tok.size() != 1 || tok[0] != "ply")
        input_error("{}: not a PLY file (first line is not 'ply')", path);
      continue;
    }
    if (tok.empty() || tok[0] == "comment" || tok[0] == "obj_info") continue;
    if (tok[0] == "end_header") break;
    if (tok[0] == "format") {
      h.format = parse_format_line(line);
      have_format = true;
    } else if (tok[0] == "element") {
      h.elements.push_back(parse_element_line(line));
    } else if (tok[0] == "property") {
      if (h.elements.empty())
        input_error("{}: header line {}: property before any element", path, line_no);
      h.elements.back().properties.push_back(parse_property_line(line));
    } else {
      input_error("{}: header line {}: unexpected '{}'", path, line_no, tok[0]);
    }
  }
  check_header(h, have_format, path);
  h.data_offset = pos;
  h.header_lines = line_no;
  return h;
}

// Where the vertex properties we understand sit in a vertex record.
struct VertexLayout {
  int x = -1, y = -1, z = -1, nx = -1, ny = -1, nz = -1, r = -1, g = -1, b = -1, radius = -1;
  // The 3D Gaussian Splatting layout (core/gaussians.hpp): log scales, rotation quaternion
  // (w, x, y, z), opacity logit, and the zeroth SH band of the colour; f_rest_* are not read.
  std::array<int, 3> scale = {-1, -1, -1}, dc = {-1, -1, -1};
  std::array<int, 4> rot = {-1, -1, -1, -1};
  int opacity = -1;
  [[nodiscard]] bool gaussian() const { return opacity >= 0; }
  [[nodiscard]] bool dc_colour() const { return dc[0] >= 0 && r < 0; }
};

// The slot of a 3D Gaussian Splatting property ("scale_0", "rot_3", "f_dc_1", "opacity").
int* gaussian_slot(VertexLayout& l, const std::string& n) {
  auto indexed = [&](const char* prefix, auto& slots) -> int* {
    const std::string p(prefix);
    if (n.size() != p.size() + 1 || n.compare(0, p.size(), p) != 0) return nullptr;
    const int k = n.back() - '0';
    return k >= 0 && k < int(slots.size()) ? &slots[size_t(k)] : nullptr;
  };
  if (n == "opacity") return &l.opacity;
  if (int* s = indexed("scale_", l.scale)) return s;
  if (int* s = indexed("rot_", l.rot)) return s;
  return indexed("f_dc_", l.dc);
}

void check_gaussian_layout(const VertexLayout& l, const std::string& path) {
  const auto present = [](const auto& slots) {
    return int(std::count_if(slots.begin(), slots.end(), [](int i) { return i >= 0; }));
  };
  const int g = present(l.scale) + present(l.rot) + (l.opacity >= 0);
  if (g != 0 && g != 8)
    input_error(
        "{}: vertex element has only some of the Gaussian properties scale_0..2, "
        "rot_0..3 and opacity",
        path);
  const int dc = present(l.dc);
  if (dc != 0 && dc != 3) input_error("{}: vertex element has only some of f_dc_0..2", path);
}

VertexLayout vertex_layout(const PlyElement& e, const std::string& path) {
  VertexLayout l;
  for (size_t i = 0; i < e.properties.size(); ++i) {
    const std::string& n = e.properties[i].name;
    int* slot = nullptr;
    if (n == "x")
      slot = &l.x;
    else if (n == "y")
      slot = &l.y;
    else if (n == "z")
      slot = &l.z;
    else if (n == "nx")
      slot = &l.nx;
    else if (n == "ny")
      slot = &l.ny;
    else if (n == "nz")
      slot = &l.nz;
    else if (n == "red" || n == "diffuse_red")
      slot = &l.r;
    else if (n == "green" || n == "diffuse_green")
      slot = &l.g;
    else if (n == "blue" || n == "diffuse_blue")
      slot = &l.b;
    else if (n == "radius" || n == "scale")
      slot = &l.radius;
    else
      slot = gaussian_slot(l, n);
    if (!slot) continue;
    if (e.properties[i].is_list) input_error("{}: vertex property '{}' is a list", path, n);
    if (*slot >= 0)
      input_error("{}: vertex property '{}' gives a value property '{}' gave already", path, n,
                  e.properties[size_t(*slot)].name);
    *slot = static_cast<int>(i);
  }
  if (l.x < 0 || l.y < 0 || l.z < 0) input_error("{}: vertex element lacks x, y and z", path);
  const int normals = (l.nx >= 0) + (l.ny >= 0) + (l.nz >= 0);
  if (normals != 0 && normals != 3)
    input_error("{}: vertex element has only some of nx, ny, nz", path);
  const int colours = (l.r >= 0) + (l.g >= 0) + (l.b >= 0);
  if (colours != 0 && colours != 3)
    input_error("{}: vertex element has only some of red, green, blue", path);
  check_gaussian_layout(l, path);
  return l;
}

uint8_t colour_byte(double v, PlyType t) {
  switch (t) {
    case PlyType::kFloat32:
    case PlyType::kFloat64:
      return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
    case PlyType::kUint16:
      return static_cast<uint8_t>(std::clamp(v, 0.0, 65535.0) / 257.0);
    default:
      return static_cast<uint8_t>(std::clamp(v, 0.0, 255.0));
  }
}

// Collects one vertex's recognised values into the cloud.
struct VertexSink {
  const PlyElement& element;
  VertexLayout layout;
  PointCloud& cloud;
  std::vector<double> values;
  LocalFrame frame;

  void reserve(uint64_t n) {
    cloud.positions.reserve(n);
    if (layout.nx >= 0) cloud.normals.reserve(n);
    if (layout.r >= 0) cloud.colours.reserve(n);
    if (layout.radius >= 0) cloud.radii.reserve(n);
    if (layout.dc_colour()) cloud.colours.reserve(n);
    if (layout.gaussian()) {
      cloud.gaussians.scales.reserve(n);
      cloud.gaussians.rotations.reserve(n);
      cloud.gaussians.opacities.reserve(n);
    }
  }
  // One particle's activated values; the file's own are checked where exp and sigmoid need it.
  void emit_gaussian(const std::string& path, uint64_t index) {
    auto v = [&](int i) { return values[size_t(i)]; };
    const Vec3d log_scale(v(layout.scale[0]), v(layout.scale[1]), v(layout.scale[2]));
    const Vec3 scale = log_scale.array().exp().cast<float>().matrix();
    if (!(log_scale.allFinite() && scale.allFinite() && scale.minCoeff() > 0.0f))
      input_error("{}: vertex {} has log scales ({:g}, {:g}, {:g}) beyond float's range", path,
                  index, log_scale.x(), log_scale.y(), log_scale.z());
    const double logit_opacity = v(layout.opacity);
    if (!std::isfinite(logit_opacity))
      input_error("{}: vertex {} has a non-finite opacity", path, index);
    Eigen::Vector4d q(v(layout.rot[0]), v(layout.rot[1]), v(layout.rot[2]), v(layout.rot[3]));
    if (!q.allFinite() || !(q.norm() > 1e-12))
      input_error("{}: vertex {} has a zero or non-finite rotation quaternion", path, index);
    cloud.gaussians.scales.push_back(scale);
    cloud.gaussians.rotations.push_back(q.normalized().cast<float>());
    cloud.gaussians.opacities.push_back(float(1.0 / (1.0 + std::exp(-logit_opacity))));
  }
  void emit_dc_colour(const std::string& path, uint64_t index) {
    for (int k : layout.dc)
      if (!std::isfinite(values[size_t(k)]))
        input_error("{}: vertex {} has a non-finite colour", path, index);
    auto byte = [&](int i) {
      const double c = 0.5 + double(kShC0) * values[size_t(i)];
      return static_cast<uint8_t>(std::lround(std::clamp(c, 0.0, 1.0) * 255.0));
    };
    cloud.colours.push_back(Rgb8{byte(layout.dc[0]), byte(layout.dc[1]), byte(layout.dc[2])});
  }
  void emit(const std::string& path, uint64_t index) {
    auto v = [&](int i) { return values[size_t(i)]; };
    auto f = [&](int i) { return static_cast<float>(v(i)); };
    const Vec3d world(v(layout.x), v(layout.y), v(layout.z));
    if (!world.cast<float>().allFinite())
      input_error("{}: vertex {} has a non-finite or out-of-range coordinate", path, index);
    if (!within_coordinate_range(world))
      input_error("{}: vertex {} has a coordinate beyond +-{:g}", path, index, kMaxCoordinate);
    cloud.positions.push_back(frame.place(world));
    if (layout.nx >= 0) cloud.normals.emplace_back(f(layout.nx), f(layout.ny), f(layout.nz));
    if (layout.r >= 0) {
      const auto& ps = element.properties;
      if (!std::isfinite(v(layout.r) + v(layout.g) + v(layout.b)))
        input_error("{}: vertex {} has a non-finite colour", path, index);
      cloud.colours.push_back(Rgb8{colour_byte(v(layout.r), ps[size_t(layout.r)].type),
                                   colour_byte(v(layout.g), ps[size_t(layout.g)].type),
                                   colour_byte(v(layout.b), ps[size_t(layout.b)].type)});
    }
    if (layout.radius >= 0) cloud.radii.push_back(f(layout.radius));
    if (layout.dc_colour()) emit_dc_colour(path, index);
    if (layout.gaussian()) emit_gaussian(path, index);
  }
};

// An ascii value of an integer property must be one its type holds: a uchar colour of 300 is a
// damaged file, not a colour to clamp.
void check_ascii_value(double v, const PlyProperty& p, const std::string& path, size_t line) {
  double lo = 0, hi = 0;
  switch (p.type) {
    case PlyType::kInt8:
      lo = -128, hi = 127;
      break;
    case PlyType::kUint8:
      hi = 255;
      break;
    case PlyType::kInt16:
      lo = -32768, hi = 32767;
      break;
    case PlyType::kUint16:
      hi = 65535;
      break;
    case PlyType::kInt32:
      lo = -2147483648.0, hi = 2147483647.0;
      break;
    case PlyType::kUint32:
      hi = 4294967295.0;
      break;
    case PlyType::kFloat32:
    case PlyType::kFloat64:
      return;
  }
  if (!(v >= lo && v <= hi && v == std::floor(v)))
    input_error("{}: line {}: property '{}' is {:g}, not an integer in [{:g}, {:g}]", path, line,
                p.name, v, lo, hi);
}

// Collects the polygons of the 'face' element's vertex_indices list, fanned into triangles.
struct FaceSink {
  std::vector<std::array<uint32_t, 3>>* triangles = nullptr;
  std::vector<double> polygon;
  static bool is_index_list(const PlyElement& e, const PlyProperty& p) {
    return e.name == "face" && p.is_list &&
           (p.name == "vertex_indices" || p.name == "vertex_index");
  }
  void emit(const std::string& path, uint64_t face, uint64_t vertices) {
    if (polygon.size() < 3) input_error("{}: face {} has {} vertices", path, face, polygon.size());
    for (double v : polygon)
      if (!(v >= 0 && v < double(vertices)) || v != std::floor(v))
        input_error("{}: face {} names vertex {} of {}", path, face, v, vertices);
    for (size_t k = 1; k + 1 < polygon.size(); ++k)
      triangles->push_back({uint32_t(polygon[0]), uint32_t(polygon[k]), uint32_t(polygon[k + 1])});
    polygon.clear();
  }
};

template <typename T>
T load_raw(const char* p, bool swap) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  if (swap) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    std::reverse(b, b + sizeof(T));
    std::memcpy(&v, b, sizeof(T));
  }
  return v;
}

double load_binary(const char* p, PlyType t, bool swap) {
  switch (t) {
    case PlyType::kInt8:
      return load_raw<int8_t>(p, false);
    case PlyType::kUint8:
      return load_raw<uint8_t>(p, false);
    case PlyType::kInt16:
      return load_raw<int16_t>(p, swap);
    case PlyType::kUint16:
      return load_raw<uint16_t>(p, swap);
    case PlyType::kInt32:
      return load_raw<int32_t>(p, swap);
    case PlyType::kUint32:
      return load_raw<uint32_t>(p, swap);
    case PlyType::kFloat32:
      return load_raw<float>(p, swap);
    case PlyType::kFloat64:
      return load_raw<double>(p, swap);
  }
  return 0;
}

size_t min_record_bytes(const PlyElement& e) {
  size_t s = 0;
  for (const auto& p : e.properties) s += p.is_list ? type_size(p.count_type) : type_size(p.type);
  return s;
}

void read_binary(const std::string& text, const PlyHeader& h, const std::string& path,
                 PointCloud& cloud, FaceSink& faces) {
  const bool swap =
      (h.format == PlyFormat::kBinaryBigEndian) == (std::endian::native == std::endian::little);
  size_t pos = h.data_offset;
  for (const PlyElement& e : h.elements) {
    const bool is_vertex = e.name == "vertex";
    if (e.count > 0 && min_record_bytes(e) > 0 &&
        e.count > (text.size() - pos) / min_record_bytes(e))
      input_error(
          "{}: truncated: the header promises {} '{}' elements but the file is too short for them",
          path, e.count, e.name);
    std::optional<VertexSink> sink;
    if (is_vertex) {
      sink.emplace(VertexSink{
          e, vertex_layout(e, path), cloud, std::vector<double>(e.properties.size()), {}});
      sink->reserve(e.count);
    }
    for (uint64_t i = 0; i < e.count; ++i) {
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const PlyProperty& prop = e.properties[k];
        auto need = [&](size_t bytes) {
          if (text.size() - pos < bytes)
            input_error("{}: truncated in '{}' element {} of {}", path, e.name, i, e.count);
        };
        if (prop.is_list) {
          need(type_size(prop.count_type));
          const double n = load_binary(text.data() + pos, prop.count_type, swap);
          pos += type_size(prop.count_type);
          if (n < 0) input_error("{}: '{}' element {} has a negative list length", path, e.name, i);
          const size_t bytes = static_cast<size_t>(n) * type_size(prop.type);
          need(bytes);
          if (faces.triangles && FaceSink::is_index_list(e, prop)) {
            for (size_t j = 0; j < size_t(n); ++j)
              faces.polygon.push_back(
                  load_binary(text.data() + pos + j * type_size(prop.type), prop.type, swap));
            faces.emit(path, i, cloud.positions.size());
          }
          pos += bytes;
        } else {
          need(type_size(prop.type));
          if (sink) sink->values[k] = load_binary(text.data() + pos, prop.type, swap);
          pos += type_size(prop.type);
        }
      }
      if (sink) sink->emit(path, i);
    }
    if (sink) cloud.origin = sink->frame.origin;
  }
  if (pos != text.size())
    input_error("{}: {} bytes follow the last element; the header's counts do not match the data",
                path, text.size() - pos);
}

void read_ascii(const std::string& text, const PlyHeader& h, const std::string& path,
                PointCloud& cloud, FaceSink& faces) {
  TextScanner scan(std::string_view(text).substr(h.data_offset), path, h.header_lines);
  const size_t remaining_lines =
      static_cast<size_t>(std::count(text.begin() + long(h.data_offset), text.end(), '\n')) + 1;
  for (const PlyElement& e : h.elements) {
    if (e.count > remaining_lines)
      input_error("{}: truncated: the header promises {} '{}' elements but only {} lines remain",
                  path, e.count, e.name, remaining_lines);
    std::optional<VertexSink> sink;
    if (e.name == "vertex") {
      sink.emplace(VertexSink{
          e, vertex_layout(e, path), cloud, std::vector<double>(e.properties.size()), {}});
      sink->reserve(e.count);
    }
    for (uint64_t i = 0; i < e.count; ++i) {
      if (!scan.next_line(false))
        input_error("{}: truncated: file ends at '{}' element {} of {}", path, e.name, i, e.count);
      const auto& tok = scan.tokens();
      size_t t = 0;
      for (size_t k = 0; k < e.properties.size(); ++k) {
        if (t >= tok.size())
          input_error("{}: line {}: '{}' element {} has too few values", path, scan.line(), e.name,
                      i);
        if (e.properties[k].is_list) {
          const auto n = scan.number<long long>(t);
          if (n < 0) input_error("{}: line {}: negative list length", path, scan.line());
          if (faces.triangles && FaceSink::is_index_list(e, e.properties[k])) {
            if (t + 1 + size_t(n) > tok.size())
              input_error("{}: line {}: face {} has too few indices", path, scan.line(), i);
            for (size_t j = 0; j < size_t(n); ++j)
              faces.polygon.push_back(scan.number<double>(t + 1 + j));
            faces.emit(path, i, cloud.positions.size());
          }
          t += 1 + static_cast<size_t>(n);
        } else {
          const double v = scan.number<double>(t++);
          check_ascii_value(v, e.properties[k], path, scan.line());
          if (sink) sink->values[k] = v;
        }
      }
      if (t != tok.size())
        input_error("{}: line {}: '{}' element {} has {} values, the header says {}", path,
                    scan.line(), e.name, i, tok.size(), t);
      if (sink) sink->emit(path, i);
    }
    if (sink) cloud.origin = sink->frame.origin;
  }
  if (scan.next_line(false))
    input_error(
        "{}: line {}: data after the last element; the header's counts do not match the data", path,
        scan.line());
}

// Trainers write no normals of their own (3D Gaussian Splatting stores zeros, 3dgrut (0, 0, 1) for
// every particle): a particle's normal is its shortest axis, the normal of a flat particle's plane,
// as the splat methods need one per point.
void gaussian_normals(PointCloud& cloud) {
  const GaussianParticles& g = cloud.gaussians;
  cloud.normals.resize(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i)
    cloud.normals[i] = shortest_axis(g.scales[i], g.rotations[i]);
}

}  // namespace

PointCloud read_ply(const std::string& path) { return read_ply(path, nullptr); }

PointCloud read_ply(const std::string& path, std::vector<std::array<uint32_t, 3>>* triangles) {
  return parse_ply(read_file(path), path, triangles);
}

PointCloud parse_ply(const std::string& text, const std::string& path,
                     std::vector<std::array<uint32_t, 3>>* triangles) {
  const PlyHeader h = parse_header(text, path);
  if (std::none_of(h.elements.begin(), h.elements.end(),
                   [](const PlyElement& e) { return e.name == "vertex"; }))
    input_error("{}: PLY file has no vertex element", path);
  // Faces index the vertices read so far: a mesh's face element must follow its vertex element.
  const auto element_named = [&](const char* name) {
    return std::find_if(h.elements.begin(), h.elements.end(),
                        [&](const PlyElement& e) { return e.name == name; });
  };
  if (triangles && element_named("face") < element_named("vertex"))
    input_error("{}: the face element comes before the vertex element (a mesh's vertices first)",
                path);
  PointCloud cloud;
  cloud.name = path;
  FaceSink faces{triangles, {}};
  if (h.format == PlyFormat::kAscii)
    read_ascii(text, h, path, cloud, faces);
  else
    read_binary(text, h, path, cloud, faces);
  if (cloud.has_gaussians()) gaussian_normals(cloud);
  normalize_loaded_normals(cloud);
  return cloud;
}

namespace {

template <typename T>
void put_binary(std::ostream& out, T v, bool big_endian) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big_endian == (std::endian::native == std::endian::little)) std::reverse(b, b + sizeof(T));
  out.write(b, sizeof(T));
}

void write_ply_header(std::ostream& out, const PointCloud& cloud, PlyFormat format) {
  out << "ply\nformat "
      << (format == PlyFormat::kAscii                ? "ascii"
          : format == PlyFormat::kBinaryLittleEndian ? "binary_little_endian"
                                                     : "binary_big_endian")
      << " 1.0\ncomment written by pcrt\nelement vertex " << cloud.size() << "\n";
  // A georeferenced cloud goes back to its file's coordinates, which float cannot hold.
  const char* type = cloud.origin.isZero() ? "float" : "double";
  out << fmt::format("property {0} x\nproperty {0} y\nproperty {0} z\n", type);
  if (cloud.has_normals()) out << "property float nx\nproperty float ny\nproperty float nz\n";
  if (cloud.has_gaussians()) {
    // 3D Gaussian Splatting's layout, in its order; colours go into the zeroth SH band.
    out << "property float f_dc_0\nproperty float f_dc_1\nproperty float f_dc_2\n"
           "property float opacity\n"
           "property float scale_0\nproperty float scale_1\nproperty float scale_2\n"
           "property float rot_0\nproperty float rot_1\nproperty float rot_2\nproperty float "
           "rot_3\n";
  } else if (cloud.has_colours()) {
    out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  }
  if (cloud.has_radii()) out << "property float radius\n";
  out << "end_header\n";
}

// Particle i as the file layout stores it: f_dc (grey without colours), opacity logit, log
// scales, rotation. Opacities of exactly 0 or 1 are written 1e-6 inside, where the logit is finite.
std::array<float, 11> gaussian_record(const PointCloud& cloud, size_t i) {
  const GaussianParticles& g = cloud.gaussians;
  std::array<float, 11> r{};
  for (int k = 0; k < 3; ++k) {
    const float c = cloud.has_colours() ? float((&cloud.colours[i].r)[k]) / 255.0f : 0.5f;
    r[size_t(k)] = (c - 0.5f) / kShC0;
  }
  r[3] = logit(std::clamp(g.opacities[i], 1e-6f, 1.0f - 1e-6f));
  for (int k = 0; k < 3; ++k) r[size_t(4 + k)] = std::log(g.scales[i][k]);
  for (int k = 0; k < 4; ++k) r[size_t(7 + k)] = g.rotations[i][k];
  return r;
}

void write_ascii_vertex(std::ostream& out, const PointCloud& cloud, size_t i) {
  if (cloud.origin.isZero()) {
    const Vec3& p = cloud.positions[i];
    out << fmt::format("{} {} {}", p.x(), p.y(), p.z());
  } else {
    const Vec3d p = to_world(cloud.positions[i], cloud.origin);
    out << fmt::format("{} {} {}", p.x(), p.y(), p.z());
  }
  if (cloud.has_normals()) {
    const Vec3& n = cloud.normals[i];
    out << fmt::format(" {} {} {}", n.x(), n.y(), n.z());
  }
  if (cloud.has_gaussians()) {
    for (float v : gaussian_record(cloud, i)) out << fmt::format(" {}", v);
  } else if (cloud.has_colours()) {
    const Rgb8& c = cloud.colours[i];
    out << ' ' << int(c.r) << ' ' << int(c.g) << ' ' << int(c.b);
  }
  if (cloud.has_radii()) out << ' ' << fmt::format("{}", cloud.radii[i]);
  out << '\n';
}

void write_binary_vertex(std::ostream& out, const PointCloud& cloud, size_t i, bool big) {
  if (cloud.origin.isZero()) {
    for (int k = 0; k < 3; ++k) put_binary(out, cloud.positions[i][k], big);
  } else {
    const Vec3d p = to_world(cloud.positions[i], cloud.origin);
    for (int k = 0; k < 3; ++k) put_binary(out, p[k], big);
  }
  if (cloud.has_normals())
    for (int k = 0; k < 3; ++k) put_binary(out, cloud.normals[i][k], big);
  if (cloud.has_gaussians()) {
    for (float v : gaussian_record(cloud, i)) put_binary(out, v, big);
  } else if (cloud.has_colours()) {
    const Rgb8& c = cloud.colours[i];
    out.put(static_cast<char>(c.r)).put(static_cast<char>(c.g)).put(static_cast<char>(c.b));
  }
  if (cloud.has_radii()) put_binary(out, cloud.radii[i], big);
}

}  // namespace

void write_ply(const std::string& path, const PointCloud& cloud, PlyFormat format) {
  write_file_atomically(
      path,
      [&](std::ostream& out) {
        write_ply_header(out, cloud, format);
        const bool big = format == PlyFormat::kBinaryBigEndian;
        for (size_t i = 0; i < cloud.size(); ++i) {
          if (format == PlyFormat::kAscii)
            write_ascii_vertex(out, cloud, i);
          else
            write_binary_vertex(out, cloud, i, big);
        }
      },
      format != PlyFormat::kAscii);
}

namespace {

// A vertex's property k, from its binary record or its ascii line's values.
struct RecordField {
  const char* record;
  const std::vector<size_t>& offsets;  // of each property in a record
  const PlyElement& vertex;
  bool swap;
  double operator()(int k) const {
    return load_binary(record + offsets[size_t(k)], vertex.properties[size_t(k)].type, swap);
  }
};
struct ValuesField {
  const std::vector<double>& values;
  double operator()(int k) const { return values[size_t(k)]; }
};

// A PLY file's vertices, chunk by chunk (core/point_stream.hpp): what `pcrt render --stream`
// reads a cloud too large to hold from. The vertex element first, no list property in it, the
// file's own normals; binary records read as they are, ascii lines in blocks (the same values as
// read_ply's, parsed as it parses them). Georeferenced files are read relative to the local
// origin of their first vertex, as read_ply does.
class PlyStream final : public PointStream {
 public:
  explicit PlyStream(std::string path) : path_(std::move(path)) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path_, ec))
      input_error("{}: not a regular file (only files are streamed)", path_);
    file_bytes_ = std::filesystem::file_size(path_, ec);
    if (ec) input_error("{}: cannot read its size", path_);
    header_ = parse_header(read_prefix(std::min<uint64_t>(file_bytes_, kMaxHeaderBytes)), path_);
    check_streamable();
    swap_ = (header_.format == PlyFormat::kBinaryBigEndian) ==
            (std::endian::native == std::endian::little);
    if (size() > 0) frame_.choose(first_position());
  }

  [[nodiscard]] const std::string& name() const override { return path_; }
  [[nodiscard]] size_t size() const override { return size_t(vertex().count); }
  [[nodiscard]] Vec3d origin() const override { return frame_.origin; }

  void read(const std::function<void(const PointChunk&)>& chunk) const override {
    if (ascii()) return read_lines(chunk);
    std::ifstream in = open_at(header_.data_offset);
    std::vector<char> bytes(kChunkPoints * record_);
    std::vector<Vec3> positions(kChunkPoints), normals(kChunkPoints);
    for (size_t first = 0; first < size(); first += kChunkPoints) {
      const size_t count = std::min(kChunkPoints, size() - first);
      if (!in.read(bytes.data(), std::streamsize(count * record_)))
        input_error("{}: truncated: the file ended within vertex {} of {}", path_, first, size());
      for (size_t i = 0; i < count; ++i)
        decode(record_field(bytes.data() + i * record_), first + i, positions[i], normals[i]);
      chunk(PointChunk{{positions.data(), count}, {normals.data(), count}, first});
    }
  }

 private:
  [[nodiscard]] bool ascii() const { return header_.format == PlyFormat::kAscii; }

  // The ascii vertex lines, kChunkPoints at a time.
  void read_lines(const std::function<void(const PointChunk&)>& chunk) const {
    std::vector<Vec3> positions(kChunkPoints), normals(kChunkPoints);
    std::vector<double> values(vertex().properties.size());
    size_t index = 0, held = 0;
    auto flush = [&] {
      chunk(PointChunk{{positions.data(), held}, {normals.data(), held}, index - held});
      held = 0;
    };
    for_each_line_block(path_, header_.data_offset, header_.header_lines,
                        [&](std::string_view text, size_t lines_before) {
                          TextScanner scan(text, path_, lines_before);
                          while (index < size() && scan.next_line(false)) {
                            line_values(scan, index, values);
                            decode(values_field(values), index++, positions[held], normals[held]);
                            if (++held == kChunkPoints) flush();
                          }
                          return index < size();
                        });
    if (index < size())
      input_error("{}: truncated: file ends at 'vertex' element {} of {}", path_, index, size());
    if (held > 0) flush();
  }
  // Vertex `index`'s values from its line, as read_ply's ascii reader takes them.
  void line_values(const TextScanner& scan, size_t index, std::vector<double>& values) const {
    if (scan.tokens().size() < values.size())
      input_error("{}: line {}: 'vertex' element {} has too few values", path_, scan.line(), index);
    if (scan.tokens().size() > values.size())
      input_error("{}: line {}: 'vertex' element {} has {} values, the header says {}", path_,
                  scan.line(), index, scan.tokens().size(), values.size());
    for (size_t k = 0; k < values.size(); ++k) {
      values[k] = scan.number<double>(k);
      check_ascii_value(values[k], vertex().properties[k], path_, scan.line());
    }
  }
  static constexpr uint64_t kMaxHeaderBytes = uint64_t(1) << 20;

  [[nodiscard]] const PlyElement& vertex() const { return header_.elements.front(); }

  [[nodiscard]] std::ifstream open_at(uint64_t offset) const {
    std::ifstream in(path_, std::ios::binary);
    if (!in || !in.seekg(std::streamoff(offset))) input_error("{}: cannot be read", path_);
    return in;
  }
  [[nodiscard]] std::string read_prefix(uint64_t bytes) const {
    std::string text(size_t(bytes), '\0');
    std::ifstream in = open_at(0);
    if (!in.read(text.data(), std::streamsize(bytes))) input_error("{}: cannot be read", path_);
    return text;
  }

  // What the fixed-size records need, each refusal one line naming the file.
  void check_streamable() {
    if (header_.elements.empty() || header_.elements.front().name != "vertex")
      input_error("{}: the vertex element must come first to be streamed", path_);
    record_ = 0;
    for (const PlyProperty& p : vertex().properties) {
      if (p.is_list) input_error("{}: vertex property '{}' is a list: not streamed", path_, p.name);
      offsets_.push_back(record_);
      record_ += type_size(p.type);
    }
    layout_ = vertex_layout(vertex(), path_);
    if (layout_.nx < 0) input_error("{}: has no normals: only clouds with normals stream", path_);
    if (layout_.gaussian()) input_error("{}: Gaussian particles are not streamed", path_);
    if (!ascii() &&
        (record_ == 0 || vertex().count > (file_bytes_ - header_.data_offset) / record_))
      input_error(
          "{}: truncated: the header promises {} 'vertex' elements but the file is too short for "
          "them",
          path_, vertex().count);
  }

  [[nodiscard]] RecordField record_field(const char* record) const {
    return {record, offsets_, vertex(), swap_};
  }
  static ValuesField values_field(const std::vector<double>& values) { return {values}; }
  template <class Field>
  [[nodiscard]] Vec3d world(const Field& field) const {
    return {field(layout_.x), field(layout_.y), field(layout_.z)};
  }
  [[nodiscard]] Vec3d first_position() const {
    if (ascii()) {
      std::vector<double> values(vertex().properties.size());
      bool found = false;
      for_each_line_block(path_, header_.data_offset, header_.header_lines,
                          [&](std::string_view text, size_t lines_before) {
                            TextScanner scan(text, path_, lines_before);
                            if ((found = scan.next_line(false))) line_values(scan, 0, values);
                            return !found;
                          });
      if (!found)
        input_error("{}: truncated: file ends at 'vertex' element 0 of {}", path_, size());
      return world(values_field(values));
    }
    std::string b(record_, '\0');
    std::ifstream in = open_at(header_.data_offset);
    in.read(b.data(), std::streamsize(record_));
    return world(record_field(b.data()));
  }
  // Vertex `index`'s position (relative to the origin) and unit normal, checked as read_ply does.
  template <class Field>
  void decode(const Field& field, uint64_t index, Vec3& position, Vec3& normal) const {
    const Vec3d w = world(field);
    if (!within_coordinate_range(w))
      input_error("{}: vertex {} has a coordinate that is not finite or beyond +-{:g}", path_,
                  index, kMaxCoordinate);
    position = to_local(w, frame_.origin);
    normal = Vec3(float(field(layout_.nx)), float(field(layout_.ny)), float(field(layout_.nz)));
    if (!to_unit_normal(normal))
      input_error("{}: vertex {} has a zero or non-finite normal", path_, index);
  }

  std::string path_;
  uint64_t file_bytes_ = 0;
  PlyHeader header_;
  VertexLayout layout_;
  std::vector<size_t> offsets_;  // of each vertex property in a record
  size_t record_ = 0;
  bool swap_ = false;
  LocalFrame frame_;
};

}  // namespace

std::unique_ptr<PointStream> open_ply_stream(const std::string& path) {
  return std::make_unique<PlyStream>(path);
}

}  // namespace pcrt
