#include "methods/kernels/gaussian_particles.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "preprocess/point_attributes.hpp"
#include "structures/knn_index.hpp"

namespace pcrt {

const ParamList<ParticleParams>& ParticleParams::list() {
  using P = ParticleParams;
  static const auto l =
      ParamList<P>()
          .add(&P::init, {"init", 0, 0, 1,
                          "particles for a cloud without them: 0 flat (normal-aligned, each one's "
                          "half-opacity contour the point's splat disc), 1 isotropic (3D Gaussian "
                          "Splatting's initialisation: RMS distance to 3 nearest neighbours)"})
          .add(&P::opacity, {"opacity", 0, 0, 1,
                             "initial peak opacity; 0: the init's own (flat 1, isotropic 0.1)"})
          .add(&P::flatness, {"flatness", 0.001, 1e-4, 1,
                              "flat init: the normal scale as a fraction of the tangent scale"})
          .add(&P::min_response,
               {"min_response", 1.0 / 255, 1e-4, 0.5,
                "alpha_min: particle responses below it are ignored and the proxies reach it"})
          .add(&P::max_alpha, {"max_alpha", 0.99, 0.5, 1, "the clamp on one particle's alpha"})
          .add(&P::splat, SplatParams::list());
  return l;
}

namespace {

// The regular icosahedron of edge 2 (vertices (0, +-1, +-phi) cycled), centrally symmetric: its
// 20 faces lie on 10 planes pairs +-n . x = inradius.
struct Icosahedron {
  std::array<Vec3, 12> vertices;
  std::array<Vec3, 10> face_normals;  // unit, one of each opposite pair
  float inradius = 0;

