#include "harness/scene_file.hpp"

#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "core/error.hpp"
#include "core/json_input.hpp"
#include "reconstruction/mesh_surface.hpp"
#include "render/mesh_truth.hpp"
#include "render/scene.hpp"

namespace pcrt {
namespace {

using nlohmann::json;

constexpr float kBig = 1e30f;

// Where a value sits, for errors: "scene.json: objects[1].transform.scale".
struct Where {
  const std::string& file;
  std::string key;
  [[nodiscard]] Where operator/(const std::string& k) const {
    return {file, key.empty() ? k : key + "." + k};
  }
  [[nodiscard]] Where at(size_t i) const { return {file, fmt::format("{}[{}]", key, i)}; }
  [[noreturn]] void fail(const std::string& what) const {
    input_error("{}: {} {}", file, key.empty() ? std::string("scene") : key, what);
  }
};

void only_keys(const json& j, const Where& w, std::initializer_list<const char*> keys) {
  if (!j.is_object()) w.fail("must be an object");
  const std::set<std::string> known(keys.begin(), keys.end());
  for (const auto& [k, v] : j.items())
    if (!known.count(k))
      (w / k).fail(fmt::format("is not a key here (known: {})", fmt::join(known, ", ")));
}

double number_in_double(const json& j, const Where& w, double lo, double hi) {
  if (!j.is_number()) w.fail("must be a number");
  const double v = j.get<double>();
  if (!std::isfinite(v) || v < lo || v > hi)
    w.fail(fmt::format("must lie in [{:g}, {:g}]", lo, hi));
  return v;
}

float number(const json& j, const Where& w, float lo, float hi) {
  return float(number_in_double(j, w, lo, hi));
}

// A position in the scene file's coordinates, in double: georeferenced scenes need it.
double coordinate(const json& j, const Where& w) {
  return number_in_double(j, w, -double(kMaxCoordinate), double(kMaxCoordinate));
}

Vec3d position_in_file(const json& j, const Where& w) {
  if (j.is_number()) return Vec3d::Constant(coordinate(j, w));
  if (!j.is_array() || j.size() != 3) w.fail("must be a number or an array of 3 numbers");
  return Vec3d(coordinate(j[0], w.at(0)), coordinate(j[1], w.at(1)), coordinate(j[2], w.at(2)));
}

// The same relative to the scene's origin (SceneFile::origin), as the renderer takes it.
Vec3 position(const json& j, const Where& w, const Vec3d& origin) {
  return to_local(position_in_file(j, w), origin);
}

// A vector of three numbers, or one number for all three.
Vec3 vec3(const json& j, const Where& w, float lo, float hi) {
  if (j.is_number()) return Vec3::Constant(number(j, w, lo, hi));
  if (!j.is_array() || j.size() != 3) w.fail("must be a number or an array of 3 numbers");
  return Vec3(number(j[0], w.at(0), lo, hi), number(j[1], w.at(1), lo, hi),
              number(j[2], w.at(2), lo, hi));
}

// A direction: a number or three, not all zero, normalised in double (in float a component of
// 1e20 squares to infinity).
Vec3 direction(const json& j, const Where& w) {
  Vec3d v;
  if (j.is_number()) {
    v = Vec3d::Constant(number_in_double(j, w, -kBig, kBig));
  } else {
    if (!j.is_array() || j.size() != 3) w.fail("must be a number or an array of 3 numbers");
    for (int a = 0; a < 3; ++a) v[a] = number_in_double(j[size_t(a)], w.at(size_t(a)), -kBig, kBig);
  }
  if (!(v.norm() > 0)) w.fail("must not be zero");
  return v.normalized().cast<float>();
}

std::string text(const json& j, const Where& w) {
  if (!j.is_string() || j.get<std::string>().empty()) w.fail("must be a non-empty string");
  return j.get<std::string>();
}

// What `make` throws for a value of the file (an unknown method or material, an unreadable
// cloud), prefixed with the file and the key unless it names the file already.
template <typename Make>
auto named(const Where& w, Make make) {
  try {
    return make();
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (what.find(w.file) != std::string::npos) throw;
    w.fail(fmt::format("({})", what));
  }
}

Material parse_material(const json& j, const Where& w) {
  only_keys(j, w,
            {"type", "albedo", "eta", "roughness", "conductor_eta", "conductor_k", "emission"});
  Material m;
  if (!j.contains("type")) w.fail("needs a \"type\"");
  m.kind = named(w / "type", [&] { return material_kind(text(j["type"], w / "type")); });
  if (j.contains("albedo")) m.albedo = vec3(j["albedo"], w / "albedo", 0, 1);
  if (j.contains("eta")) m.eta = number(j["eta"], w / "eta", 1e-2f, 100);
  if (j.contains("roughness")) m.alpha = number(j["roughness"], w / "roughness", 1e-3f, 1);
  if (j.contains("conductor_eta"))
    m.conductor_eta = vec3(j["conductor_eta"], w / "conductor_eta", 1e-3f, 100);
  if (j.contains("conductor_k")) m.conductor_k = vec3(j["conductor_k"], w / "conductor_k", 0, 100);
  if (j.contains("emission")) m.emission = vec3(j["emission"], w / "emission", 0, kBig);
  return m;
}

Transform parse_transform(const json& j, const Where& w) {
  only_keys(j, w, {"translate", "scale", "rotate"});
  Transform t;
  if (j.contains("translate"))
    t.translate = vec3(j["translate"], w / "translate", -kMaxCoordinate, kMaxCoordinate);
  if (j.contains("scale")) t.scale = number(j["scale"], w / "scale", 1e-6f, 1e6f);
  if (j.contains("rotate")) {
    const Where r = w / "rotate";
    only_keys(j["rotate"], r, {"axis", "degrees"});
    if (!j["rotate"].contains("axis") || !j["rotate"].contains("degrees"))
      r.fail("needs \"axis\" and \"degrees\"");
    const Vec3 axis = direction(j["rotate"]["axis"], r / "axis");
    const float deg = number(j["rotate"]["degrees"], r / "degrees", -360, 360);
    t.rotate = Eigen::AngleAxisf(deg * kPi / 180.0f, axis.normalized()).toRotationMatrix();
  }
  return t;
}

Light parse_light(const json& j, const Where& w, const std::filesystem::path& dir,
                  const Vec3d& origin, std::vector<std::string>& files) {
  only_keys(j, w, {"type", "position", "intensity", "radius", "radiance", "file", "sampled"});
  if (!j.contains("type")) w.fail("needs a \"type\"");
  const std::string type = text(j["type"], w / "type");
  Light l;
  auto need = [&](const char* key) -> const json& {
    if (!j.contains(key)) w.fail(fmt::format("({}) needs \"{}\"", type, key));
    return j[key];
  };
  if (type == "point") {
    l.position = position(need("position"), w / "position", origin);
    l.power = vec3(need("intensity"), w / "intensity", 0, kBig);
  } else if (type == "sphere") {
    l.kind = LightKind::kSphere;
    l.position = position(need("position"), w / "position", origin);
    // Within the coordinate range: a radius past about 1.8e19 squares to infinity in float, and
    // the light's sampling and pdf square it (and distances as large).
    l.radius = number(need("radius"), w / "radius", 1e-9f, kMaxCoordinate);
    l.power = vec3(need("radiance"), w / "radiance", 0, kBig);
  } else if (type == "environment") {
    l.kind = LightKind::kEnvironment;
    l.power = j.contains("radiance") ? vec3(j["radiance"], w / "radiance", 0, kBig) : Vec3::Ones();
    if (j.contains("file")) {
      files.push_back((dir / text(j["file"], w / "file")).string());
      l.map = EnvironmentMap::load(files.back());
    }
  } else if (type == "sky") {
    l.kind = LightKind::kSky;
  } else {
    (w / "type")
        .fail(fmt::format("'{}' is not a light (known: point, sphere, environment, sky)", type));
  }
  if (j.contains("sampled")) {
    if (!j["sampled"].is_boolean()) (w / "sampled").fail("must be true or false");
    if (l.kind == LightKind::kPoint) (w / "sampled").fail("does not apply to a point light");
    l.sampled = j["sampled"].get<bool>();
  }
  return l;
}

CameraSpec parse_camera(const json& j, const Where& w, const Vec3d& origin) {
  only_keys(j, w, {"eye", "target", "up", "fov"});
  if (!j.contains("eye") || !j.contains("target")) w.fail("needs \"eye\" and \"target\"");
  CameraSpec c;
  c.eye = position(j["eye"], w / "eye", origin);
  c.target = position(j["target"], w / "target", origin);
  if (j.contains("up")) c.up = direction(j["up"], w / "up");
  if (j.contains("fov")) c.fov_degrees = number(j["fov"], w / "fov", 1, 170);
  if (!((c.target - c.eye).norm() > 0)) w.fail("eye and target must differ");
  if ((c.target - c.eye).cross(c.up).norm() <= 1e-6f * (c.target - c.eye).norm() * c.up.norm())
    w.fail("up must not be parallel to the view direction");
  return c;
}

// A path in a scene file is relative to the file's folder; a generator spec is not a path.
std::string resolve(const std::string& value, const std::filesystem::path& dir) {
  const std::filesystem::path p = dir / value;
  std::error_code ec;
  return std::filesystem::exists(p, ec) ? p.string() : value;
}

ParamValues parse_set(const json& j, const Where& w) {
  if (!j.is_object()) w.fail("must be an object of name: number");
  ParamValues set;
  for (const auto& [k, v] : j.items()) set[k] = number(v, w / k, -kBig, kBig);
  return set;
}

// Points sampled on a mesh (outward normals by default): what `pcrt accuracy --truth` traces.
Dataset sampled_dataset(const json& j, const Where& w, const std::string& mesh_file,
                        OpCounters& counters) {
  const MeshSampling sampling = parse_mesh_sampling(
      j.contains("sampling") ? text(j["sampling"], w / "sampling") : std::string());
  auto truth = std::make_shared<MeshSurface>(read_mesh(mesh_file), mesh_file, "bvh");
  SampledCloud sampled = sample_cloud(*truth, sampling, mesh_file, counters);
  return Dataset{std::move(sampled.cloud), truth};
}

bool is_swept(const json& j, const Where& w) {
  if (!j.contains("swept")) return false;
  if (!j["swept"].is_boolean()) (w / "swept").fail("must be true or false");
  if (!j.contains("points") && !j.contains("sample"))
    (w / "swept").fail("applies only to point clouds");
  return j["swept"].get<bool>();
}

// A swept object: the run's method on the run's cloud, one structure for every swept object.
void add_swept_geometry(SceneFile& s, const SweptCloud& run, SceneObject& o, json& record) {
  if (!s.swept) {
    s.geometry.push_back(
        std::make_unique<PointScene>(run.cloud, run.options, s.prepare, s.timings));
    s.swept = static_cast<const PointScene*>(s.geometry.back().get());
  }
  record = {{"swept", true},
            {"method", run.options.method},
            {"structure", s.swept->structure_id()},
            {"N", run.cloud.size()}};
  o.geometry = s.swept;
  o.points = &run.cloud;
  o.bounds = run.cloud.bounds();
}

// An object's geometry: a point method over a dataset, a mesh file on an engine, or the quad.
void add_geometry(SceneFile& s, const json& j, const Where& w, const std::filesystem::path& dir,
                  SceneObject& o, json& record) {
  const int kinds = int(j.contains("points")) + int(j.contains("sample")) +
                    int(j.contains("mesh")) + int(j.contains("quad"));
  if (kinds != 1) w.fail("needs exactly one of \"points\", \"sample\", \"mesh\" or \"quad\"");
  if (j.contains("sampling") && !j.contains("sample"))
    (w / "sampling").fail("applies only to \"sample\"");
  if (j.contains("points") || j.contains("sample")) {
    if (!j.contains("method")) w.fail("(a point cloud) needs \"method\"");
    const std::string data = j.contains("points") ? resolve(text(j["points"], w / "points"), dir)
                                                  : resolve(text(j["sample"], w / "sample"), dir);
    s.files.push_back(data);  // a generator spec too: no file has its name, so it is never one
    s.clouds.push_back(j.contains("points") ? load_dataset(data)
                                            : sampled_dataset(j, w, data, s.prepare));
    const PointCloud& cloud = s.clouds.back().cloud;
    SceneOptions so{text(j["method"], w / "method"),
                    j.contains("structure") ? text(j["structure"], w / "structure") : "",
                    j.contains("set") ? parse_set(j["set"], w / "set") : ParamValues{}};
    auto scene = std::make_unique<PointScene>(cloud, so, s.prepare, s.timings);
    record = {{j.contains("points") ? "points" : "sample", data},
              {"method", so.method},
              {"structure", scene->structure_id()},
              {"N", cloud.size()}};
    o.points = &cloud;
    o.bounds = cloud.bounds();
    s.geometry.push_back(std::move(scene));
    o.geometry = s.geometry.back().get();
    return;
  }
  if (j.contains("mesh")) {
    const std::string file = resolve(text(j["mesh"], w / "mesh"), dir);
    s.files.push_back(file);
    s.meshes.push_back(read_mesh(file));
    orient_outward(s.meshes.back());  // dielectrics tell inside from outside by the normal
    record = {{"mesh", file}};
  } else {
    only_keys(j["quad"], w / "quad", {"size"});
    if (!j["quad"].contains("size")) (w / "quad").fail("needs \"size\"");
    s.meshes.push_back(quad_mesh(number(j["quad"]["size"], w / "quad" / "size", 1e-6f, kBig)));
    record = {{"quad", j["quad"]["size"]}};
  }
  const std::string engine = j.contains("engine") ? text(j["engine"], w / "engine") : "bvh";
  record["engine"] = engine;
  record["triangles"] = s.meshes.back().triangles.size();
  o.bounds = s.meshes.back().bounds();
  s.geometry.push_back(std::make_unique<MeshScene>(s.meshes.back(), engine, s.prepare, s.timings));
  o.geometry = s.geometry.back().get();
}

// What placing an object in the scene's frame needs once every object is loaded: where its
// geometry's zero lies in the file's coordinates, its translation there, its own bounds.
struct Placement {
  Vec3d origin = Vec3d::Zero();
  Vec3d translate = Vec3d::Zero();
  Aabb bounds;
};

void add_object(SceneFile& s, const json& j, const Where& w, const std::filesystem::path& dir,
                const std::map<std::string, Material>& materials, const SweptCloud* swept,
                Placement& placement) {
  only_keys(j, w,
            {"name", "points", "sample", "sampling", "method", "structure", "set", "mesh", "engine",
             "quad", "material", "transform", "swept"});
  const bool cloud = j.contains("points") || j.contains("sample");
  if (!cloud)
    for (const char* key : {"method", "structure", "set"})
      if (j.contains(key)) (w / key).fail("applies only to point clouds");
  if (j.contains("engine") && cloud) (w / "engine").fail("applies only to meshes");
  SceneObject o;
  json record;
  if (is_swept(j, w) && swept)
    add_swept_geometry(s, *swept, o, record);
  else
    add_geometry(s, j, w, dir, o, record);
  if (j.contains("material")) {
    const std::string name = text(j["material"], w / "material");
    const auto it = materials.find(name);
    if (it == materials.end())
      (w / "material").fail(fmt::format("'{}' is not in \"materials\"", name));
    o.material = it->second;
    record["material"] = name;
  }
  placement.origin = o.points ? o.points->origin : s.meshes.back().origin;
  placement.bounds = o.bounds;
  if (j.contains("transform")) {
    o.transform = parse_transform(j["transform"], w / "transform");
    if (j["transform"].contains("translate"))  // checked by parse_transform; again in double
      placement.translate =
          position_in_file(j["transform"]["translate"], w / "transform" / "translate");
  }
  o.name = j.contains("name") ? text(j["name"], w / "name") : w.key;
  record["name"] = o.name;
  s.params["objects"].push_back(record);
  s.scene.objects.push_back(o);
}

// Every object in the frame of the first one read in a local frame (kLocalOriginReach), or of
// the file's own coordinates when none is: objects apart by less than their float range meet.
void place_objects(SceneFile& s, const std::vector<Placement>& placements) {
  for (const Placement& p : placements)
    if (!p.origin.isZero()) {
      s.origin = p.origin;
      break;
    }
  if (!s.origin.isZero()) s.params["origin"] = {s.origin.x(), s.origin.y(), s.origin.z()};
  for (size_t i = 0; i < placements.size(); ++i) {
    SceneObject& o = s.scene.objects[i];
    Transform& t = o.transform;
    const Placement& p = placements[i];
    const Vec3d shift =
        double(t.scale) * (t.rotate.cast<double>() * p.origin) + p.translate - s.origin;
    t.translate = shift.cast<float>();
    o.bounds = t.to_world(p.bounds);
  }
}

// Every ray a frame of the scene traces starts within reach of it: inside the box of its objects
// and camera, or of a camera framing the objects (Camera::framing: 3.5 bounding radii out),
// or within --ray-epsilon (at most kMaxCoordinate) of a surface. An object's transform takes the
// rays into its own frame, where a scale of 1e-6 makes 1e12 into 1e18, near where Embree aborts
// (about 1.8e18): so that reach must lie within kMaxCoordinate of every moved object's zero, in
// the object's frame, as a ray origin in a file must.
void check_object_frames(const SceneFile& s, const Where& objects) {
  const Aabb box = s.scene.bounds();
  if (box.empty()) return;
  Aabb reach = box;
  const Vec3 margin = Vec3::Constant(4.0f * box.diagonal());
  reach.extend(box.center() + margin), reach.extend(box.center() - margin);
  if (s.camera) reach.extend(s.camera->eye), reach.extend(s.camera->target);
  for (size_t i = 0; i < s.scene.objects.size(); ++i) {
    const Transform& t = s.scene.objects[i].transform;
    if (t.identity()) continue;
    const Eigen::Matrix3d to_object = t.rotate.cast<double>().transpose() / double(t.scale);
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3d c((corner & 1) ? reach.hi.x() : reach.lo.x(),
                    (corner & 2) ? reach.hi.y() : reach.lo.y(),
                    (corner & 4) ? reach.hi.z() : reach.lo.z());
      if (!within_coordinate_range(Vec3d(to_object * (c - t.translate.cast<double>()))))
        (objects.at(i) / "transform")
            .fail(fmt::format("puts the scene's rays beyond +-{:g} in the object's own frame "
                              "(its scale is too small for the scene's extent)",
                              kMaxCoordinate));
    }
  }
}

}  // namespace

