// The Python module `pcrt._pcrt` (re-exported by the package `pcrt`): clouds with numpy views,
// scenes of any method on any structure, closest hits of numpy rays and rendered frames as numpy
// arrays, the method registry. The same library code the CLI runs: a Scene is a PointScene,
// Scene.trace is trace_rays (what `pcrt trace` runs), Scene.render is the renderer.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <exception>
#include <future>
#include <memory>
#include <optional>

#include "core/dataset.hpp"
#include "core/error.hpp"
#include "core/exr_output.hpp"
#include "core/memory_budget.hpp"
#include "core/ray_io.hpp"
#include "harness/catalogue.hpp"
#include "methods/method.hpp"
#include "render/renderer.hpp"
#include "render/scene.hpp"

namespace py = pybind11;
using namespace pcrt;

namespace {

// Float rows in the caller's own layout: a strided or broadcast float32 array is read in place,
// never copied into a contiguous one first.
using FloatRows = py::array_t<float, py::array::forcecast>;

// A read-only numpy view of `count` rows of `columns` values of T starting at `data`, kept alive
// by `owner` (the Python object holding the cloud): no copy.
template <typename T>
py::array view(const T* data, size_t count, size_t columns, size_t row_bytes, py::handle owner) {
  std::vector<py::ssize_t> shape{py::ssize_t(count)}, strides{py::ssize_t(row_bytes)};
  if (columns > 1) {
    shape.push_back(py::ssize_t(columns));
    strides.push_back(py::ssize_t(sizeof(T)));
  }
  py::array a(py::dtype::of<T>(), shape, strides, data, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

// Raises MemoryError (as pybind11 does for std::bad_alloc) saying what did not fit.
[[noreturn]] void memory_error(const std::string& what) {
  PyErr_SetString(PyExc_MemoryError, what.c_str());
  throw py::error_already_set();
}

// (n, 3) float rows of a numpy argument, or an error naming the argument: the shape is checked
// before any conversion, so that a conversion that does not fit is reported as memory, not shape.
FloatRows rows3(const py::handle& obj, const char* name) {
  if (py::isinstance<py::array>(obj)) {
    const auto given = py::reinterpret_borrow<py::array>(obj);
    if (given.ndim() != 2 || given.shape(1) != 3)
      input_error("{}: expected an array of shape (n, 3), got shape {}", name,
                  py::str(obj.attr("shape")).cast<std::string>());
    // Numbers only: numpy would cast complex to real and refuses text and objects as memory.
    const char kind = given.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u' && kind != 'b')
      input_error("{}: an array of {} values, not numbers", name,
                  py::str(given.dtype()).cast<std::string>());
  }
  FloatRows a = FloatRows::ensure(obj);
  if (!a && py::isinstance<py::array>(obj))
    memory_error(fmt::format("{}: {} rows do not fit in memory as float32", name,
                             py::reinterpret_borrow<py::array>(obj).shape(0)));
  if (!a || a.ndim() != 2 || a.shape(1) != 3)
    input_error("{}: expected an array of shape (n, 3)", name);
  return a;
}

// Text arguments end at a NUL in every C++ message: one is refused, with the text escaped.
const std::string& text_arg(const std::string& text, const char* name) {
  const size_t nul = text.find('\0');
  if (nul != std::string::npos) {
    std::string shown = text;
    shown.replace(nul, 1, "\\x00");
    input_error("{}: contains a NUL byte at position {}: '{}'", name, nul, shown);
  }
  return text;
}

// Runs `work` (GIL released) on a thread of its own while the caller's thread looks for Ctrl-C
// every 50 ms: on a signal, `stop` is set, the work's loops leave within a ray or a pixel (a
// frame first traces the shadow rays of the samples it has drawn, at most 1024), and the
// signal's exception (KeyboardInterrupt) is raised here once the work has returned.
template <typename Work>
void interruptible(Work&& work) {
  std::atomic<bool> stop{false};
  bool interrupted = false;
  {
    py::gil_scoped_release unlocked;
    std::future<void> done = std::async(std::launch::async, [&] { work(stop); });
    while (done.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
      py::gil_scoped_acquire locked;
      if (!interrupted && PyErr_CheckSignals() != 0) interrupted = true, stop = true;
    }
    if (!interrupted) {
      done.get();  // the work's own exception, if any
    } else {
      try {
        done.get();
      } catch (...) {  // abandoned work: the interrupt is what the caller sees
      }
    }
  }
  if (interrupted) throw py::error_already_set();
}

std::vector<Vec3> to_vec3(const FloatRows& a) {
  std::vector<Vec3> out(size_t(a.shape(0)));
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i) out[size_t(i)] = Vec3(r(i, 0), r(i, 1), r(i, 2));
  return out;
}

py::dict counters_dict(const OpCounters& c) {
  py::dict d;
  for (const auto& [name, value] : c.to_map()) d[py::str(name)] = value;
  return d;
}

// The threads of one call: an arena of its own, so that concurrent calls with different counts
// neither throttle each other nor the rest of the process (a global_control would).
void check_threads(int threads) {
  if (threads < 0 || threads > FrameLimits::kMaxThreads)
    input_error("threads = {} is impossible (0: all cores, at most {})", threads,
                FrameLimits::kMaxThreads);
}

template <typename F>
void in_arena(int threads, F&& f) {
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute(f);
}

// The command line's ranges (FrameLimits), so that no frame runs for hours by a typo.
void check_frame(int width, int height, int spp, int bounces) {
  const int side = FrameLimits::kMaxSide;
  if (width < 1 || height < 1 || width > side || height > side)
    input_error("width {} x height {}: each must lie in [1, {}]", width, height, side);
  if (spp < 1 || spp > FrameLimits::kMaxSpp)
    input_error("spp = {}: must lie in [1, {}]", spp, FrameLimits::kMaxSpp);
  if (bounces < 0 || bounces > FrameLimits::kMaxBounces)
    input_error("bounces = {}: must lie in [0, {}]", bounces, FrameLimits::kMaxBounces);
}

std::shared_ptr<PointCloud> cloud_from_arrays(const py::handle& positions,
                                              const py::object& normals, const py::object& radii,
                                              const std::string& name) {
  auto c = std::make_shared<PointCloud>();
  c->name = text_arg(name, "name");
  c->positions = to_vec3(rows3(positions, "positions"));
  if (!normals.is_none()) c->normals = to_vec3(rows3(normals, "normals"));
  if (!radii.is_none()) {
    auto r = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(radii);
    if (!r || r.ndim() != 1) input_error("radii: expected an array of shape (n,)");
    c->radii.assign(r.data(), r.data() + r.shape(0));
  }
  // An empty array given is not "none given" (which the cloud's empty vectors would say).
  for (const auto& [given, rows, what] :
       {std::tuple{!normals.is_none(), c->normals.size(), "normals"},
        std::tuple{!radii.is_none(), c->radii.size(), "radii"}})
    if (given && rows != c->positions.size())
      input_error("{}: {} rows for {} points", what, rows, c->positions.size());
  c->validate();
  // As a loaded file's: exact duplicates would make every neighbour search among them quadratic.
  if (const size_t dropped = c->remove_duplicates())
    note("pcrt: {}: dropped {} exact duplicate points ({} remain)", c->name, dropped, c->size());
  return c;
}

// A method on a structure over a cloud it keeps alive; the counters of its preparation and of
// its last trace or render.
class Scene {
 public:
  Scene(std::shared_ptr<const PointCloud> cloud, const std::string& method,
        const std::string& structure, const py::kwargs& params)
      : cloud_(std::move(cloud)) {
    if (!cloud_) input_error("Scene: cloud is None (give a cloud from pcrt.load or from_arrays)");
    SceneOptions options{
        text_arg(method, "method"), text_arg(structure, "structure"), {}, "Scene keyword"};
    for (const auto& [k, v] : params) {
      const std::string name = text_arg(py::cast<std::string>(k), "parameter name");
      try {
        options.set[name] = py::cast<double>(v);
      } catch (const py::cast_error&) {
        input_error("parameter {}: expected a number, got {}", name,
                    py::str(v).cast<std::string>());
      }
    }
    py::gil_scoped_release unlocked;
    scene_ = std::make_unique<PointScene>(*cloud_, options, prepare_, timings_);
  }

  py::dict trace(const py::handle& origins, const py::handle& directions, int threads) {
    const FloatRows o = rows3(origins, "origins"), d = rows3(directions, "directions");
    if (o.shape(0) != d.shape(0))
      input_error("origins has {} rows but directions {}", o.shape(0), d.shape(0));
    const size_t n = size_t(o.shape(0));
    // The rays, their hits and the five result arrays, before any of them is allocated.
    require_memory(n * (sizeof(Ray) + sizeof(Hit) + 1 + 37), fmt::format("a trace of {} rays", n));
    std::vector<Ray> rays(n);
    auto ro = o.unchecked<2>(), rd = d.unchecked<2>();
    for (size_t i = 0; i < n; ++i) {
      // Ctrl-C during the checks of millions of rows too (the GIL is held here).
      if (i % 65536 == 0 && PyErr_CheckSignals() != 0) throw py::error_already_set();
      const Vec3 origin(ro(i, 0), ro(i, 1), ro(i, 2)), direction(rd(i, 0), rd(i, 1), rd(i, 2));
      if (const char* why = user_ray_problem(origin, direction)) input_error("ray {}: {}", i, why);
      rays[i] = user_ray(origin, direction);
    }
    check_threads(threads);
    std::vector<Hit> hits(n);
    std::vector<char> found(n, 0);
    interruptible([&](const std::atomic<bool>& stop) {
      in_arena(threads, [&] { last_ = trace_in_chunks(rays, hits, found, stop); });
    });
    py::array_t<bool> hit{py::ssize_t(n)};
    py::array_t<float> t{py::ssize_t(n)};
    py::array_t<float> position({py::ssize_t(n), py::ssize_t(3)});
    py::array_t<float> normal({py::ssize_t(n), py::ssize_t(3)});
    py::array_t<int64_t> primitive{py::ssize_t(n)};
    auto h = hit.mutable_unchecked<1>();
    auto tt = t.mutable_unchecked<1>();
    auto p = position.mutable_unchecked<2>(), nn = normal.mutable_unchecked<2>();
    auto pr = primitive.mutable_unchecked<1>();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (size_t i = 0; i < n; ++i) {
      const auto j = py::ssize_t(i);
      h(j) = found[i] != 0;
      tt(j) = found[i] ? hits[i].t : kInfinity;
      pr(j) = found[i] ? int64_t(hits[i].prim) : -1;
      for (py::ssize_t k = 0; k < 3; ++k) {
        p(j, k) = found[i] ? hits[i].p[k] : nan;
        nn(j, k) = found[i] ? hits[i].n[k] : nan;
      }
    }
    py::dict out;
    out["hit"] = hit;
    out["t"] = t;
    out["position"] = position;
    out["normal"] = normal;
    out["primitive"] = primitive;
    return out;
  }

  // Chunks of kChunk rays, `stop` looked at between them; counters are sums over rays, so the
  // chunks change none of them.
  OpCounters trace_in_chunks(std::span<const Ray> rays, std::span<Hit> hits, std::span<char> found,
                             const std::atomic<bool>& stop) const {
    constexpr size_t kChunk = 1024;
    OpCounters total;
    for (size_t begin = 0; begin < rays.size() && !stop; begin += kChunk) {
      const size_t count = std::min(kChunk, rays.size() - begin);
      total.merge(trace_rays(*scene_, rays.subspan(begin, count), hits.subspan(begin, count),
                             found.subspan(begin, count)));
    }
    return total;
  }

  py::array render(int width, int height, int spp, int bounces, uint64_t seed, bool point_light,
                   int threads) {
    RenderSettings rs;
    rs.width = width;
    rs.height = height;
    rs.spp = spp;
    rs.bounces = bounces;
    rs.seed = seed;
    rs.point_light = point_light;
    rs.threads = threads;
    check_frame(width, height, spp, bounces);
    check_threads(threads);
    // The frame's three images, depth and normals, and the array returned.
    require_memory(size_t(width) * size_t(height) * (4 * sizeof(Vec3) + sizeof(float) + 12),
                   fmt::format("a frame of {} x {} pixels", width, height));
    std::optional<RenderResult> r;
    // The renderer keeps to rs.threads in an arena of its own.
    interruptible([&](const std::atomic<bool>& stop) {
      rs.stop = &stop;
      r.emplace(pcrt::render(*scene_, *cloud_, rs));
    });
    last_ = r->counters;
    py::array_t<float> image({py::ssize_t(height), py::ssize_t(width), py::ssize_t(3)});
    auto im = image.mutable_unchecked<3>();
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        for (int k = 0; k < 3; ++k) im(y, x, k) = r->image.at(x, y)[k];
    return image;
  }

  [[nodiscard]] py::dict prepare_counters() const { return counters_dict(prepare_); }
  [[nodiscard]] py::dict counters() const { return counters_dict(last_); }
  [[nodiscard]] std::string method() const { return scene_->method_info().id; }
  [[nodiscard]] std::string structure() const { return scene_->structure_id(); }
  [[nodiscard]] size_t structure_bytes() const { return scene_->structure_bytes(); }

 private:
  std::shared_ptr<const PointCloud> cloud_;
  OpCounters prepare_, last_;
  Timings timings_;
  std::unique_ptr<PointScene> scene_;
};

// The registries as `pcrt list --json` has them (harness/catalogue.hpp): the same keys.
py::object catalogue_list(const char* key) {
  return py::module_::import("json").attr("loads")(catalogue_json()[key].dump());
}

py::object methods() { return catalogue_list("methods"); }
py::object structures() { return catalogue_list("structures"); }

// pcrt.Error: an InputError's one-line message as a ValueError.
void bind_errors(py::module_& m) {
  static py::exception<InputError> error(m, "Error", PyExc_ValueError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      error(e.what());
    }
  });
}

