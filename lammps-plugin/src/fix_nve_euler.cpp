// fix nve/euler: from the state at t, x += dt v(t) and v += dt f(t)/m, both in
// initial_integrate; nothing in final_integrate. The forces LAMMPS computes later in the same
// step then belong to the new state (x(t+dt), v(t+dt)), which is what the next step uses.

#include "fix_nve_euler.h"

#include "atom.h"
#include "error.h"
#include "force.h"
#include "update.h"

#include <string>

using namespace LAMMPS_NS;
using namespace FixConst;

FixNVEEuler::FixNVEEuler(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
{
  if (narg != 3)
    error->all(FLERR, std::string("Illegal fix nve/euler command: expected 'fix ID group-ID "
                                  "nve/euler' (no further arguments)"));
  dynamic_group_allow = 1;
  time_integrate = 1;
}

int FixNVEEuler::setmask()
{
  return INITIAL_INTEGRATE;
}

void FixNVEEuler::initial_integrate(int /*vflag*/)
{
  const double dtv = update->dt;
  const double dtf = update->dt * force->ftm2v;
  double **x = atom->x;
  double **v = atom->v;
  double **f = atom->f;
  const double *rmass = atom->rmass;
  const double *mass = atom->mass;
  const int *type = atom->type;
  const int *mask = atom->mask;
  const int nlocal = (igroup == atom->firstgroup) ? atom->nfirst : atom->nlocal;

  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    const double dtfm = dtf / (rmass ? rmass[i] : mass[type[i]]);
    for (int k = 0; k < 3; k++) {
      x[i][k] += dtv * v[i][k];    // uses v(t): updated below
      v[i][k] += dtfm * f[i][k];
    }
  }
}
