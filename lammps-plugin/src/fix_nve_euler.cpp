// SPDX-License-Identifier: MIT
// fix nve/euler: from the state at t, x += dt v(t) and v += dt f(t)/m, both in
// initial_integrate; nothing in final_integrate. The forces LAMMPS computes later in the same
// step then belong to the new state (x(t+dt), v(t+dt)), which is what the next step uses.
// The arguments are checked and the update is computed in Rust (dpdnl_parse_fix_integrator,
// dpdnl_euler_step: dpdnl::engine::fixes::euler_update, as in the standalone engine).

#include "fix_nve_euler.h"

#include "atom.h"
#include "error.h"
#include "force.h"
#include "update.h"

#include "dpdnl.h"

#include <string>

using namespace LAMMPS_NS;
using namespace FixConst;

FixNVEEuler::FixNVEEuler(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  if (dpdnl_parse_fix_integrator("nve/euler", narg - 3, arg + 3) != DPDNL_STATUS_OK)
    error->all(FLERR, std::string("Illegal fix nve/euler command: ") + dpdnl_last_error());
  dynamic_group_allow = 1;
  time_integrate = 1;
}

int FixNVEEuler::setmask()
{
  return INITIAL_INTEGRATE;
}

void FixNVEEuler::initial_integrate(int /*vflag*/)
{
  const int nlocal = (igroup == atom->firstgroup) ? atom->nfirst : atom->nlocal;
  const bool any = nlocal > 0;
  if (dpdnl_euler_step(nlocal, any ? &atom->x[0][0] : nullptr, any ? &atom->v[0][0] : nullptr,
                       any ? &atom->f[0][0] : nullptr, atom->type, atom->mass,
                       atom->rmass_flag ? atom->rmass : nullptr, atom->mask, groupbit, update->dt,
                       update->dt * force->ftm2v) != DPDNL_STATUS_OK)
    error->one(FLERR, std::string("Fix nve/euler: ") + dpdnl_last_error());
}