TriangleMesh quad_mesh(float size) {
  const float h = 0.5f * size;
  TriangleMesh m;
  m.vertices = {Vec3(-h, -h, 0), Vec3(h, -h, 0), Vec3(h, h, 0), Vec3(-h, h, 0)};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

std::unique_ptr<SceneFile> load_scene_file(const std::string& path, const SweptCloud* swept) {
  const json j = read_json_file(path);
  const Where root{path, ""};
  only_keys(j, root, {"materials", "objects", "lights", "camera"});
  const std::filesystem::path dir = std::filesystem::path(path).parent_path();
  std::map<std::string, Material> materials;
  if (j.contains("materials")) {
    if (!j["materials"].is_object())
      (root / "materials").fail("must be an object of name: material");
    for (const auto& [name, m] : j["materials"].items())
      materials[name] = parse_material(m, Where{path, "materials." + name});
  }
  auto s = std::make_unique<SceneFile>();
  s->params = {{"scene", path}, {"objects", json::array()}};
  const Where objects{path, "objects"};
  if (!j.contains("objects") || !j["objects"].is_array() || j["objects"].empty())
    objects.fail("must be a non-empty array");
  std::vector<Placement> placements(j["objects"].size());
  for (size_t i = 0; i < j["objects"].size(); ++i)
    named(objects.at(i), [&] {
      add_object(*s, j["objects"][i], objects.at(i), dir, materials, swept, placements[i]);
    });
  place_objects(*s, placements);
  if (swept && !s->swept) objects.fail("mark no point cloud \"swept\": true, as a sweep needs");
  const Where lights{path, "lights"};
  if (!j.contains("lights") || !j["lights"].is_array() || j["lights"].empty())
    lights.fail("must be a non-empty array");
  for (size_t i = 0; i < j["lights"].size(); ++i)
    s->scene.lights.push_back(parse_light(j["lights"][i], lights.at(i), dir, s->origin, s->files));
  if (j.contains("camera")) s->camera = parse_camera(j["camera"], root / "camera", s->origin);
  check_object_frames(*s, objects);
  return s;
}

void apply_scene_camera(const SceneFile& file, RenderSettings& settings) {
  if (!file.camera) return;
  const CameraSpec& c = *file.camera;
  settings.camera = Camera(c.eye, c.target, c.up, c.fov_degrees, settings.width, settings.height);
}

void check_sweep_scene(const std::string& path) {
  const json j = read_json_file(path);
  const Where objects{path, "objects"};
  if (!j.is_object()) Where{path, ""}.fail("must be a JSON object");
  if (!j.contains("objects") || !j["objects"].is_array()) objects.fail("must be an array");
  for (size_t i = 0; i < j["objects"].size(); ++i)
    if (j["objects"][i].is_object() && is_swept(j["objects"][i], objects.at(i))) return;
  objects.fail("mark no point cloud \"swept\": true, as a sweep needs");
}

}  // namespace pcrt
