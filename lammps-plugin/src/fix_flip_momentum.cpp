// fix flip/momentum: at the step of a box flip (fix deform's next_reneighbor is that step), in
// post_integrate, before fix deform's pre_exchange flips and remaps, every owned atom of the
// deformed group outside the box along y is put through y with remap v's velocity jump, as
// Domain::pbc would, so the momentum relative to the shear profile is conserved. `mode check`
// only counts. Either way the atoms put through y and the momentum they change are reported at
// the end of the run (post_run). The rules, the wrap and the warning text are Rust
// (dpdnl_parse_fix_flip_momentum, dpdnl_flip_momentum_setup, dpdnl_flip_wrap,
// dpdnl_flip_leak_warning: dpdnl::engine::lees_edwards, as in the standalone engine); this
// file marshals arrays, moves image flags and reduces over ranks.

#include "fix_flip_momentum.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "group.h"
#include "modify.h"
#include "update.h"
#include "utils.h"

#include "dpdnl.h"

#include <cstring>
#include <mpi.h>
#include <string>

using namespace LAMMPS_NS;
using namespace FixConst;

const char *const FixFlipMomentum::AUTO_ID = "DPDNL_FLIP_CHECK";

FixFlipMomentum::FixFlipMomentum(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), jump(1), automatic(false), active(false), deform(nullptr), crossed(0),
    momentum(0.0)
{
  if (dpdnl_parse_fix_flip_momentum(narg - 3, arg + 3, &jump) != DPDNL_STATUS_OK)
    error->all(FLERR, std::string("Illegal fix flip/momentum command: ") + dpdnl_last_error());
  automatic = strcmp(id, AUTO_ID) == 0;
}

int FixFlipMomentum::setmask()
{
  return POST_INTEGRATE;
}

void FixFlipMomentum::init()
{
  crossed = 0;
  momentum = 0.0;
  deform = nullptr;
  bool other = false;    // another flip/momentum (the user's, beside an automatic one)
  for (int i = 0; i < modify->nfix; i++) {
    Fix *f = modify->fix[i];
    if (strncmp(f->style, "deform", 6) == 0 && !deform) deform = f;
    if (f != this && strcmp(f->style, "flip/momentum") == 0) other = true;
  }
  active = !(automatic && other);
}

// The rules need fix deform's h_rate, which its own init sets: checked once every fix is
// initialised.
void FixFlipMomentum::setup(int /*vflag*/)
{
  if (!active) return;
  const double *h = domain->h_rate;
  const int xy_only = domain->xz == 0.0 && domain->yz == 0.0 && h[0] == 0.0 && h[1] == 0.0 &&
      h[2] == 0.0 && h[3] == 0.0 && h[4] == 0.0;
  const int status = dpdnl_flip_momentum_setup(deform ? deform->id : nullptr,
                                               domain->deform_vremap,
                                               deform && deform->igroup == igroup, xy_only);
  if (status == DPDNL_STATUS_OK) return;
  // The automatic instance stays out of runs it does not fit (another group, other tilts).
  if (automatic)
    active = false;
  else
    error->all(FLERR, std::string("Fix flip/momentum: ") + dpdnl_last_error());
}

void FixFlipMomentum::post_integrate()
{
  if (!active || !deform || deform->next_reneighbor != update->ntimestep) return;
  const int nlocal = atom->nlocal;
  ny.assign(nlocal > 0 ? nlocal : 1, 0);
  const bool any = nlocal > 0;
  if (dpdnl_flip_wrap(nlocal, any ? &atom->x[0][0] : nullptr, any ? &atom->v[0][0] : nullptr,
                      atom->type, atom->mass, atom->rmass_flag ? atom->rmass : nullptr,
                      atom->mask, deform->groupbit, domain->boxlo[1], domain->boxhi[1],
                      domain->xy, domain->h_rate[5], jump, ny.data(), &crossed,
                      &momentum) != DPDNL_STATUS_OK)
    error->one(FLERR, std::string("Fix flip/momentum: ") + dpdnl_last_error());
  if (!jump) return;
  // The y image flag of an atom put through y by n boxes grows by n (Domain::pbc's rule).
  imageint *image = atom->image;
  for (int i = 0; i < nlocal; i++) {
    if (ny[i] == 0) continue;
    const imageint im = image[i];
    const imageint xbox = im & IMGMASK;
    const imageint zbox = (im >> IMG2BITS) & IMGMASK;
    const imageint ybox = (((im >> IMGBITS) & IMGMASK) + ny[i]) & IMGMASK;
    image[i] = xbox | (ybox << IMGBITS) | (zbox << IMG2BITS);
  }
}

void FixFlipMomentum::post_run()
{
  if (!active) return;
  bigint all_crossed = 0;
  double all_momentum = 0.0;
  MPI_Allreduce(&crossed, &all_crossed, 1, MPI_LMP_BIGINT, MPI_SUM, world);
  MPI_Allreduce(&momentum, &all_momentum, 1, MPI_DOUBLE, MPI_SUM, world);
  if (all_crossed == 0) return;
  const double total_mass = deform ? group->mass(deform->igroup) : 0.0;
  if (dpdnl_flip_leak_warning(all_crossed, all_momentum, jump, total_mass) != DPDNL_STATUS_OK)
    error->all(FLERR, std::string("Fix flip/momentum: ") + dpdnl_last_error());
  const std::string text = dpdnl_last_message();
  if (comm->me != 0 || text.empty()) return;
  if (text.rfind("WARNING: ", 0) == 0)
    error->warning(FLERR, text.substr(9));
  else
    utils::logmesg(lmp, text + "\n");
}
