// pair_style dpd/nonlinear: DPD with non-linear (velocity-dependent) friction.
//
// The shared driver PairDpdnl (pair_dpdnl.h) over the Rust style object: arguments, set-up,
// restart, data files and every force, energy and virial are Rust's (capi/include/dpdnl.h).
//
//   pair_style dpd/nonlinear T rc seed [friction none|cross|dot] [noise plain|corrected|twostep]
//                            [weight s]
//   pair_coeff I J a gamma0 gamma1 [rc]
//   pair_coeff I J a eta E sc S [gamma1 G] [rc R]   (gamma0 and s from targets, at init)

#ifndef DPDNL_PAIR_DPD_NONLINEAR_H
#define DPDNL_PAIR_DPD_NONLINEAR_H

#include "pair_dpdnl.h"

namespace LAMMPS_NS {

class PairDPDNonlinear : public PairDpdnl {
 public:
  PairDPDNonlinear(class LAMMPS *lmp) : PairDpdnl(lmp, "dpd/nonlinear") {}
};

}    // namespace LAMMPS_NS

#endif
