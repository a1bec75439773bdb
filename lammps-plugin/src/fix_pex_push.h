// SPDX-License-Identifier: MIT
// fix ID group pex/push dp [width W] [every N]: the modified PeX momentum exchange of reverse
// non-equilibrium MD (docs/models.md §4.4, P-6). Exact semantics: docs/fixes.md.

#ifndef DPDNL_FIX_PEX_PUSH_H
#define DPDNL_FIX_PEX_PUSH_H

#include "fix.h"

#include "dpdnl.h"

namespace LAMMPS_NS {

class FixPexPush : public Fix {
 public:
  FixPexPush(class LAMMPS *, int, char **);
  int setmask() override;
  void init() override;
  void end_of_step() override;
  double compute_scalar() override;
  void write_restart(FILE *) override;
  void restart(char *) override;

 protected:
  DpdnlPexArgs args;  // dp, width (0: the default Lx/20), every; parsed in Rust
  double total;       // momentum moved so far (the fix's scalar)
  bigint exchanges;   // number of exchanges done so far
};

}    // namespace LAMMPS_NS

#endif
