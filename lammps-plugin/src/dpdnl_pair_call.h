// SPDX-License-Identifier: MIT
// The C ABI structs of one pair-style call, filled from LAMMPS's state, and the blow-up check
// after it, for the one pair driver of every style (PairDpdnl::compute adds the calls of a
// style's own passes). Marshalling only: every check and number is in Rust.

#ifndef DPDNL_PAIR_CALL_H
#define DPDNL_PAIR_CALL_H

#include "atom.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "lammps.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include "dpdnl.h"

#include <string>

namespace dpdnl_pair_call {

// Everything dpdnl_pair_compute and the pre-pass entry points read, for the owned and ghost atoms of this
// rank, its half neighbour list, the step, and the pair style's tallies.
struct PairCall {
  DpdnlAtoms atoms;
  DpdnlNeighList nl;
  DpdnlStep st;
  DpdnlTally tally;
  double *f;
};

// The masses as the atom style has them: per-atom ones (rmass) where it has them, which every
// style then reads (the choice and the checks are Rust's). The tally pointers are the Pair's own
// (eng_vdwl, virial, eatom, vatom), used when its flags ask for them.
inline PairCall fill(LAMMPS_NS::LAMMPS *lmp, LAMMPS_NS::NeighList *list, int eflag_global, int vflag_global, int eflag_atom, int vflag_atom,
                     double *eng_vdwl, double *virial, double *eatom, double **vatom)
{
  LAMMPS_NS::Atom *atom = lmp->atom;
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  const bool any = nall > 0;
  PairCall c;
  c.atoms.x = any ? &atom->x[0][0] : nullptr;
  c.atoms.v = any ? &atom->v[0][0] : nullptr;
  c.atoms.tag = atom->tag;
  c.atoms.atom_type = atom->type;
  c.atoms.mass = atom->mass;
  c.atoms.rmass = atom->rmass_flag ? atom->rmass : nullptr;
  c.atoms.nlocal = nlocal;
  c.atoms.nall = nall;

  // No list: the style builds its own (dpdnl_pair_own_list fills c.nl).
  c.nl.inum = list ? list->inum : 0;
  c.nl.ilist = list ? list->ilist : nullptr;
  c.nl.numneigh = list ? list->numneigh : nullptr;
  c.nl.firstneigh = list ? list->firstneigh : nullptr;
  c.nl.neighmask = NEIGHMASK;
  c.nl.full = 0;
  // Which build of the list this is, and the skin: Rust keeps a working copy of the list
  // between builds (DpdnlNeighList::build).
  c.nl.build = lmp->neighbor->ncalls;
  c.nl.skin = lmp->neighbor->skin;

  c.st.step = lmp->update->ntimestep;
  c.st.dt = lmp->update->dt;
  c.st.beginstep = lmp->update->beginstep;
  c.st.endstep = lmp->update->endstep;
  c.st.newton_pair = lmp->force->newton_pair;
  c.st.dimension = lmp->domain->dimension;
  LAMMPS_NS::Domain *domain = lmp->domain;
  c.st.boxlen[0] = domain->xprd;
  c.st.boxlen[1] = domain->yprd;
  c.st.boxlen[2] = domain->zprd;
  c.st.tilt[0] = domain->xy;
  c.st.tilt[1] = domain->xz;
  c.st.tilt[2] = domain->yz;
  for (int k = 0; k < 3; k++) c.st.periodic[k] = domain->periodicity[k];

  c.tally.eflag_global = eflag_global;
  c.tally.vflag_global = vflag_global;
  c.tally.eng_vdwl = eng_vdwl;
  c.tally.virial = virial;
  c.tally.eatom = eflag_atom ? eatom : nullptr;
  c.tally.vatom = (vflag_atom && any) ? &vatom[0][0] : nullptr;

  c.f = any ? &atom->f[0][0] : nullptr;
  return c;
}

// The standalone engine's blow-up check (Rust), at every neighbour rebuild and every 100 steps:
// LAMMPS itself notices only lost atoms, at thermo output. `style` names the pair style in the
// error.
inline void check_health(LAMMPS_NS::LAMMPS *lmp, const PairCall &c, const char *style)
{
  if (lmp->neighbor->ago != 0 && lmp->update->ntimestep % 100 != 0) return;
  LAMMPS_NS::Domain *domain = lmp->domain;
  const double len[3] = {domain->xprd, domain->yprd, domain->zprd};
  if (dpdnl_check_health(&c.atoms, c.f, lmp->update->ntimestep, lmp->update->dt, len,
                         domain->dimension) != DPDNL_STATUS_OK)
    lmp->error->one(FLERR, std::string(style) + ": " + dpdnl_last_error());
}

}    // namespace dpdnl_pair_call

#endif
