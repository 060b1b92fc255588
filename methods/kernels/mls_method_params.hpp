// The parameters shared by the MLS methods (Adamson and Alexa 2003, Tejada et al. 2006/2007), and
// their conversion from units of the mean spacing h into MlsSettings.
#pragma once

#include <vector>

#include "core/params.hpp"
#include "methods/kernels/mls_surface.hpp"

namespace pcrt {

inline MlsSettings mls_settings(const MlsParams& p, float h) {
  MlsSettings s;
  s.k = p.K;
  s.weight_radius = p.weight_radius * h;
  s.tolerance = p.tolerance * h;
  s.max_iterations = p.max_iterations;
  return s;
}

}  // namespace pcrt
