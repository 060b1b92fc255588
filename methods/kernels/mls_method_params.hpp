// The parameters shared by the MLS methods (Adamson and Alexa 2003, Tejada et al. 2006/2007), and
// their conversion from units of the mean spacing h into MlsSettings.
#pragma once

#include <vector>

#include "core/params.hpp"
#include "methods/kernels/mls_surface.hpp"

namespace pcrt {

inline std::vector<ParamSpec> mls_params(double max_iterations, double tolerance) {
  return {{"K", 20, 6, double(kMaxMlsNeighbours), "neighbours in each MLS fit", true},
          {"weight_radius", 2.0, 0.25, 50, "H of the Gaussian weight exp(-d^2/H^2), in h"},
          {"ball_radius", 3.5, 0.5, 50,
           "radius of the ball around each point that starts an MLS run, in h"},
          {"tolerance", tolerance, 0, 100,
           "stop when the hit point moves less than this, in h (0: always run max_iterations)"},
          {"max_iterations", max_iterations, 1, 100, "cap on the MLS iterations I per run", true}};
}

inline MlsSettings mls_settings(const ParamValues& p, float h) {
  MlsSettings s;
  s.k = size_t(p.at("K"));
  s.weight_radius = float(p.at("weight_radius")) * h;
  s.tolerance = float(p.at("tolerance")) * h;
  s.max_iterations = int(p.at("max_iterations"));
  return s;
}

}  // namespace pcrt