  Icosahedron() {
    const float phi = (1.0f + std::sqrt(5.0f)) / 2.0f;
    int k = 0;
    for (float a : {-1.0f, 1.0f})
      for (float b : {-phi, phi}) {
        vertices[size_t(k++)] = Vec3(0, a, b);
        vertices[size_t(k++)] = Vec3(a, b, 0);
        vertices[size_t(k++)] = Vec3(b, 0, a);
      }
    // A face's normal is its centroid's direction; the faces are the vertex triples at mutual
    // distance 2 (the edge). Keeps one normal of each opposite pair.
    int f = 0;
    for (int i = 0; i < 12; ++i)
      for (int j = i + 1; j < 12; ++j)
        for (int m = j + 1; m < 12; ++m) {
          const Vec3 &a = vertices[size_t(i)], &b = vertices[size_t(j)], &c = vertices[size_t(m)];
          auto edge = [](const Vec3& p, const Vec3& q) {
            return std::abs((p - q).norm() - 2) < 1e-4f;
          };
          if (!edge(a, b) || !edge(b, c) || !edge(a, c)) continue;
          const Vec3 n = (a + b + c).normalized();
          const bool seen = std::any_of(face_normals.begin(), face_normals.begin() + f,
                                        [&](const Vec3& o) { return o.dot(n) < -0.999f; });
          if (!seen && f < 10) face_normals[size_t(f++)] = n;
          inradius = n.dot(a);
        }
  }
};

const Icosahedron& icosahedron() {
  static const Icosahedron ico;
  return ico;
}

struct ParticleShape {
  Vec3 scale;
  Mat3 rotation;  // columns: the particle's axes
  float opacity;
};

// The flat init: axes (t1, t2, n), the tangent scale making opacity * exp(-r^2 / 2 s^2) = 1/2 at
// the splat radius r.
ParticleShape flat_particle(const Vec3& n, float radius, float opacity, float flatness) {
  Vec3 t1, t2;
  orthonormal_basis(n, t1, t2);
  ParticleShape p;
  p.rotation.col(0) = t1, p.rotation.col(1) = t2, p.rotation.col(2) = n;
  const float s = radius / std::sqrt(2.0f * std::log(2.0f * opacity));
  p.scale = Vec3(s, s, flatness * s);
  p.opacity = opacity;
  return p;
}

std::vector<ParticleShape> cloud_particles(const PointCloud& cloud) {
  const GaussianParticles& g = cloud.gaussians;
  std::vector<ParticleShape> out(cloud.size());
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = {g.scales[i], rotation_matrix(g.rotations[i]), g.opacities[i]};
  return out;
}

// RMS distance to the 3 nearest other points, floored where points nearly coincide.
std::vector<float> isotropic_scales(const PointCloud& cloud, PrepareContext& ctx) {
  ScopedTimer t(ctx.timings, "prepare/gaussian_scales");
  const KnnIndex knn(cloud.positions);
  std::vector<float> scale(cloud.size());
  const float floor = 1e-7f * std::max(cloud.bounds().diagonal(), 1e-30f);
  for_each_point_knn(cloud.positions, knn, 4, ctx.counters,
                     [&](size_t i, std::span<const uint32_t>, std::span<const float> d2) {
                       float sum = 0;
                       for (size_t k = 1; k < d2.size(); ++k) sum += d2[k];
                       const size_t n = std::max<size_t>(d2.size() - 1, 1);
                       scale[i] = std::max(std::sqrt(sum / float(n)), floor);
                     });
  return scale;
}

std::vector<ParticleShape> initial_particles(const PointCloud& cloud, const ParticleParams& p,
                                             std::span<const Vec3> normals,
                                             std::span<const float> radii, PrepareContext& ctx) {
  std::vector<ParticleShape> out(cloud.size());
  if (p.init == GaussianInit::kFlat) {
    const float opacity = std::min(p.opacity > 0 ? p.opacity : 1.0f, p.max_alpha);
    if (!(opacity > 0.5f))
      input_error(
          "max_alpha {} and opacity {} (0: 1) give flat particles (init=flat) a peak opacity of "
          "{}: it must be above 0.5, as their edge is where it halves",
          p.max_alpha, p.opacity, opacity);
    for (size_t i = 0; i < out.size(); ++i)
      out[i] = flat_particle(normals[i], radii[i], opacity, p.flatness);
    return out;
  }
  const std::vector<float> scale = isotropic_scales(cloud, ctx);
  for (size_t i = 0; i < out.size(); ++i)
    out[i] = {Vec3::Constant(scale[i]), Mat3::Identity(), p.opacity > 0 ? p.opacity : 0.1f};
  return out;
}

// The proxy's world box half-extents: the cut-off ellipsoid's (x = R S u, |u| <= reach: row a of
// R S has length |row|), or the icosahedron's vertices' (scaled so its inradius is the reach).
Vec3 proxy_half_extents(const ParticleShape& p, float reach, GaussianProxy proxy) {
  const Mat3 rs = p.rotation * p.scale.asDiagonal();
  if (proxy != GaussianProxy::kIcosahedron) return reach * rs.rowwise().norm();
  const Icosahedron& ico = icosahedron();
  Vec3 e = Vec3::Zero();
  for (const Vec3& v : ico.vertices) e = e.cwiseMax((rs * v).cwiseAbs());
  return e * (reach / ico.inradius);
}

}  // namespace

ParticleSet prepare_gaussians(const PointCloud& cloud, const ParticleParams& params,
                              GaussianProxy proxy, PrepareContext& ctx) {
  ParticleSet g;
  g.centres = cloud.positions;
  g.min_response = params.min_response;
  std::vector<ParticleShape> shapes;
  std::vector<Vec3> normals;
  if (cloud.has_gaussians()) {
    shapes = cloud_particles(cloud);
    normals.assign(cloud.normals.begin(), cloud.normals.end());
  } else {
    const SplatSet splats = prepare_splats(cloud, params.splat, ctx);
    const PointAttributes a = splat_attributes_by_point(splats);
    shapes = initial_particles(cloud, params, a.normals, a.radii, ctx);
    normals.assign(a.normals.begin(), a.normals.end());
  }
  ScopedTimer t(ctx.timings, "prepare/gaussians");
  const size_t n = cloud.size();
  g.to_canonical.resize(n), g.opacities.resize(n), g.reach.resize(n), g.footprints.resize(n);
  g.half_extents.resize(n), g.bound_radii.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const ParticleShape& p = shapes[i];
    const float opacity = std::min(p.opacity, params.max_alpha);
    // opacity * exp(-reach^2 / 2) = min_response; a particle that never reaches it gets none.
    const float reach = opacity > params.min_response
                            ? std::sqrt(2.0f * std::log(opacity / params.min_response))
                            : 0.0f;
    g.to_canonical[i] = p.scale.cwiseInverse().asDiagonal() * p.rotation.transpose();
    g.opacities[i] = opacity;
    g.reach[i] = reach;
    g.footprints[i] = p.scale.maxCoeff();
    g.half_extents[i] = proxy_half_extents(p, reach, proxy);
    g.bound_radii[i] = g.half_extents[i].norm();
  }
  g.normals = std::move(normals);
  return g;
}

