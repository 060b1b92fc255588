// Gaussian particles as the ray tracers of 3D Gaussians see them (3DGRT, Moenne-Loccoz et al.
// 2024): per particle the affine map into its canonical frame, where it is the isotropic Gaussian
// of unit variance, its peak opacity, its normal and a bounding proxy. Taken from the cloud's
// Gaussian attribute set (a trained 3D Gaussian Splatting file) or made from any cloud the way
// the trainers initialise from points, without training.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

#include "core/gaussians.hpp"
#include "core/params.hpp"
#include "methods/kernels/splat_set.hpp"
#include "methods/method.hpp"

namespace pcrt {

// What a ray's march through Gaussian particles counts (methods/grt_2024).
inline const Counter kProxyTests{"gaussian_proxy_tests", "particle proxies tested by a ray"};
inline const Counter kProxyHits{"gaussian_proxy_hits",
                                "particle proxies a ray's segment meets (responses evaluated)"};
inline const Counter kKBufferInserts{
    "kbuffer_inserts", "particle responses inserted into a ray's k-buffer (later ones may evict)"};
inline const Counter kParticlesBlended{"particles_blended",
                                       "particle responses blended front to back along a ray"};
inline const Counter kRetraces{"kbuffer_retraces",
                               "walks of a ray after its first, from its k-buffer's last hit"};
inline const Counter kKBufferWasted{
    "kbuffer_wasted",
    "k-buffer entries behind the surface when a ray reached it: collected, never blended"};

// How particles are made from a cloud without them (a cloud with them keeps its own).
enum class GaussianInit {
  // Normal-aligned and flat, 2D-Gaussian-like: each particle's half-opacity contour is the
  // point's splat disc (its reference_splat radius), its thickness `flatness` of that.
  kFlat = 0,
  // 3D Gaussian Splatting's start of training: isotropic, the scale the root mean square
  // distance to the 3 nearest neighbours.
  kIsotropic = 1,
};

// The bounding proxy a particle's traversal tests before its response is evaluated.
enum class GaussianProxy {
  kIcosahedron = 0,  // the paper's: a regular icosahedron around the cut-off ellipsoid (Eq. 7)
  kBox = 1,          // the cut-off ellipsoid's axis-aligned box
  kEllipsoid = 2,    // the cut-off ellipsoid itself, in closed form (RaySplats-style)
};

struct ParticleParams {
  GaussianInit init = GaussianInit::kFlat;
  float opacity = 0;       // initial peak opacity; 0: the init's own (flat 1, isotropic 0.1)
  float flatness = 0;      // flat init: normal scale over tangent scale
  float min_response = 0;  // alpha_min: responses below it are ignored; the proxies reach it
  float max_alpha = 0;     // the clamp on one particle's alpha
  SplatParams splat;       // normals and radii for the flat init
  static const ParamList<ParticleParams>& list();
};

// The particles in the cloud's order (particle i is point i, and reports prim i).
struct ParticleSet {
  std::span<const Vec3> centres;   // the cloud's positions
  std::vector<Mat3> to_canonical;  // S^-1 R^T: x -> to_canonical * (x - centre)
  std::vector<float> opacities;    // peak opacity, clamped to max_alpha
  std::vector<float> reach;        // canonical radius where the response falls to min_response
  std::vector<Vec3> normals;       // shortest axis (flat init: the point's normal)
  std::vector<float> footprints;   // largest scale: what secondary rays are lifted by
  std::vector<Vec3> half_extents;  // of the proxy's world box
  std::vector<float> bound_radii;  // of the proxy's bounding sphere
  float min_response = 0;

