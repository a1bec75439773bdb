// SPDX-License-Identifier: MIT
// fix ID group nve/euler: explicit Euler (Hoogerbrugge–Koelman) integration, docs/models.md §4.1
// (P-2; finite-step paper eqs. 1–2).
// Exact semantics: docs/fixes.md.

#ifndef DPDNL_FIX_NVE_EULER_H
#define DPDNL_FIX_NVE_EULER_H

#include "fix.h"

namespace LAMMPS_NS {

class FixNVEEuler : public Fix {
 public:
  FixNVEEuler(class LAMMPS *, int, char **);
  int setmask() override;
  void initial_integrate(int) override;
};

}    // namespace LAMMPS_NS

#endif
