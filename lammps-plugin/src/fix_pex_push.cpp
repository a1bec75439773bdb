// fix pex/push: every N steps, at end_of_step, move momentum dp along z from the fastest-v_z
// atom of slab 2 to the slowest-v_z atom of slab 1 (modified PeX, docs/models.md §4.4, P-6).
//
// Slabs: box length Lx along x, slab 1 centred at xlo + Lx/4, slab 2 at xlo + 3Lx/4, width W.
// An atom belongs to a slab when |x_w − c| < W/2, with x_w its x wrapped into [xlo, xhi).
// Selection is global over all MPI ranks: MPI_MINLOC / MPI_MAXLOC on (v_z, tag), which break
// ties by the lowest tag; the rank owning the chosen atom applies the kick. See docs/fixes.md.

#include "fix_pex_push.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "update.h"
#include "utils.h"

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
    Fix(lmp, narg, arg), dp(0.0), width(-1.0), total(0.0), exchanges(0)
{
  const std::string usage =
      "Illegal fix pex/push command: expected 'fix ID group-ID pex/push dp [width W] [every N]'";
  if (narg < 4) error->all(FLERR, usage);
  dp = utils::numeric(FLERR, arg[3], false, lmp);
  if (!(std::isfinite(dp) && dp > 0.0))
    error->all(FLERR, "Illegal fix pex/push command: dp = " + std::string(arg[3]) +
                          " must be a finite number > 0");
  nevery = 1;
  for (int iarg = 4; iarg < narg; iarg += 2) {
    const std::string key = arg[iarg];
    if (iarg + 1 >= narg)
      error->all(FLERR, "Illegal fix pex/push command: keyword '" + key + "' needs a value");
    if (key == "width") {
      width = utils::numeric(FLERR, arg[iarg + 1], false, lmp);
      if (!(std::isfinite(width) && width > 0.0))
        error->all(FLERR, "Illegal fix pex/push command: width = " + std::string(arg[iarg + 1]) +
                              " must be a finite number > 0");
    } else if (key == "every") {
      nevery = utils::inumeric(FLERR, arg[iarg + 1], false, lmp);
      if (nevery < 1)
        error->all(FLERR, "Illegal fix pex/push command: every = " + std::string(arg[iarg + 1]) +
                              " must be >= 1");
    } else {
      error->all(FLERR, "Illegal fix pex/push command: unknown keyword '" + key +
                            "' (expected width or every)");
    }
  }

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
  if (domain->dimension != 3)
    error->all(FLERR, std::string("Fix pex/push requires a 3-D system (it moves z momentum)"));
  if (domain->triclinic)
    error->all(FLERR, std::string("Fix pex/push requires an orthogonal box"));
  if (!domain->xperiodic)
    error->all(FLERR, std::string("Fix pex/push requires a periodic x boundary"));
  const double w = (width > 0.0) ? width : domain->xprd / 20.0;
  if (!(w < 0.5 * domain->xprd))
    error->all(FLERR, "Fix pex/push: width " + std::to_string(w) +
                          " must be smaller than Lx/2 = " + std::to_string(0.5 * domain->xprd));
}

void FixPexPush::end_of_step()
{
  const double lx = domain->xprd;
  const double xlo = domain->boxlo[0];
  const double xhi = domain->boxhi[0];
  const double half_w = 0.5 * ((width > 0.0) ? width : lx / 20.0);
  const double c1 = xlo + 0.25 * lx;
  const double c2 = xlo + 0.75 * lx;

  double **x = atom->x;
  double **v = atom->v;
  const tagint *tag = atom->tag;
  const int *mask = atom->mask;
  const int nlocal = atom->nlocal;

  ValueTag slow = {HUGE_VAL, MAXTAGINT};
  ValueTag fast = {-HUGE_VAL, MAXTAGINT};
  for (int i = 0; i < nlocal; i++) {
    if (!(mask[i] & groupbit)) continue;
    double xw = x[i][0];
    if (xw < xlo)
      xw += lx;
    else if (xw >= xhi)
      xw -= lx;
    const double vz = v[i][2];
    if (std::fabs(xw - c1) < half_w) {
      if (vz < slow.value || (vz == slow.value && tag[i] < slow.tag)) slow = {vz, tag[i]};
    } else if (std::fabs(xw - c2) < half_w) {
      if (vz > fast.value || (vz == fast.value && tag[i] < fast.tag)) fast = {vz, tag[i]};
    }
  }

  ValueTag gslow, gfast;
  MPI_Allreduce(&slow, &gslow, 1, MPI_DOUBLE_INT, MPI_MINLOC, world);
  MPI_Allreduce(&fast, &gfast, 1, MPI_DOUBLE_INT, MPI_MAXLOC, world);
  // An empty slab: no exchange this time (both kicks or none, so momentum is conserved).
  if (std::isinf(gslow.value) || std::isinf(gfast.value)) return;

  const double *rmass = atom->rmass;
  const double *mass = atom->mass;
  const int *type = atom->type;
  for (int i = 0; i < nlocal; i++) {
    const double m = rmass ? rmass[i] : mass[type[i]];
    if (tag[i] == gslow.tag) v[i][2] += dp / m;
    if (tag[i] == gfast.tag) v[i][2] -= dp / m;
  }
  total += dp;
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
