// Tejada et al. 2006 and 2007: primary hits from rasterizing the points into a z-buffer (no
// acceleration structure for camera rays), refined by MLS from the rasterized point; secondary
// rays through a structure (brute force in 2006, a grid in 2007) with the MLS leaf kernel. The
// two papers differ in the iteration (2006 iterates, 2007 takes one step) and the secondary
// structure, which are parameters and defaults of their modules.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>

#include "methods/kernels/mls_surface.hpp"
#include "methods/method.hpp"

namespace pcrt {

inline const Counter kRasterPoints{"raster_points", "points projected by a z-buffer pass"};
inline const Counter kRasterPixels{"raster_pixels", "pixels a z-buffer pass depth-tested"};
inline const Counter kRasterMisses{"raster_mls_misses",
                                   "camera rays whose rasterized point gave no MLS hit"};

// The MLS parameters and the z-buffer's disc size.
struct RasterMlsParams {
  MlsParams mls;
  float raster_radius = 3;  // in h
  // The declaration with the method's own defaults for the iteration.
  static ParamList<RasterMlsParams> list(double max_iterations, double tolerance);
};

class RasterMlsMethod final : public Method {
 public:
  explicit RasterMlsMethod(const RasterMlsParams& params) : params_(params) {}

  void prepare(const PointCloud& cloud, PrepareContext& ctx) override;
  [[nodiscard]] ItemSet items() const override { return {mls_.positions, mls_.radii, {}}; }
  bool intersect_leaf(const Ray& ray, const LeafVisit& leaf, Hit& hit,
                      OpCounters& counters) const override {
    return mls_intersect_leaf(ray, leaf, mls_.positions, mls_.ball, *mls_.surface, hit, counters);
  }
  [[nodiscard]] std::unique_ptr<PrimaryPass> primary_pass(const Camera& camera,
                                                          OpCounters& counters) const override;

  // Where an MLS run from point i searches the ray: the chord of i's ball, or the whole ray.
  enum class Reach : uint8_t { kBall, kWholeRay };
  // An MLS run from point i for the ray: the primary pass's refinement.
  bool refine(const Ray& ray, uint32_t i, Reach reach, Hit& hit, OpCounters& counters) const;

 private:
  RasterMlsParams params_;
  MlsPoints mls_;
  float footprint_ = 0;
};

}  // namespace pcrt
