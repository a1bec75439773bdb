// SPDX-License-Identifier: MIT
// fix pex/push: every N steps, at end_of_step, move momentum dp along z from the fastest-v_z
// atom of slab 2 to the slowest-v_z atom of slab 1 (modified PeX, docs/models.md §4.4, P-6).
//
// Slabs: box length Lx along x, slab 1 centred at xlo + Lx/4, slab 2 at xlo + 3Lx/4, width W.
// An atom belongs to a slab when |x_w − c| < W/2, with x_w its x wrapped into [xlo, xhi).
// Selection is global over all MPI ranks: MPI_MINLOC / MPI_MAXLOC on (v_z, tag), which break
// ties by the lowest tag; the rank owning the chosen atom applies the kick. See docs/fixes.md.
// Arguments, box checks, the per-rank pick and the kick are Rust (dpdnl_parse_fix_pex_push,
// dpdnl_pex_box_check, dpdnl_pex_select, dpdnl_pex_apply: dpdnl::engine::fixes, as in the
// standalone engine); only the MPI reductions are here.

#include "fix_pex_push.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "update.h"
#include "utils.h"

#include "dpdnl.h"

#include <cmath>
#include <string>

using namespace LAMMPS_NS;
using namespace FixConst;

static_assert(sizeof(tagint) == sizeof(int), "fix pex/push reduces tags as MPI_DOUBLE_INT");

namespace {
// Layout of MPI_DOUBLE_INT.
struct ValueTag {
  double value;
  int tag;
};
}    // namespace

FixPexPush::FixPexPush(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), args(), total(0.0), exchanges(0)
{
  if (dpdnl_parse_fix_pex_push(domain->dimension, narg - 3, arg + 3, &args) != DPDNL_STATUS_OK)
    error->all(FLERR, std::string("Illegal fix pex/push command: ") + dpdnl_last_error());
  nevery = args.every;

  scalar_flag = 1;
  global_freq = 1;
  extscalar = 0;    // a total momentum, not normalised by the atom count in thermo output
  restart_global = 1;
  dynamic_group_allow = 1;
}

int FixPexPush::setmask()
{
  return END_OF_STEP;
}

void FixPexPush::init()
{
  if (dpdnl_pex_box_check(&args, domain->xprd, domain->triclinic, domain->xperiodic) !=
      DPDNL_STATUS_OK)
    error->all(FLERR, std::string("Fix pex/push: ") + dpdnl_last_error());
}

void FixPexPush::end_of_step()
{
  const int nlocal = atom->nlocal;
  const bool any = nlocal > 0;
  DpdnlPexPick pick;
  if (dpdnl_pex_select(&args, nlocal, any ? &atom->x[0][0] : nullptr,
                       any ? &atom->v[0][0] : nullptr, atom->tag, atom->mask, groupbit,
                       domain->boxlo[0], domain->boxhi[0], &pick) != DPDNL_STATUS_OK)
    error->one(FLERR, std::string("Fix pex/push: ") + dpdnl_last_error());

  ValueTag slow = {pick.slow_v, pick.slow_tag}, fast = {pick.fast_v, pick.fast_tag};
  ValueTag gslow, gfast;
  MPI_Allreduce(&slow, &gslow, 1, MPI_DOUBLE_INT, MPI_MINLOC, world);
  MPI_Allreduce(&fast, &gfast, 1, MPI_DOUBLE_INT, MPI_MAXLOC, world);
  // An empty slab: no exchange this time (both kicks or none, so momentum is conserved).
  if (std::isinf(gslow.value) || std::isinf(gfast.value)) return;

  if (dpdnl_pex_apply(&args, nlocal, any ? &atom->v[0][0] : nullptr, atom->tag, atom->type,
                      atom->mass, atom->rmass_flag ? atom->rmass : nullptr, gslow.tag,
                      gfast.tag) != DPDNL_STATUS_OK)
    error->one(FLERR, std::string("Fix pex/push: ") + dpdnl_last_error());
  total += args.dp;
  exchanges++;
}

double FixPexPush::compute_scalar()
{
  return total;
}

void FixPexPush::write_restart(FILE *fp)
{
  if (comm->me == 0) {
    const double list[2] = {total, static_cast<double>(exchanges)};
    const int size = sizeof(list);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list, sizeof(double), 2, fp);
  }
}

void FixPexPush::restart(char *buf)
{
  const double *list = reinterpret_cast<const double *>(buf);
  total = list[0];
  exchanges = static_cast<bigint>(list[1]);
}
