// SPDX-License-Identifier: MIT
// compute ID all sdpd/density: the number densities of pair_style sdpd's last evaluation.
//
// Per atom: d_i (for dump custom c_ID and fix ave/chunk c_ID). Global vector of 2: the mean
// density and the relative rms fluctuation rms(d - mean)/mean (for thermo c_ID[1], c_ID[2] and
// fix ave/time). The same definitions as the standalone engine's compute (docs/input.md).

#ifndef DPDNL_COMPUTE_SDPD_DENSITY_H
#define DPDNL_COMPUTE_SDPD_DENSITY_H

#include "compute.h"

namespace LAMMPS_NS {

class ComputeSDPDDensity : public Compute {
 public:
  ComputeSDPDDensity(class LAMMPS *, int, char **);
  ~ComputeSDPDDensity() override;
  void init() override;
  void compute_vector() override;
  void compute_peratom() override;
  double memory_usage() override;

 private:
  int nmax;
  double *density;
  const double *pair_rho();
};

}    // namespace LAMMPS_NS

#endif
