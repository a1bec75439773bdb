// pair_style sdpd: smoothed DPD of the weighting-function paper (docs/models.md 3.7).
//
// The shared driver PairDpdnl (pair_dpdnl.h) over the Rust style object: arguments, set-up,
// the number densities (the style's pre-pass, communicated between the passes as pair eam does
// with its embedding term), restart, data files and every force, energy and virial are Rust's.
//
//   pair_style sdpd T rc seed [kernel lucy|quintic|proposed S]
//   pair_coeff I J rho0 c0 eta0 [rc]
//   pair_coeff I J rho0 c0 eta E sc S [rc R]   (eta0 and the kernel's s from targets, at init)

#ifndef DPDNL_PAIR_SDPD_H
#define DPDNL_PAIR_SDPD_H

#include "pair_dpdnl.h"

namespace LAMMPS_NS {

class PairSDPD : public PairDpdnl {
 public:
  PairSDPD(class LAMMPS *lmp) : PairDpdnl(lmp, "sdpd") {}
};

}    // namespace LAMMPS_NS

#endif
