// pair_style sdpd: smoothed DPD of the weighting-function paper (docs/models.md 3.7).
//
// A thin LAMMPS driver: arguments are parsed, checked and resolved in Rust (the standalone
// engine's grammar and set-up, through an opaque DpdnlSdpd handle); the number densities and
// every force, energy and virial are computed in Rust (capi/include/dpdnl.h). This file only
// marshals arrays and does the communication between the two passes: ghost densities summed
// into their owners (reverse_comm, newton on) and the owners' densities sent to the ghosts
// (forward_comm), as pair eam does with its embedding term.
//
//   pair_style sdpd T rc seed [kernel lucy|quintic|proposed S]
//   pair_coeff I J rho0 c0 eta0 [rc]
//   pair_coeff I J rho0 c0 eta E sc S [rc R]   (eta0 and the kernel's s from targets, at init)

#ifndef DPDNL_PAIR_SDPD_H
#define DPDNL_PAIR_SDPD_H

#include "pair.h"

#include "dpdnl.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class PairSDPD : public Pair {
 public:
  PairSDPD(class LAMMPS *);
  ~PairSDPD() override;

  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;

  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;
  double memory_usage() override;
  void *extract(const char *, int &) override;

 protected:
  // The words of the pair_style line and of every pair_coeff line (replayed into a new handle
  // when pair_style is given again, as LAMMPS keeps coefficients across pair_style lines).
  std::vector<std::string> style_words;
  std::vector<std::vector<std::string>> coeff_words;
  DpdnlSdpd *handle;
  double *rho;    // number density per owned and ghost atom
  int nmax;

  void allocate();
  void make_handle();
  void apply_coeff(const std::vector<std::string> &words);
  void box_check();
  [[noreturn]] void rust_error(const std::string &context);
};

}    // namespace LAMMPS_NS

#endif