// The T a bound member is called on, checked: an object whose __init__ never ran
// (Scene.__new__(Scene), Cloud.__new__(Cloud)) has no C++ object behind it, and pybind11 would
// read garbage through it.
template <class T>
T& held(const py::handle& self, const char* type, const char* make) {
  if (!py::isinstance<T>(self))
    throw py::type_error(fmt::format("{} method called on another type", type));
  auto* inst = reinterpret_cast<py::detail::instance*>(self.ptr());
  const py::detail::value_and_holder vh =
      inst->get_value_and_holder(py::detail::get_type_info(typeid(T)));
  if (!vh.holder_constructed() || !vh.value_ptr())
    throw py::type_error(fmt::format("{} is not initialised: make it with {}", type, make));
  return *vh.value_ptr<T>();
}

const PointCloud& cloud_of(const py::handle& self) {
  return held<PointCloud>(self, "pcrt.Cloud", "pcrt.load(...) or pcrt.from_arrays(...)");
}

// pcrt.Cloud: the cloud's own arrays as read-only numpy views.
void bind_cloud(py::module_& m) {
  py::class_<PointCloud, std::shared_ptr<PointCloud>>(m, "Cloud")
      .def_property_readonly("name", [](py::handle self) { return cloud_of(self).name; })
      .def("__len__", [](py::handle self) { return cloud_of(self).size(); })
      .def_property_readonly(
          "positions",
          [](py::object self) {
            const PointCloud& c = cloud_of(self);
            return view(c.positions.data()->data(), c.size(), 3, sizeof(Vec3), self);
          },
          "(n, 3) float32, read-only, no copy")
      .def_property_readonly(
          "normals",
          [](py::object self) -> py::object {
            const PointCloud& c = cloud_of(self);
            if (!c.has_normals()) return py::none();
            return view(c.normals.data()->data(), c.size(), 3, sizeof(Vec3), self);
          },
          "(n, 3) float32 unit normals, read-only, or None")
      .def_property_readonly(
          "radii",
          [](py::object self) -> py::object {
            const PointCloud& c = cloud_of(self);
            if (!c.has_radii()) return py::none();
            return view(c.radii.data(), c.size(), 1, sizeof(float), self);
          },
          "(n,) float32 splat radii, read-only, or None")
      .def_property_readonly(
          "colours",
          [](py::object self) -> py::object {
            const PointCloud& c = cloud_of(self);
            if (!c.has_colours()) return py::none();
            return view(&c.colours.data()->r, c.size(), 3, sizeof(Rgb8), self);
          },
          "(n, 3) uint8, read-only, or None")
      .def_property_readonly("bounds",
                             [](py::handle self) {
                               const Aabb b = cloud_of(self).bounds();
                               return py::make_tuple(py::make_tuple(b.lo.x(), b.lo.y(), b.lo.z()),
                                                     py::make_tuple(b.hi.x(), b.hi.y(), b.hi.z()));
                             })
      .def_property_readonly(
          "origin",
          [](py::handle self) {
            const Vec3d& o = cloud_of(self).origin;
            return py::make_tuple(o.x(), o.y(), o.z());
          },
          "where positions' zero lies in the file's coordinates (a georeferenced file's local "
          "origin; (0, 0, 0) otherwise): positions, rays and hits are relative to it")
      .def("__repr__", [](py::handle self) {
        const PointCloud& c = cloud_of(self);
        return fmt::format("<pcrt.Cloud {} points from {}>", c.size(), c.name);
      });
}

}  // namespace

