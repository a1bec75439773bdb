// fix ID group flip/momentum [mode jump|check]: `remap v`'s velocity jump for the atoms that a
// box flip of `fix deform` puts through the y boundary (issue 41; LAMMPS's fix deform leaves
// their velocities alone, which leaks momentum relative to the shear profile).
// Exact semantics: docs/manual/styles/fix_flip_momentum.md.

#ifndef DPDNL_FIX_FLIP_MOMENTUM_H
#define DPDNL_FIX_FLIP_MOMENTUM_H

#include "fix.h"

#include <vector>

namespace LAMMPS_NS {

class FixFlipMomentum : public Fix {
 public:
  FixFlipMomentum(class LAMMPS *, int, char **);
  int setmask() override;
  void init() override;
  void setup(int) override;
  void post_integrate() override;
  void post_run() override;

  // The ID of the fix that pair styles of this project add (mode check) when a run has a
  // `fix deform` and no `fix flip/momentum`, so that the leak is reported in LAMMPS as in the
  // standalone engine.
  static const char *const AUTO_ID;

 private:
  int jump;                // 1: mode jump, 0: mode check
  bool automatic;          // added by a pair style: inert where the user's own rules fail
  bool active;             // this run has a fix deform this fix works with
  Fix *deform;             // the run's fix deform, or null
  bigint crossed;          // atoms put through y at flips, this run, this rank
  double momentum;         // Σ m n h_rate_xy over them, this rank
  std::vector<int> ny;     // crossings per owned atom at a flip
};

}    // namespace LAMMPS_NS

#endif
