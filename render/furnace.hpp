// The white furnace: an object of albedo 1 under a uniform environment of radiance 1 that is
// reached only by bounce rays. Every path that leaves the object within B bounces carries
// exactly 1 and every other carries 0, so a pixel's value is the share of its S paths that got
// out. For a convex object at B >= 1 any loss is a secondary ray that hit the surface it left
// (a self-hit) or went through it (a leak): the renderer's spawn rule measured per method.
#pragma once

#include "core/image.hpp"
#include "render/renderer.hpp"

namespace pcrt {

struct FurnaceResult {
  RenderResult frame;
  size_t object_pixels = 0;  // pixels whose centre sample hit the object
  double mean = 0;           // mean radiance over those pixels (1: nothing lost)
  size_t dark_pixels = 0;    // of those, pixels that lost at least one of their S paths
};

// `settings` gives M, S, B, the camera and the threads; its point light is not used.
FurnaceResult white_furnace(const SceneIntersector& geometry, const PointCloud& cloud,
                            const RenderSettings& settings);

}  // namespace pcrt