bool proxy_hit(const ParticleSet& g, GaussianProxy proxy, uint32_t i, const Ray& ray,
               const Vec3& inv_d) {
  float t0 = ray.tmin, t1 = ray.tmax;
  if (proxy == GaussianProxy::kBox) {
    const Vec3 lo = g.centres[i] - g.half_extents[i], hi = g.centres[i] + g.half_extents[i];
    for (int a = 0; a < 3; ++a) {
      const float inv = inv_d[a];
      float ta = (lo[a] - ray.o[a]) * inv, tb = (hi[a] - ray.o[a]) * inv;
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta), t1 = std::min(t1, tb);
    }
    return t0 <= t1;
  }
  const float reach = g.reach[i];
  if (proxy == GaussianProxy::kEllipsoid) {
    float a = 0, b = 0;
    return ellipsoid_chord(g, i, ray, reach, a, b) && a <= t1 && b >= t0;
  }
  const Mat3& m = g.to_canonical[i];
  const Vec3 og = m * (ray.o - g.centres[i]);
  const Vec3 dg = m * ray.d;
  // The solid icosahedron: the segment clipped to its 10 slabs |n . x| <= inradius * scale.
  const Icosahedron& ico = icosahedron();
  const float slab = reach;  // the icosahedron's inradius is the reach
  for (const Vec3& n : ico.face_normals) {
    const float s = n.dot(og), v = n.dot(dg);
    if (v == 0) {
      if (std::abs(s) > slab) return false;
      continue;
    }
    const float inv = 1.0f / v;
    float ta = (-slab - s) * inv, tb = (slab - s) * inv;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta), t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

std::vector<float> constant_density_ellipsoids(ParticleSet& g) {
  std::vector<float> density(g.size());
  for (size_t i = 0; i < g.size(); ++i) {
    // to_canonical = S^-1 R^T: its inverse R S has the axes' world extents in its rows' norms,
    // and its own rows have norms 1 / s_j, the largest 1 / s_min.
    const Mat3& m = g.to_canonical[i];
    const float s_min = 1.0f / m.rowwise().norm().maxCoeff();
    g.reach[i] = kHalfMaximumRadius;
    // Inverted in a unit near its entries (1 / length): the determinant is the cube of them, and
    // overflows for a cloud 10^-12 across. The same half-extents as m.inverse() gave.
    const float c = 1.0f / length_unit(m.cwiseAbs().maxCoeff());
    const Mat3 world = (c * m).inverse() * c;  // R S
    g.half_extents[i] = kHalfMaximumRadius * world.rowwise().norm();
    g.bound_radii[i] = g.half_extents[i].norm();
    // An opacity of 1 would be an infinite density: a particle lets at least 10^-6 through.
    density[i] =
        -std::log1p(-std::min(g.opacities[i], 1 - 1e-6f)) / (2.0f * kHalfMaximumRadius * s_min);
  }
  return density;
}

size_t ParticleSet::memory_bytes() const {
  return to_canonical.capacity() * sizeof(Mat3) +
         (opacities.capacity() + reach.capacity() + footprints.capacity() +
          bound_radii.capacity()) *
             sizeof(float) +
         (normals.capacity() + half_extents.capacity()) * sizeof(Vec3);
}

}  // namespace pcrt
