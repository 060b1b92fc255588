// The MLS surface of Adamson and Alexa 2003 and Tejada et al. 2006/2007 (thesis section 5.1.2,
// Algorithm 3), as a leaf kernel: around a point, a weighted least-squares reference plane and a
// bivariate quadratic height field over it are fitted to the K nearest points; the ray meets that
// height field where a quadratic in t vanishes; the step is repeated from the new point until it
// moves less than a tolerance or a cap on iterations is reached.
#pragma once

#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/counters.hpp"
#include "core/geometry.hpp"
#include "core/params.hpp"
#include "core/point_cloud.hpp"
#include "methods/kernels/ball_runs.hpp"
#include "structures/knn_index.hpp"
#include "structures/structure.hpp"

namespace pcrt {

inline const Counter kMlsFits{"mls_fits", "MLS plane + polynomial fits (one k-NN query each)"};
inline const Counter kMlsNeighbours{"mls_neighbours", "points used by MLS fits (K per fit)"};
inline const Counter kMlsRuns{"mls_runs", "MLS iterations started (one per ball a ray enters)"};
inline const Counter kMlsConverged{"mls_converged", "MLS runs that met the tolerance"};
inline const Counter kMlsConvergedIterations{
    "mls_converged_iterations",
    "iterations of the runs that met the tolerance (mean I = this / mls_converged)"};
inline const Counter kMlsCapped{"mls_capped", "MLS runs stopped by the iteration cap"};
inline const Counter kMlsNoRoot{"mls_no_root", "MLS runs whose polynomial the ray missed"};

inline constexpr size_t kMaxMlsNeighbours = 128;

struct MlsSettings {
  size_t k = 20;            // K neighbours per fit
  float weight_radius = 1;  // H in theta(d) = exp(-d^2 / H^2), absolute
  float tolerance = 0;      // stop when the hit point moves less than this (absolute)
  int max_iterations = 3;   // cap on I
  bool polynomial = true;   // false: the reference plane alone (a degree-1 MLS)
};

// The local frame (origin on the reference plane, axes u, v, normal n) and the height field
// z = c0 + c1 x + c2 y + c3 x^2 + c4 xy + c5 y^2 over it, with x, y in units of H.
struct LocalPolynomial {
  Vec3d origin, u, v, n;
  double c[6] = {0, 0, 0, 0, 0, 0};
  double scale = 1;  // H
};

class MlsSurface {
 public:
  // The positions and the index stay the caller's.
  MlsSurface(std::span<const Vec3> positions, const KnnIndex& knn, const MlsSettings& settings)
      : positions_(positions), knn_(knn), s_(settings) {}

  // Algorithm 3, lines 2-3: plane and height field fitted to the K neighbours of q.
  LocalPolynomial fit(const Vec3& q, OpCounters& counters) const;
  // Line 4: the smallest t in [t0, t1] where the ray meets the height field, else +inf.
  static float intersect(const LocalPolynomial& f, const Ray& ray, float t0, float t1);
  // Unit normal of the height field at the point x (its gradient, not the reference plane's).
  static Vec3 normal(const LocalPolynomial& f, const Vec3& x);

  // Algorithm 3 from `start`, for hits with t in [t0, t1] (the chord of the ball that started
  // it). Returns t (and the normal) or +inf; with tolerance 0 it runs exactly max_iterations.
  float intersect_ray(const Ray& ray, const Vec3& start, float t0, float t1, Vec3& normal,
                      OpCounters& counters) const;

  [[nodiscard]] const MlsSettings& settings() const { return s_; }

 private:
  std::span<const Vec3> positions_;
  const KnnIndex& knn_;
  MlsSettings s_;
};

// What every MLS method prepares from positions alone: the k-NN index, the mean spacing h, a
// ball of `ball_radius` h around each point (the items a structure indexes) and the MLS surface
// with the parameters of mls_params() (methods/kernels/mls_method_params.hpp).
// The MLS parameters in mean spacings h (declared in methods/kernels/mls_method_params.hpp, with
// each method's own defaults for the iteration).
struct MlsParams {
  size_t K = 20;
  float weight_radius = 2;
  float ball_radius = 3.5f;
  float tolerance = 0;
  int max_iterations = 10;
  static ParamList<MlsParams> list(double max_iterations, double tolerance);
};

struct MlsPoints {
  std::span<const Vec3> positions;
  std::vector<float> radii;
  float h = 0, ball = 0;
  std::optional<KnnIndex> knn;
  std::optional<MlsSurface> surface;
  // Times "prepare/knn_build" and "prepare/spacing" into `timings`.
  void prepare(const PointCloud& cloud, const MlsParams& params, OpCounters& counters,
               std::map<std::string, double>& timings);
};

// The MLS leaf intersection shared by the MLS methods: every ball (item centre, radius) of the
// leaf the ray enters before the current hit starts Algorithm 3 at its centre; the nearest
// result wins. `items` are indices into `centres`; prim is the item index.
bool mls_intersect_leaf(const Ray& ray, const LeafVisit& leaf, std::span<const Vec3> centres,
                        float ball_radius, const MlsSurface& surface, Hit& hit,
                        OpCounters& counters);

}  // namespace pcrt
