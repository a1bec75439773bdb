// pair_style dpd/nonlinear: DPD with non-linear (velocity-dependent) friction.
//
// A thin LAMMPS driver: arguments are parsed in Rust (dpdnl_parse_pair_style/pair_coeff, the
// standalone engine's grammar); coefficient storage, restart and data-file I/O live here; every force, energy and virial is computed in Rust through the dpdnl C ABI
// (capi/include/dpdnl.h), which walks the whole neighbour list in one call.
//
//   pair_style dpd/nonlinear T rc seed [friction none|cross|dot] [noise plain|corrected|twostep]
//                            [weight s]
//   pair_coeff I J a gamma0 gamma1 [rc]
//   pair_coeff I J a eta E sc S [gamma1 G] [rc R]   (gamma0 and s from targets, at init)

#ifndef DPDNL_PAIR_DPD_NONLINEAR_H
#define DPDNL_PAIR_DPD_NONLINEAR_H

#include "pair.h"

#include "dpdnl.h"

#include <string>


namespace LAMMPS_NS {

class PairDPDNonlinear : public Pair {
 public:
  PairDPDNonlinear(class LAMMPS *);
  ~PairDPDNonlinear() override;

  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;

  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;
  void write_data(FILE *) override;
  void write_data_all(FILE *) override;

 protected:
  // pair_style settings, parsed and validated by the Rust side (dpdnl_parse_pair_style); the
  // global cut-off is style.rc.
  DpdnlPairStyle style;

  // pair_coeff values per type pair (1-based), kept for init_one, restart and write_data.
  double **a0, **gamma0, **gamma1, **cut;
  // (eta, sc) targets per type pair (0: gamma0 given explicitly); resolved in init_style().
  double **eta_t, **sc_t;

  // The validated parameter table handed to Rust; rebuilt in init_style().
  DpdnlParams *params;

  void allocate();
  void build_params();
  void resolve_targets();
  void euler_check();
  void box_check();
  [[noreturn]] void rust_error(const std::string &context);
};

}    // namespace LAMMPS_NS

#endif
