#include "methods/kernels/mls_surface.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>

#include "methods/kernels/mls_method_params.hpp"
#include "preprocess/point_attributes.hpp"

namespace pcrt {

LocalPolynomial MlsSurface::fit(const Vec3& q, OpCounters& counters) const {
  std::array<uint32_t, kMaxMlsNeighbours> idx;
  std::array<float, kMaxMlsNeighbours> d2;
  const size_t k = knn_.knn(q, std::min(s_.k, kMaxMlsNeighbours), idx.data(), d2.data(), counters);
  counters.add(kMlsFits);
  counters.add(kMlsNeighbours, k);
  const double inv_h2 = 1.0 / (double(s_.weight_radius) * s_.weight_radius);
  std::array<double, kMaxMlsNeighbours> w;
  // Reference plane: weighted centroid and the smallest eigenvector of the weighted covariance.
  double wsum = 0;
  Vec3d m = Vec3d::Zero();
  for (size_t j = 0; j < k; ++j) {
    w[j] = std::exp(-double(d2[j]) * inv_h2);
    wsum += w[j];
    m += w[j] * positions_[idx[j]].cast<double>();
  }
  LocalPolynomial f;
  f.scale = s_.weight_radius;
  if (!(wsum > 0)) {  // every neighbour far outside the weight radius: unweighted
    for (size_t j = 0; j < k; ++j) w[j] = 1;
    wsum = double(k);
    m = Vec3d::Zero();
    for (size_t j = 0; j < k; ++j) m += positions_[idx[j]].cast<double>();
  }
  m /= wsum;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (size_t j = 0; j < k; ++j) {
    const Vec3d d = positions_[idx[j]].cast<double>() - m;
    cov += w[j] * d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  f.n = eig.eigenvectors().col(0);
  if (!f.n.allFinite() || f.n.squaredNorm() < 0.5) f.n = Vec3d::UnitZ();
  f.n.normalize();
  f.u = eig.eigenvectors().col(2).normalized();
  f.v = f.n.cross(f.u);
  const Vec3d qd = q.cast<double>();
  f.origin = qd - f.n * f.n.dot(qd - m);
  f.c[0] = f.n.dot(m - f.origin);  // 0 up to rounding: the plane through m
  if (!s_.polynomial || k < 6) return f;
  // Height field: weighted least squares on [1 x y x^2 xy y^2], x and y in units of H.
  Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  for (size_t j = 0; j < k; ++j) {
    const Vec3d d = positions_[idx[j]].cast<double>() - f.origin;
    const double x = f.u.dot(d) / f.scale, y = f.v.dot(d) / f.scale, z = f.n.dot(d);
    Eigen::Matrix<double, 6, 1> row;
    row << 1, x, y, x * x, x * y, y * y;
    a += w[j] * row * row.transpose();
    b += w[j] * z * row;
  }
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(a);
  const Eigen::Matrix<double, 6, 1> c = ldlt.solve(b);
  // A rank-deficient neighbourhood (collinear points) keeps the plane.
  if (ldlt.info() == Eigen::Success && c.allFinite() &&
      (a * c - b).norm() <= 1e-6 * b.norm() + 1e-300)
    for (int i = 0; i < 6; ++i) f.c[i] = c[i];
  return f;
}

float MlsSurface::intersect(const LocalPolynomial& f, const Ray& ray, float t0, float t1) {
  // In the frame: x(t) = x0 + t dx (likewise y, z); F(t) = g(x(t), y(t)) - z(t) = A t^2 + B t + C.
  const Vec3d o = ray.o.cast<double>() - f.origin, d = ray.d.cast<double>();
  const double x0 = f.u.dot(o) / f.scale, dx = f.u.dot(d) / f.scale;
  const double y0 = f.v.dot(o) / f.scale, dy = f.v.dot(d) / f.scale;
  const double z0 = f.n.dot(o), dz = f.n.dot(d);
  const double* c = f.c;
  const double qa = c[3] * dx * dx + c[4] * dx * dy + c[5] * dy * dy;
  const double qb = c[1] * dx + c[2] * dy + 2 * c[3] * x0 * dx + c[4] * (x0 * dy + y0 * dx) +
                    2 * c[5] * y0 * dy - dz;
  const double qc =
      c[0] + c[1] * x0 + c[2] * y0 + c[3] * x0 * x0 + c[4] * x0 * y0 + c[5] * y0 * y0 - z0;
  double r0 = kInfinity, r1 = kInfinity;
  // qa is per unit of length (x and y are in units of H), qb a pure number: the test of a flat
  // F compares qa H with qb, so that it asks the same at every scale of the cloud.
  if (std::abs(qa) * f.scale <= 1e-12 * std::abs(qb)) {
    if (qb != 0) r0 = -qc / qb;
  } else {
    const double disc = qb * qb - 4 * qa * qc;
    if (disc < 0) return kInfinity;
    // The numerically stable pair of roots.
    const double s = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
    r0 = s / qa;
    r1 = s != 0 ? qc / s : r0;
    if (r1 < r0) std::swap(r0, r1);
  }
  if (r0 >= t0 && r0 <= t1) return float(r0);
  if (r1 >= t0 && r1 <= t1) return float(r1);
  return kInfinity;
}

Vec3 MlsSurface::normal(const LocalPolynomial& f, const Vec3& x) {
  const Vec3d d = x.cast<double>() - f.origin;
  const double px = f.u.dot(d) / f.scale, py = f.v.dot(d) / f.scale;
  const double gx = (f.c[1] + 2 * f.c[3] * px + f.c[4] * py) / f.scale;
  const double gy = (f.c[2] + f.c[4] * px + 2 * f.c[5] * py) / f.scale;
  const Vec3d n = (f.n - gx * f.u - gy * f.v).normalized();
  return n.allFinite() ? Vec3(n.cast<float>()) : Vec3(f.n.cast<float>());
}

float MlsSurface::intersect_ray(const Ray& ray, const Vec3& start, float t0, float t1,
                                Vec3& normal_out, OpCounters& counters) const {
  counters.add(kMlsRuns);
  Vec3 p = start;
  float t = kInfinity;
  for (int i = 0; i < s_.max_iterations; ++i) {
    const LocalPolynomial f = fit(p, counters);
    t = intersect(f, ray, t0, t1);
    if (t == kInfinity) {
      counters.add(kMlsNoRoot);
      return kInfinity;
    }
    const Vec3 next = ray.at(t);
    normal_out = normal(f, next);
    if (s_.tolerance > 0 && (next - p).norm() <= s_.tolerance) {
      counters.add(kMlsConverged);
      counters.add(kMlsConvergedIterations, uint64_t(i + 1));
      return t;
    }
    p = next;
  }
  counters.add(kMlsCapped);
  return t;
}

bool mls_intersect_leaf(const Ray& ray, const LeafVisit& leaf, std::span<const Vec3> centres,
                        float ball_radius, const MlsSurface& surface, Hit& hit,
                        OpCounters& counters) {
  auto ball = [&](uint32_t i, Vec3& c, float& r, uint32_t& prim) {
    c = centres[i], r = ball_radius, prim = i;
  };
  auto run = [&](uint32_t i, float t0, float t1, Vec3& n) {
    return surface.intersect_ray(ray, centres[i], t0, t1, n, counters);
  };
  return nearest_ball_hit(ray, leaf.items, ball, run, hit);
}

// The declaration with the method's own defaults for the iteration.
ParamList<MlsParams> MlsParams::list(double max_iterations, double tolerance) {
  using P = MlsParams;
  return ParamList<P>()
      .add(&P::K, {"K", 20, 6, double(kMaxMlsNeighbours), "neighbours in each MLS fit"})
      .add(&P::weight_radius,
           {"weight_radius", 2.0, 0.25, 50, "H of the Gaussian weight exp(-d^2/H^2), in h"})
      .add(&P::ball_radius, {"ball_radius", 3.5, 0.5, 50,
                             "radius of the ball around each point that starts an MLS run, in h"})
      .add(&P::tolerance,
           {"tolerance", tolerance, 0, 100,
            "stop when the hit point moves less than this, in h (0: always run max_iterations)"})
      .add(&P::max_iterations,
           {"max_iterations", max_iterations, 1, 100, "cap on the MLS iterations I per run"});
}

void MlsPoints::prepare(const PointCloud& cloud, const MlsParams& params, OpCounters& counters,
                        std::map<std::string, double>& timings) {
  {
    ScopedTimer t(timings, "prepare/knn_build");
    knn.emplace(cloud.positions);
  }
  {
    ScopedTimer t(timings, "prepare/spacing");
    h = std::max(float(mean_spacing(cloud.positions, *knn, counters)), 1e-30f);
  }
  positions = cloud.positions;
  ball = params.ball_radius * h;
  radii.assign(cloud.size(), ball);
  surface.emplace(positions, *knn, mls_settings(params, h));
}

}  // namespace pcrt
