// The second seam, T_int: a Method prepares what its paper needs from the cloud and intersects a
// ray with one leaf's points. Each surveyed method lives in its own folder under methods/ and
// registers a MethodInfo from a static object (see methods/reference_splat/).
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/camera.hpp"
#include "core/counters.hpp"
#include "core/params.hpp"
#include "core/point_cloud.hpp"
#include "core/point_stream.hpp"
#include "core/registry.hpp"
#include "structures/structure.hpp"

namespace pcrt {

struct PrepareContext {
  OpCounters& counters;
  Timings& timings;  // phases under "prepare/..."
};

// A method's own way of finding primary hits in place of tracing camera rays (Tejada et al.
// rasterize the points into a z-buffer): made once per frame from the camera, then asked once
// per camera ray. Its work counts into the frame's counters like any other.
class PrimaryPass {
 public:
  virtual ~PrimaryPass() = default;
  // The closest hit of the camera ray through film position (px, py), in pixels.
  virtual bool closest_hit(const Ray& ray, float px, float py, Hit& hit,
                           OpCounters& counters) const = 0;
};

// The mean spacing h that scales a method's radii and tolerances, timed as "prepare/spacing"
// (at least 1e-30, so that h-relative sizes stay positive on degenerate clouds).
float prepare_spacing(const PointCloud& cloud, PrepareContext& ctx);

class Method : public LeafIntersector {
 public:
  // Computes the method's preconditions (normals, radii, splats, ...) from the cloud, which must
  // outlive the method. Counts into ctx.counters and times into ctx.timings.
  virtual void prepare(const PointCloud& cloud, PrepareContext& ctx) = 0;
  // The same from a stream, never holding the whole cloud (core/point_stream.hpp), for the
  // methods and parameters MethodInfo::stream_bytes_per_point names; the scene asks no other.
  virtual void prepare_stream(const PointStream& /*stream*/, PrepareContext& /*ctx*/) {
    throw std::logic_error("prepare_stream called on a method that does not stream");
  }
  // What the structure indexes: a position, bounding radius and (optionally) box per item.
  [[nodiscard]] virtual ItemSet items() const = 0;
  // Called once the structure over items() is built, with its leaf references
  // (Structure::leaf_references), for methods that lay their data out in leaf order.
  virtual void bind_leaf_references(std::span<const uint32_t> /*refs*/) {}
  // The closest hit through the structure built over items(). Methods whose ray walks the
  // structure more than once (3DGRT's k-buffer march re-traces from its last hit) override it;
  // the default is one walk with this method's leaf test.
  virtual bool closest_hit_through(const Structure& structure, const Ray& ray, Hit& hit,
                                   OpCounters& counters) const {
    return structure.closest_hit(ray, *this, hit, counters);
  }
  // The occlusion query through the structure, likewise.
  virtual bool any_hit_through(const Structure& structure, const Ray& ray,
                               OpCounters& counters) const {
    return structure.any_hit(ray, *this, counters);
  }
  // n <= 16 occlusion queries at once, as any_hit_through answers each (Structure::any_hits).
  // A method overriding any_hit_through overrides this too (render/renderer_test.cpp renders
  // every method both ways and requires the same image and counts).
  virtual void any_hits_through(const Structure& structure, const Ray* rays, int n, char* blocked,
                                OpCounters& counters) const {
    structure.any_hits(rays, n, *this, blocked, counters);
  }
  // For methods that trace whole rays through an acceleration of their own (MethodInfo::
  // own_structure, e.g. Embree's BVH): the closest hit, in place of structure + leaf.
  virtual bool own_closest_hit(const Ray& /*ray*/, Hit& /*hit*/, OpCounters& /*counters*/) const {
    return false;
  }
  // The occlusion query of such methods (Embree's rtcOccluded1); this default asks for a hit.
  virtual bool own_any_hit(const Ray& ray, OpCounters& counters) const {
    Hit h;
    h.t = ray.tmax;
    return own_closest_hit(ray, h, counters);
  }
  // Methods with a primary pass of their own return it; nullptr: camera rays are traced.
  [[nodiscard]] virtual std::unique_ptr<PrimaryPass> primary_pass(const Camera& /*camera*/,
                                                                  OpCounters& /*counters*/) const {
    return nullptr;
  }
};

// What kind of surface a method's leaf kernel intersects, so that comparisons pick like with like
// by type, never by matching names (`pcrt anchor` times the splat family against Embree's discs,
// and headlines the methods whose surface is exactly Embree's: one disc per point).
enum class LeafFamily {
  kOther,       // MLS, implicit, triangle fans, ...: a different surface
  kDisc,        // one oriented disc per point (normal, radius), the nearest disc hit wins
  kSplatBlend,  // splats of the method's own making, hits blended within a depth window
  kProjection,  // points projected onto the ray through their tangent planes (cylinder, cone)
};

// The splat family: methods that intersect oriented discs.
inline bool splat_family(LeafFamily f) {
  return f == LeafFamily::kDisc || f == LeafFamily::kSplatBlend;
}

// A caustic sample map (Goradia et al. 2011): before a frame of a scene holding an object of this
// method, photons from the scene's point and sphere lights are traced through its specular
// surfaces and stored where they first land on a non-specular one (render/caustic_map.hpp); the
// frame adds their density estimate at the non-specular vertices the camera reaches directly or
// through specular vertices only.
struct CausticMapSpec {
  int photons = 0;       // photons emitted over all lights
  int k = 1;             // nearest photons per density estimate
  float max_radius = 0;  // bound on the estimate's radius, as a fraction of the scene diagonal
};

// A complexity claim of the thesis about one method.
struct MethodClaim {
  std::string quantity;                // "leaf intersection" or "frame"
  std::string complexity;              // as printed, e.g. "O(IK)"
  std::vector<std::string> variables;  // the swept variables it is in, e.g. {"I", "K"}
  std::string source;                  // "Table 5.5", "Table 6.1", ...
};

// What a method's I counts: `steps` per iterative run (`runs`), so that I_run = steps / runs
// (Newton steps per Newton run, MLS fits per MLS run, ...). Both null: no iterative kernel.
struct IterationCounters {
  const Counter* steps = nullptr;
  const Counter* runs = nullptr;
};

struct MethodInfo {
  std::string id;
  std::string paper;       // citation
  std::string thesis_ref;  // the thesis's reference number, e.g. "[55]"
  std::string description;
  std::string structure;           // the paper's structure (Table 5.4): the default
  std::vector<std::string> needs;  // Table 5.3 preconditions
  std::vector<ParamSpec> params;
  std::vector<MethodClaim> claims;
  std::function<std::unique_ptr<Method>(const ParamValues&)> create;
  std::string own_structure =
      {};  // non-empty: traces whole rays itself (own_closest_hit); --structure does not apply
  // The counters of this method's own leaf work (weighted-plane terms, MLS neighbours, march
  // steps, ...): with the traversal's nodes and items, the work frame claims are judged on.
  std::vector<const Counter*> work = {};
  LeafFamily family = LeafFamily::kOther;
  // Methods whose memory the splat-and-structure estimate (render/memory_estimate) does not
  // describe for some parameters: their bytes per point for those parameters, else 0.
  std::function<size_t(const PointCloud&, const ParamValues&)> own_bytes_per_point = {};
  // Bytes per point a method keeps besides the estimate's splats and structure (its own copies of
  // the splats it makes, fields per splat): an upper bound, one splat per point.
  size_t own_data_bytes_per_point = 0;
  // Methods that prepare from a stream (Method::prepare_stream) for some parameters: their peak
  // bytes per streamed point for those parameters, else 0 (they do not stream).
  std::function<size_t(const ParamValues&)> stream_bytes_per_point = {};
  // Table 5.1's columns as the thesis marks this method, each with its source (empty: not
  // marked): real time (at least 1 frame/s) and iterative (iterations few enough not to matter,
  // chapter 6). The claims registry makes their claims from these.
  std::string real_time_claim = {};
  std::string iterative_claim = {};
  IterationCounters iterations = {};
  // What its H counts: the hits a ray's walk makes (3DGRT: the any-hit calls, proxies the ray
  // enters), per ray cast. Null: the method makes no claim in hits.
  const Counter* hits = nullptr;
  // Its structure is built over items of its own making (implicit cells, patches, fitted or
  // reduced splats: Table 5.4's "other preprocessing"), so its build is a claim of its own.
  bool own_items = false;
  // Methods whose paper adds a caustic sample map: its settings from the method's parameters.
  std::function<CausticMapSpec(const ParamValues&)> caustic_map = {};
  // What its runs cost, for balancing a sweep's shards (harness/shard_plan): nanoseconds per
  // N log2 N of preparation and build, and per ray and log2 N of a frame, medians over
  // results/thesis at 2 threads. The defaults are the splat oracle's order of magnitude.
  struct RunCost {
    double prepare_ns = 100, ray_ns = 60;
  } cost = {};
  // The accuracy bounds (render/accuracy.hpp) it is known to miss with its defaults, per
  // generator shape, each explained in its README; render/accuracy_test.cpp requires exactly these.
  struct KnownMiss {
    std::string dataset;  // a generator: "sphere", "torus"
    std::string bound;  // "holes", "false hits", "distance median", "distance p95", "normal median"
  };
  std::vector<KnownMiss> accuracy_misses = {};
  // Claims of the thesis about this method beyond its leaf and frame costs and Table 5.1's
  // columns, each judged under the id "<id>/<name>".
  struct OtherClaim {
    std::string name;        // the claim id's suffix: "fan"
    std::string statement;   // what is claimed, in words
    std::string complexity;  // "O(K^2)", or a threshold such as "I <= 1"
    std::vector<std::string> variables;
    std::string source;  // "section 5.5.2"
    // Why the sweep harness cannot judge it (its variables are none of the harness's), and where
    // it is measured instead; empty: a design of this method judges it.
    std::string not_tested = {};
  };
  std::vector<OtherClaim> other_claims = {};
  // How the thesis config sweeps this method's own claims (scripts/make_thesis_config.py writes
  // configs/thesis.json from these): one design per claim and experiment, on the sphere.
  struct ClaimDesign {
    std::string claim = "leaf";  // the claim id's suffix: "<id>/leaf"
    // Methods naming the same experiment share its runs, so their designs must agree (the
    // generator refuses them if they do not): e.g. every octree splat method in "leaf_K_octree".
    std::string experiment;
    std::string structure = {};  // the structure swept on, when not the method's own default
    std::string variable = {};   // the fit's variable ("K", "k", "I"); empty: a threshold claim
    std::string param = {};      // the parameter swept through `values`; empty: none swept
    std::vector<int> values = {};
    int N = 5000, M = 1024, B = 0;
    std::vector<int> Ns = {};  // non-empty: the experiment sweeps N through these instead
    bool build = false;        // a build experiment (the structure over the method's items)
    bool timed = false;        // fitted on the median repetition's time instead of `metric`
    // Held variables the swept parameter moves by construction ("H": a larger k-buffer walks
    // farther past the surface), exempt from the drift check.
    std::vector<std::string> free = {};
    std::vector<const Counter*> metric = {};  // fitted as their sum per `per`
    const Counter* per = nullptr;
    // A run column fitted against instead of the variable. I is not a knob: runs stop when the ray
    // leaves the local surface whatever the cap, so the I sweeps fit against the measured
    // iterations per run ("I_run"), where K per iteration is an identity: a loop check.
    std::string x = {};
    double max = 0;  // a threshold claim's bound on metric per `per`; 0: a growth claim
    // Parameters held for the whole experiment: the I sweeps hold tolerance = 0, so that the
    // iteration cap, not convergence, ends the runs.
    std::vector<std::pair<std::string, double>> fixed = {};
    int replicates = 3;  // dataset seeds per grid point (the pure error a fit is tested against)
    // On the four shapes of the iteration claims (sphere, torus, bumpy sphere, building scan).
    bool shapes = false;
  };
  std::vector<ClaimDesign> designs = {};
  // Where Table 5.1's real-time claim is judged: one frame at N points, 512x512, 1 spp, 1 bounce,
  // in the common experiment unless a method needs its own (minutes a frame, the paper's own N).
  struct RealTimeDesign {
    std::string experiment = "real_time";
    int N = 1000000, repetitions = 5;
    std::string why = {};  // the experiment's description when it is the method's own
  };
  std::vector<RealTimeDesign> real_time_designs = {RealTimeDesign{}};

  // One of the thesis's surveyed methods (it has a reference number), not a reference oracle.
  [[nodiscard]] bool surveyed() const { return thesis_ref != "-"; }
};

// MethodInfo::create for a method constructed from its typed parameters (declared by `list`).
template <class M, class P>
std::function<std::unique_ptr<Method>(const ParamValues&)> create_from(const ParamList<P>& list,
                                                                       const char* id) {
  return [&list, id](const ParamValues& given) -> std::unique_ptr<Method> {
    return std::make_unique<M>(list.read(given, id));
  };
}

using MethodRegistry = Registry<MethodInfo>;

// The methods pcrt ships (methods/builtin_methods.cpp, the one list).
void register_builtins(MethodRegistry& registry);

}  // namespace pcrt