namespace {

Scene& initialised(const py::handle& self) {
  return held<Scene>(self, "pcrt.Scene", "pcrt.Scene(cloud, method=...)");
}

template <typename R, typename... A>
auto on_scene(R (Scene::*f)(A...)) {
  return [f](const py::handle& self, A... a) -> R {
    return (initialised(self).*f)(std::forward<A>(a)...);
  };
}
template <typename R, typename... A>
auto on_scene(R (Scene::*f)(A...) const) {
  return [f](const py::handle& self, A... a) -> R {
    return (initialised(self).*f)(std::forward<A>(a)...);
  };
}

// An EXR file's channels as a dict of (height, width) float32 arrays: what `pcrt render` writes
// for .exr names (R, G, B radiance; Z depth; normals as R, G, B).
py::dict read_exr_channels(const std::string& path) {
  text_arg(path, "path");
  ExrImage image;
  {
    py::gil_scoped_release unlocked;
    image = read_exr(path);
  }
  py::dict out;
  for (const FloatChannel& c : image.channels) {
    py::array_t<float> a({image.height, image.width});
    std::copy(c.values.begin(), c.values.end(), a.mutable_data());
    out[py::str(c.name)] = a;
  }
  return out;
}

}  // namespace

PYBIND11_MODULE(_pcrt, m) {
  m.doc() = "pcrt: ray tracing point clouds with the methods of the 2019 survey";
  bind_errors(m);
  bind_cloud(m);

  m.def(
      "load",
      [](const std::string& spec) {
        text_arg(spec, "data");
        py::gil_scoped_release unlocked;
        return std::make_shared<PointCloud>(load_dataset(spec).cloud);
      },
      py::arg("data"), "A file (.ply .xyz .pwn .off) or a generator spec such as 'sphere:n=1e5'");
  m.def("from_arrays", &cloud_from_arrays, py::arg("positions"), py::arg("normals") = py::none(),
        py::arg("radii") = py::none(), py::arg("name") = "arrays",
        "A cloud copied from numpy arrays (validated as a loaded file is; exact duplicate points "
        "dropped as a file's are, so hits index the cloud's own positions)");

  py::class_<Scene>(m, "Scene")
      .def(py::init<std::shared_ptr<const PointCloud>, const std::string&, const std::string&,
                    const py::kwargs&>(),
           py::arg("cloud"), py::arg("method"), py::arg("structure") = "",
           "A method on a structure (default: its paper's) over a cloud; keyword arguments set "
           "method or structure parameters")
      .def("trace", on_scene(&Scene::trace), py::arg("origins"), py::arg("directions"),
           py::arg("threads") = 0,
           "Closest hits: a dict of numpy arrays hit, t, position, normal, primitive (-1: none)")
      .def("render", on_scene(&Scene::render), py::arg("width") = 512, py::arg("height") = 512,
           py::arg("spp") = 1, py::arg("bounces") = 1, py::arg("seed") = 1,
           py::arg("point_light") = true, py::arg("threads") = 0,
           "A frame as an (height, width, 3) float32 array of linear radiance")
      .def_property_readonly("method", on_scene(&Scene::method))
      .def_property_readonly("structure", on_scene(&Scene::structure))
      .def_property_readonly("structure_bytes", on_scene(&Scene::structure_bytes))
      .def_property_readonly("prepare_counters", on_scene(&Scene::prepare_counters))
      .def_property_readonly("counters", on_scene(&Scene::counters),
                             "operation counters of the last trace or render");

  m.def("read_exr", &read_exr_channels, py::arg("path"),
        "An EXR file's channels: a dict of name -> (height, width) float32 array");
  m.def("methods", &methods, "every method with its parameters and the thesis's claims");
  m.def("structures", &structures, "every structure with its parameters and claims");
}
