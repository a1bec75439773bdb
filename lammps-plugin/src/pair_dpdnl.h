// SPDX-License-Identifier: MIT
// The one LAMMPS driver of every dpdnl pair style (pair_style dpd/nonlinear, pair_style sdpd).
//
// A style is an opaque Rust handle (DpdnlPair, capi/include/dpdnl.h): the standalone engine's
// style object, with its grammar, set-up, kernel, restart lines and data coefficients. This
// class forwards narg/arg, marshals LAMMPS's arrays and neighbour list, does the MPI
// communication of a many-body style's per-atom values between its two passes (as pair eam does
// with its embedding term), and turns Rust's errors into error->all/one. It holds no
// coefficient, rule or equation, and no style's name: every style the library lists is
// registered under its name (dpdnl_styles.cpp).

#ifndef DPDNL_PAIR_DPDNL_H
#define DPDNL_PAIR_DPDNL_H

#include "pair.h"

#include "dpdnl.h"

#include <string>

namespace LAMMPS_NS {

class PairDpdnl : public Pair {
 public:
  PairDpdnl(class LAMMPS *, const char *style_name);
  ~PairDpdnl() override;

  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;
  double single(int, int, int, int, double, double, double, double &) override;

  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  void write_restart_settings(FILE *) override;
  void read_restart_settings(FILE *) override;
  void write_data(FILE *) override;
  void write_data_all(FILE *) override;

  int pack_forward_comm(int, int *, double *, int, int *) override;
  void unpack_forward_comm(int, int, double *) override;
  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;
  double memory_usage() override;
  void *extract(const char *, int &) override;

 protected:
  std::string name;      // the style's name, as LAMMPS knows it
  DpdnlPair *handle;
  DpdnlPairInfo info;    // what the style needs from this driver
  double *values;        // the pre-pass's value per owned and ghost atom (e.g. sdpd's density)
  int nmax;
  double rc_max;         // the largest cut-off, from the last init (dpdnl_pair_init)
  int own_list;          // 1: the style builds its pair list (dpdnl_pair_own_list); 0: LAMMPS's
  class FixDpdnlFrames *frames;    // fix dpdnl/frames of this run, if any

  void allocate();
  void adopt(DpdnlPair *h);
  void sync_setflag();
  void box_check();
  void add_flip_check();
  void write_text(FILE *fp, int settings_only);
  void read_text(FILE *fp);
  void write_data_lines(FILE *fp, bool all);
  [[noreturn]] void rust_error(const std::string &context);
};

}    // namespace LAMMPS_NS

#endif
