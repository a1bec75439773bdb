// SPDX-License-Identifier: MIT
// fix dpdnl/frames (see fix_dpdnl_frames.h). Arguments, the due steps and the file format are
// Rust (dpdnl_frames_new, dpdnl_frames_due, dpdnl_frames_write); here only the buffer, the
// reverse communication and the gather to rank 0.

#include "fix_dpdnl_frames.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "lammps_compat.h"
#include "memory.h"
#include "modify.h"
#include "update.h"

#include <cstring>
#include <string>
#include <vector>

using namespace LAMMPS_NS;

static_assert(sizeof(tagint) == sizeof(int), "fix dpdnl/frames gathers tags as MPI_INT");

FixDpdnlFrames::FixDpdnlFrames(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), frames(nullptr), owner(nullptr), claimed(0), fown(nullptr), nmax(0)
{
  if (dpdnl_frames_new(arg[1], narg - 3, arg + 3, comm->me == 0 ? 1 : 0, &frames) !=
      DPDNL_STATUS_OK)
    error->all(FLERR, std::string("Illegal fix dpdnl/frames command: ") + dpdnl_last_error());
  comm_reverse = 3;
}

FixDpdnlFrames::~FixDpdnlFrames()
{
  dpdnl_frames_free(frames);
  memory->destroy(fown);
}

int FixDpdnlFrames::setmask()
{
  return 0;
}

// Pair styles are set up before fixes (force->init, then modify->init): by now the dpdnl pair
// style of this run has claimed the fix.
void FixDpdnlFrames::init()
{
  if (claimed == 0)
    error->all(FLERR, std::string("Fix dpdnl/frames: no dpdnl pair style in this run "
                                  "(pair_style dpd/nonlinear, sdpd, ..., alone or under "
                                  "hybrid/overlay)"));
  if (claimed > 1)
    error->all(FLERR, std::string("Fix dpdnl/frames: two dpdnl pair styles under hybrid; a "
                                  "frame holds the force of one (use one dpdnl sub-style)"));
  claimed = 0;
}

void FixDpdnlFrames::claim(Pair *pair)
{
  owner = pair;
  claimed++;
}

bool FixDpdnlFrames::due(bigint step)
{
  int yes = 0;
  if (dpdnl_frames_due(frames, static_cast<int64_t>(step), &yes) != DPDNL_STATUS_OK)
    error->one(FLERR, std::string("Fix dpdnl/frames: ") + dpdnl_last_error());
  return yes != 0;
}

double *FixDpdnlFrames::begin()
{
  if (atom->nmax > nmax) {
    memory->destroy(fown);
    nmax = atom->nmax;
    memory->create(fown, nmax, 3, "dpdnl/frames:fown");
  }
  const int nall = atom->nlocal + atom->nghost;
  if (nall > 0) std::memset(&fown[0][0], 0, sizeof(double) * 3 * nall);
  return nmax > 0 ? &fown[0][0] : nullptr;
}

namespace {
// Gather `per` values per atom of every rank onto rank 0 (in rank order).
template <typename T>
std::vector<T> gather(MPI_Comm world, MPI_Datatype type, const T *mine, int n, int per,
                      const std::vector<int> &counts, int me)
{
  std::vector<int> cnt(counts.size()), disp(counts.size());
  int total = 0;
  for (size_t r = 0; r < counts.size(); r++) {
    cnt[r] = counts[r] * per;
    disp[r] = total;
    total += cnt[r];
  }
  std::vector<T> all(me == 0 ? total : 0);
  MPI_Gatherv(mine, n * per, type, all.data(), cnt.data(), disp.data(), type, 0, world);
  return all;
}
}    // namespace

void FixDpdnlFrames::finish(DpdnlPair *handle, const double *special_lj)
{
  const int nlocal = atom->nlocal;
  const int nall = nlocal + atom->nghost;
  double **f = atom->f;
  for (int i = 0; i < nall; i++)
    for (int d = 0; d < 3; d++) f[i][d] += fown[i][d];
  if (force->newton_pair) dpdnl_compat::reverse_comm_fix(comm, this);

  std::vector<double> mass(nlocal);
  for (int i = 0; i < nlocal; i++)
    mass[i] = atom->rmass_flag ? atom->rmass[i] : atom->mass[atom->type[i]];
  int nprocs = comm->nprocs;
  std::vector<int> counts(nprocs);
  MPI_Gather(&nlocal, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, world);
  const double *x = nlocal ? &atom->x[0][0] : nullptr;
  const double *v = nlocal ? &atom->v[0][0] : nullptr;
  const double *fo = nlocal ? &fown[0][0] : nullptr;
  const int me = comm->me;
  auto tag = gather<int>(world, MPI_INT, atom->tag, nlocal, 1, counts, me);
  auto type = gather<int>(world, MPI_INT, atom->type, nlocal, 1, counts, me);
  auto m = gather<double>(world, MPI_DOUBLE, mass.data(), nlocal, 1, counts, me);
  auto xa = gather<double>(world, MPI_DOUBLE, x, nlocal, 3, counts, me);
  auto va = gather<double>(world, MPI_DOUBLE, v, nlocal, 3, counts, me);
  auto fa = gather<double>(world, MPI_DOUBLE, fo, nlocal, 3, counts, me);
  if (me != 0) return;

  DpdnlFrameHead h = {};
  h.step = static_cast<int64_t>(update->ntimestep);
  h.dimension = domain->dimension;
  h.ntypes = atom->ntypes;
  h.triclinic = domain->triclinic;
  h.periodic[0] = domain->xperiodic;
  h.periodic[1] = domain->yperiodic;
  h.periodic[2] = domain->zperiodic;
  for (int k = 0; k < modify->nfix; k++)
    if (std::strcmp(modify->fix[k]->style, "nve/euler") == 0) h.euler = 1;
  h.molecular = atom->molecular != 0 ? 1 : 0;
  for (int d = 0; d < 3; d++) {
    h.boxlo[d] = domain->boxlo[d];
    h.boxhi[d] = domain->boxhi[d];
  }
  h.tilt[0] = domain->xy;
  h.tilt[1] = domain->xz;
  h.tilt[2] = domain->yz;
  h.dt = update->dt;
  h.beginstep = static_cast<int64_t>(update->beginstep);
  h.endstep = static_cast<int64_t>(update->endstep);
  for (int k = 0; k < 4; k++) h.special_lj[k] = special_lj[k];
  const int64_t n = static_cast<int64_t>(tag.size());
  if (dpdnl_frames_write(frames, handle, &h, n, tag.data(), type.data(), m.data(), xa.data(),
                         va.data(), fa.data()) != DPDNL_STATUS_OK)
    error->one(FLERR, std::string("Fix dpdnl/frames: ") + dpdnl_last_error());
}

int FixDpdnlFrames::pack_reverse_comm(int n, int first, double *buf)
{
  int m = 0;
  for (int i = first; i < first + n; i++)
    for (int d = 0; d < 3; d++) buf[m++] = fown[i][d];
  return m;
}

void FixDpdnlFrames::unpack_reverse_comm(int n, int *list, double *buf)
{
  int m = 0;
  for (int k = 0; k < n; k++)
    for (int d = 0; d < 3; d++) fown[list[k]][d] += buf[m++];
}

double FixDpdnlFrames::memory_usage()
{
  return 3.0 * nmax * sizeof(double);
}
