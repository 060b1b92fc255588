#include "methods/embree_oriented_disc/disc_packets.hpp"

#include <algorithm>
#include <vector>

#include "core/error.hpp"
#include "methods/embree_oriented_disc/embree_discs.hpp"

namespace pcrt {

struct EmbreeDiscPackets::Impl {
  SplatSet splats;
  std::vector<uint32_t> item_of_point;  // empty: Morton order
  std::unique_ptr<EmbreeScene> embree;
};

namespace {

// Embree's packet types by width, and its entry points for them.
template <int W>
struct Packet;
template <>
struct Packet<8> {
  using RayHit = RTCRayHit8;
  using RayOnly = RTCRay8;
  static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect8(v, s, c, r);
  }
  static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, RayOnly* r) {
    rtcOccluded8(v, s, c, r);
  }
};
template <>
struct Packet<16> {
  using RayHit = RTCRayHit16;
  using RayOnly = RTCRay16;
  static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) {
    rtcIntersect16(v, s, c, r);
  }
  static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, RayOnly* r) {
    rtcOccluded16(v, s, c, r);
  }
};

// Fills lane i of an Embree ray packet; lanes past `count` are invalid (valid[i] = 0).
template <class R>
void load_lanes(const Ray* rays, int count, int width, R& r, int* valid) {
  for (int i = 0; i < width; ++i) {
    valid[i] = i < count ? -1 : 0;
    const Ray& ray = rays[std::min(i, count - 1)];
    r.org_x[i] = ray.o.x(), r.org_y[i] = ray.o.y(), r.org_z[i] = ray.o.z();
    r.dir_x[i] = ray.d.x(), r.dir_y[i] = ray.d.y(), r.dir_z[i] = ray.d.z();
    r.tnear[i] = ray.tmin;
    r.tfar[i] = ray.tmax;
    r.time[i] = 0;
    r.mask[i] = ~0u;
    r.id[i] = unsigned(i);
    r.flags[i] = 0;
  }
}

RTCIntersectContext context_for(bool coherent) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags =
      coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  return context;
}

template <int W>
void closest_packet(const EmbreeDiscPackets::Impl& m, const Ray* rays, int count, bool coherent,
                    Hit* hits) {
  alignas(64) typename Packet<W>::RayHit rh;
  alignas(64) int valid[W];
  load_lanes(rays, count, W, rh.ray, valid);
  for (int i = 0; i < W; ++i) rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext context = context_for(coherent);
  Packet<W>::intersect(valid, m.embree->scene(), &context, &rh);
  for (int i = 0; i < count; ++i) {
    Hit& h = hits[i];
    h = Hit{};
    if (rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
    const uint32_t id = rh.hit.primID[i];
    const uint32_t k = m.item_of_point.empty() ? id : m.item_of_point[id];
    h.t = rh.ray.tfar[i];
    h.prim = m.splats.point_of(k);
    h.p = rays[i].at(h.t);
    h.n = m.splats.normals[k];
    h.footprint = m.splats.radii[k];
  }
}

template <int W>
void occluded_packet(const EmbreeDiscPackets::Impl& m, const Ray* rays, int count, bool coherent,
                     char* blocked) {
  alignas(64) typename Packet<W>::RayOnly r;
  alignas(64) int valid[W];
  load_lanes(rays, count, W, r, valid);
  RTCIntersectContext context = context_for(coherent);
  Packet<W>::occluded(valid, m.embree->scene(), &context, &r);
  for (int i = 0; i < count; ++i) blocked[i] = char(r.tfar[i] < 0);  // -inf on a hit
}

}  // namespace

EmbreeDiscPackets::EmbreeDiscPackets(const PointCloud& cloud, int width, PrepareContext& ctx)
    : impl_(std::make_unique<Impl>()), width_(width) {
  if (width != 8 && width != 16) input_error("Embree disc packets: width {} is not 8 or 16", width);
  impl_->splats = prepare_splats(cloud, SplatParams{}, ctx);
  ScopedTimer t(ctx.timings, "prepare/embree_build");
  impl_->embree = build_embree_discs(impl_->splats, true, impl_->item_of_point, "Embree packets");
}

EmbreeDiscPackets::~EmbreeDiscPackets() = default;

void EmbreeDiscPackets::closest_hits(const Ray* rays, int count, bool coherent, Hit* hits) const {
  if (count <= 0) return;
  if (width_ == 8)
    closest_packet<8>(*impl_, rays, count, coherent, hits);
  else
    closest_packet<16>(*impl_, rays, count, coherent, hits);
}

void EmbreeDiscPackets::occluded(const Ray* rays, int count, bool coherent, char* blocked) const {
  if (count <= 0) return;
  if (width_ == 8)
    occluded_packet<8>(*impl_, rays, count, coherent, blocked);
  else
    occluded_packet<16>(*impl_, rays, count, coherent, blocked);
}

bool EmbreeDiscPackets::native() const { return impl_->embree->native_packets(width_); }

}  // namespace pcrt
