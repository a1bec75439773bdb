// SPDX-License-Identifier: MIT
// Registration of the dpdnl styles into one LAMMPS instance.

#ifndef DPDNL_STYLES_H
#define DPDNL_STYLES_H

namespace LAMMPS_NS {
class LAMMPS;
}

// Add pair_style dpd/nonlinear, fix nve/euler and fix pex/push to the style maps of `lmp`.
// The maps belong to Force and Modify, which LAMMPS rebuilds on `clear`: call again after that.
void dpdnl_register_styles(LAMMPS_NS::LAMMPS *lmp);

// True if `lmp` currently knows pair_style dpd/nonlinear.
bool dpdnl_styles_registered(LAMMPS_NS::LAMMPS *lmp);

#endif
