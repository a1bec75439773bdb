// SPDX-License-Identifier: MIT
// fix ID all dpdnl/frames N FILE: every N steps, the state a dpdnl pair style's force saw
// (positions, the velocities it used, ids, types, masses, step, box) and that style's own share
// of the force per atom, appended to FILE as one binary frame (format: dpdnl::io::frames,
// docs/manual/verify.md), for `dpdnl verify SCRIPT FILE`.
//
// The pair style (PairDpdnl) drives it: at a due step its compute() adds its force into this
// fix's zeroed buffer instead of atom->f, then calls finish(), which adds the buffer to atom->f,
// sums the ghosts' parts into their owners (newton on: reverse communication), gathers every
// atom on rank 0 and has Rust write the frame. So the velocities are those the force used (the
// half-step ones of velocity Verlet), and the force is this style's alone, whatever other
// styles (hybrid/overlay), fixes or kspace add to atom->f.

#ifndef DPDNL_FIX_DPDNL_FRAMES_H
#define DPDNL_FIX_DPDNL_FRAMES_H

#include "fix.h"

#include "dpdnl.h"

namespace LAMMPS_NS {

class FixDpdnlFrames : public Fix {
 public:
  FixDpdnlFrames(class LAMMPS *, int, char **);
  ~FixDpdnlFrames() override;
  int setmask() override;
  void init() override;

  // Called by PairDpdnl::init_style: the one dpdnl pair style whose force the frames hold.
  void claim(class Pair *pair);
  // True when the force of `step` is a frame.
  bool due(bigint step);
  // A zeroed buffer of 3 doubles per owned and ghost atom, for the style's force of a due step.
  double *begin();
  // After the style's force went into begin()'s buffer: add it to atom->f, sum the ghosts'
  // parts into their owners, and write the frame (the style's handle gives its name and
  // settings; special_lj: the factors in force during its compute).
  void finish(DpdnlPair *handle, const double *special_lj);

  int pack_reverse_comm(int, int, double *) override;
  void unpack_reverse_comm(int, int *, double *) override;
  double memory_usage() override;

 protected:
  DpdnlFrames *frames;    // period and, on rank 0, the open file (Rust)
  class Pair *owner;      // the style that claimed the fix at this init (null: none yet)
  int claimed;            // claims since the last init()
  double **fown;          // the style's force per owned and ghost atom at a due step
  int nmax;
};

}    // namespace LAMMPS_NS

#endif