  [[nodiscard]] size_t size() const { return centres.size(); }
  [[nodiscard]] ItemSet items() const { return {centres, bound_radii, half_extents}; }
  [[nodiscard]] size_t memory_bytes() const;
};

// The particles of `cloud` (its own, or made by params.init), with proxies of the given kind.
// The cloud must outlive the set.
ParticleSet prepare_gaussians(const PointCloud& cloud, const ParticleParams& params,
                              GaussianProxy proxy, PrepareContext& ctx);

// A particle's response along a ray: the distance of its maximum and its alpha there.
struct ParticleResponse {
  float t = 0;
  float alpha = 0;
  float min_d2 = 0;  // the squared canonical distance of the ray from the centre
};
inline ParticleResponse particle_response(const ParticleSet& g, uint32_t i, const Ray& ray) {
  const Mat3& m = g.to_canonical[i];
  const Vec3 og = m * (ray.o - g.centres[i]);
  const Vec3 dg = m * ray.d;
  const float dd = dg.squaredNorm();
  const float od = og.dot(dg);
  ParticleResponse r;
  r.t = -od / dd;
  r.min_d2 = (og + r.t * dg).squaredNorm();
  r.alpha = g.opacities[i] * std::exp(-0.5f * r.min_d2);
  return r;
}

// The chord of the ray's line through particle i's ellipsoid |x'| <= radius (canonical frame), as
// [t0, t1]; false if the line misses it.
inline bool ellipsoid_chord(const ParticleSet& g, uint32_t i, const Ray& ray, float radius,
                            float& t0, float& t1) {
  // |og + t dg|^2 = radius^2: the chord around the point nearest the centre, tau, of half-length
  // sqrt((radius^2 - d2) / dd) with d2 the ray's squared distance from the centre there. (The
  // textbook discriminant od^2 - dd (og^2 - radius^2) cancels catastrophically for flat
  // particles, whose canonical frame stretches the normal by 1 / flatness.)
  const Mat3& m = g.to_canonical[i];
  const Vec3 og = m * (ray.o - g.centres[i]);
  const Vec3 dg = m * ray.d;
  const float dd = dg.squaredNorm();
  const float tau = -og.dot(dg) / dd;
  const float d2 = (og + tau * dg).squaredNorm();
  if (d2 > radius * radius) return false;
  const float half = std::sqrt((radius * radius - d2) / dd);
  t0 = tau - half, t1 = tau + half;
  return true;
}

// EVER's constant-density ellipsoids (methods/ever_2024): each particle's half-maximum contour
// |x'| <= sqrt(2 ln 2), the density that gives a chord through the centre along the shortest axis
// the particle's peak opacity. Resizes the set's proxies to these ellipsoids; returns the
// densities (per unit of world length).
inline constexpr float kHalfMaximumRadius = 1.17741002251547469f;  // sqrt(2 ln 2)
std::vector<float> constant_density_ellipsoids(ParticleSet& g);

// The exact optical depth along a ray through constant-density ellipsoids: linear between the
// events (entries and exits, in order of t), its slope the summed density of the ellipsoids the
// ray is in. Double precision, so that exits cancel their entries.
struct OpticalDepth {
  double t = 0, rate = 0, depth = 0;
  uint32_t front = kNoPrim;  // the ellipsoid entered last: the surface's particle
  // Moves to t_next; true, with t_surface, if the depth reaches `target` on the way.
  bool advance(float t_next, double target, double d_norm, float& t_surface) {
    const double grown = depth + rate * (double(t_next) - t) * d_norm;
    if (rate > 0 && grown >= target) {
      t_surface = float(t + (target - depth) / (rate * d_norm));
      return true;
    }
    depth = grown, t = t_next;
    return false;
  }
  void enter(uint32_t prim, double density) { rate += density, front = prim; }
  void exit(double density) { rate = std::max(rate - density, 0.0); }
};

// Whether the ray's segment [tmin, tmax] meets particle i's proxy; inv_d is 1 / ray.d, made once
// per ray for the box's slabs.
bool proxy_hit(const ParticleSet& g, GaussianProxy proxy, uint32_t i, const Ray& ray,
               const Vec3& inv_d);
inline bool proxy_hit(const ParticleSet& g, GaussianProxy proxy, uint32_t i, const Ray& ray) {
  return proxy_hit(g, proxy, i, ray, ray.d.cwiseInverse());
}

}  // namespace pcrt
