// Embree's oriented discs of a SplatSet (centre, radius, normal per splat) in one committed scene:
// what embree_oriented_disc traces ray by ray and EmbreeDiscPackets in packets, built one way so
// both references trace exactly the same discs. Include only from translation units that link
// Embree.
#pragma once

#include <memory>
#include <vector>

#include "core/embree_scene.hpp"
#include "methods/kernels/splat_set.hpp"

namespace pcrt {

// Embree's primitive i is splat i in Morton order (`morton`), else the cloud's point i; then
// `item_of_point` maps a point back to its splat.
inline std::unique_ptr<EmbreeScene> build_embree_discs(const SplatSet& splats, bool morton,
                                                       std::vector<uint32_t>& item_of_point,
                                                       const char* who) {
  auto embree = std::make_unique<EmbreeScene>(who);
  RTCGeometry geom = embree->new_geometry(RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT);
  // Embree wants x, y, z, radius per point and its own copy of the normals.
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), splats.size()));
  auto* n = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), splats.size()));
  for (size_t k = 0; k < splats.size(); ++k) {
    const size_t i = morton ? k : splats.point_of(uint32_t(k));
    for (int a = 0; a < 3; ++a) v[4 * i + size_t(a)] = splats.centres[k][a];
    v[4 * i + 3] = splats.radii[k];
    for (int a = 0; a < 3; ++a) n[3 * i + size_t(a)] = splats.normals[k][a];
  }
  item_of_point.clear();
  if (!morton) {
    item_of_point.resize(splats.size());
    for (uint32_t k = 0; k < splats.size(); ++k) item_of_point[splats.point_of(k)] = k;
  }
  embree->build(geom);
  return embree;
}

}  // namespace pcrt
