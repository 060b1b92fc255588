// The white furnace: an object of albedo 1 under a uniform environment of radiance 1 that is
// reached only by bounce rays. Every path that leaves the object within B bounces carries
// exactly 1 and every other carries 0, so a pixel's value is the share of its S paths that got
// out. For a convex object at B >= 1 any loss is a secondary ray that hit the surface it left
// (a self-hit) or went through it (a leak): the renderer's spawn rule measured per method.
#pragma once

#include <optional>

#include "core/image.hpp"
#include "core/surfaces.hpp"
#include "render/renderer.hpp"

namespace pcrt {

// The exact surface the object samples, and the spacing its tolerances are in.
struct FurnaceTruth {
  const Surface& surface;
  double h = 0;
};

// Where the dark pixels lost their light, judged by each pixel's centre sample against the exact
// surface: `primary`, the camera ray's own hit is false (more than 5 h from the exact first hit,
// or no exact hit: the accuracy table's see-through, early and phantom hits), so the path started
// inside or off the object; `secondary`, the camera ray hit the surface where it is, so a
// secondary ray was lost (a self-hit, a leak, or, on a non-convex shape, light that needed more
// bounces). At S = 1 the centre sample is a pixel's only path and the split is exact.
struct FurnaceCauses {
  size_t primary = 0, secondary = 0;
};

struct FurnaceResult {
  RenderResult frame;
  size_t object_pixels = 0;             // pixels whose centre sample hit the object
  double mean = 0;                      // mean radiance over those pixels (1: nothing lost)
  size_t dark_pixels = 0;               // of those, pixels that lost at least one of their S paths
  std::optional<FurnaceCauses> causes;  // with a truth only
};

// `settings` gives M, S, B, the camera and the threads; its point light is not used.
FurnaceResult white_furnace(const SceneIntersector& geometry, const PointCloud& cloud,
                            const RenderSettings& settings,
                            const std::optional<FurnaceTruth>& truth = std::nullopt);

}  // namespace pcrt
