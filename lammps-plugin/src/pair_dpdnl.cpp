// SPDX-License-Identifier: MIT
// The one LAMMPS driver of every dpdnl pair style (see pair_dpdnl.h).
//
// compute(): for a style with a pre-pass (info.values_per_atom = 1, sdpd's density):
// (1) dpdnl_pair_prepass sums over the half list (ghost entries too with newton on),
// (2) reverse_comm adds the ghosts' parts to their owners, dpdnl_pair_prepass_finish completes
// the owned atoms and tallies their energy, forward_comm sends every owner's value to its
// ghosts; then (3) dpdnl_pair_compute forms the forces. The pair noise is keyed by (seed, step,
// tag pair), so newton on/off and any number of MPI ranks draw the same random number for the
// same pair.
//
// LAMMPS on Debian 12 is built without C++ exceptions: an error ends the process. Errors from
// Rust come back as status codes with a message; this file turns them into error->all/one.

#include "pair_dpdnl.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix.h"
#include "fix_dpdnl_frames.h"
#include "fix_flip_momentum.h"
#include "force.h"
#include "group.h"
#include "lammps_compat.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"
#include "utils.h"

#include "dpdnl_pair_call.h"

#include <cstring>
#include <sstream>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

using namespace LAMMPS_NS;

#ifdef _OPENMP
// The team launcher of the threaded force pass (dpdnl_pair_launcher): one OpenMP parallel
// region, so that the pass runs on LAMMPS's own OpenMP threads. Built with -fopenmp against
// the OpenMP runtime LAMMPS uses (Makefile, build-plugin.sh, CMakeLists.txt); without OpenMP the pass runs
// on the Rust library's own pool, whose threads would compete for the cores with LAMMPS's
// OpenMP threads (those wait busily between their loops).
static void omp_launch(DpdnlTeamBody body, void *ctx, int32_t nthreads)
{
#pragma omp parallel num_threads(nthreads)
  body(ctx, omp_get_thread_num());
}
#endif

static_assert(sizeof(tagint) == sizeof(int32_t), "dpdnl pair styles need 32-bit tags (LAMMPS_SMALLBIG)");
static_assert(SBBITS == 30, "the C ABI reads a neighbour's special-bond class from bits 30-31");

PairDpdnl::PairDpdnl(LAMMPS *lmp, const char *style_name) :
    Pair(lmp), name(style_name), handle(nullptr), info(), values(nullptr), nmax(0), rc_max(0.0),
    own_list(0), frames(nullptr)
{
  restartinfo = 1;
  writedata = 1;
  single_enable = 0;
}

PairDpdnl::~PairDpdnl()
{
  dpdnl_pair_free(handle);
  memory->destroy(values);
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
  }
}

void PairDpdnl::rust_error(const std::string &context)
{
  error->all(FLERR, context + ": " + dpdnl_last_error());
}

void PairDpdnl::allocate()
{
  allocated = 1;
  const int n = atom->ntypes;
  memory->create(setflag, n + 1, n + 1, "pair:setflag");
  for (int i = 1; i <= n; i++)
    for (int j = i; j <= n; j++) setflag[i][j] = 0;
  memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
}

// Take `h` as the style's handle and read what it needs from this driver.
void PairDpdnl::adopt(DpdnlPair *h)
{
  if (h != handle) dpdnl_pair_free(handle);
  handle = h;
  info = dpdnl_pair_info(handle);
  single_enable = info.single;
  writedata = info.data;
  comm_forward = comm_reverse = info.values_per_atom;
}

// setflag from the handle: which type pairs have coefficients.
void PairDpdnl::sync_setflag()
{
  if (!allocated) allocate();
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) {
      double rc = 0.0;
      int set = 0;
      if (dpdnl_pair_cutoff(handle, i, j, &rc, &set) != DPDNL_STATUS_OK)
        rust_error("Pair " + name);
      setflag[i][j] = set;
    }
}

// pair_style NAME args: parsed and validated in Rust (the standalone engine's grammar); the
// same style again keeps its coefficients under the style's own rule.
void PairDpdnl::settings(int narg, char **arg)
{
  if (handle) {
    if (dpdnl_pair_settings(handle, narg, arg) != DPDNL_STATUS_OK)
      rust_error("Illegal pair_style " + name + " command");
    adopt(handle);
    if (allocated) sync_setflag();
    return;
  }
  DpdnlPair *h = nullptr;
  if (dpdnl_pair_new(name.c_str(), narg, arg, atom->ntypes, &h) != DPDNL_STATUS_OK)
    rust_error("Illegal pair_style " + name + " command");
  adopt(h);
}

// pair_coeff I J ...: parsed, validated and stored in Rust; setflag marks the pairs set.
void PairDpdnl::coeff(int narg, char **arg)
{
  if (!handle) error->all(FLERR, "Pair " + name + ": pair_coeff before pair_style");
  if (dpdnl_pair_coeff(handle, atom->ntypes, narg, arg) != DPDNL_STATUS_OK)
    rust_error("Incorrect args for pair coefficients of pair_style " + name);
  sync_setflag();
}

void PairDpdnl::init_style()
{
  if (comm->ghost_velocity == 0)
    error->all(FLERR, "Pair " + name + " requires ghost atoms store velocity: use "
                      "'comm_modify vel yes'");
  if (atom->tag_enable == 0)
    error->all(FLERR, "Pair " + name + " requires atom IDs (its noise is keyed by them)");
  if (!handle) error->all(FLERR, "Pair " + name + ": no pair_coeff given");
  bool euler = false;
  frames = nullptr;
  for (int k = 0; k < modify->nfix; k++) {
    if (strcmp(modify->fix[k]->style, "nve/euler") == 0) euler = true;
    if (strcmp(modify->fix[k]->style, "dpdnl/frames") == 0) {
      frames = dynamic_cast<FixDpdnlFrames *>(modify->fix[k]);
      if (frames) frames->claim(this);
    }
  }
  DpdnlSetup s;
  s.dimension = domain->dimension;
  s.natoms = atom->natoms;
  s.volume = domain->xprd * domain->yprd;
  if (s.dimension == 3) s.volume *= domain->zprd;
  // Both kinds of mass as the atom style has them; which one the style reads is decided in
  // Rust (per-atom where the atom style has them, as LAMMPS's own styles do).
  s.mass = atom->mass;
  s.per_atom_mass = atom->rmass_flag ? 1 : 0;
  s.dt = update->dt;
  s.euler = euler ? 1 : 0;
  // special_bonds lj: a bonded neighbour's pair scaled by its factor (or refused by a style
  // that cannot), in Rust; the list flags them in bits SBBITS.. of each entry.
  s.special_lj = force->special_lj;
  // The unit style and LAMMPS's own constants of it: T is a temperature (kT = boltz T, as for
  // pair dpd) and every conversion is done in Rust with these numbers, in every unit style.
  s.units.style = update->unit_style;
  s.units.boltz = force->boltz;
  s.units.mvv2e = force->mvv2e;
  s.units.ftm2v = force->ftm2v;
  s.units.nktv2p = force->nktv2p;
  s.units.mv2d = force->mv2d;
  // A sub-style of pair_style hybrid or hybrid/overlay: which type pairs it may leave to other
  // styles is decided in Rust. PairHybrid turns this style's list request into a skip list of
  // its own type pairs.
  s.substyle = (force->pair != this) ? 1 : 0;
  // Threads of the force pass inside this rank: LAMMPS's OpenMP threads per MPI task
  // (package omp N, -pk omp N, -sf omp, or OMP_NUM_THREADS at start-up); the same bits for
  // every count. Before the set-up, whose notes name the count.
#ifdef _OPENMP
  if (dpdnl_pair_launcher(handle, &omp_launch) != DPDNL_STATUS_OK) rust_error("Pair " + name);
#endif
  if (dpdnl_pair_threads(handle, comm->nthreads) != DPDNL_STATUS_OK) rust_error("Pair " + name);
  if (dpdnl_pair_init(handle, &s, &rc_max) != DPDNL_STATUS_OK) rust_error("Pair " + name);
  if (comm->me == 0) {
    std::istringstream notes(dpdnl_last_message());
    std::string line;
    while (std::getline(notes, line)) {
      if (line.rfind("WARNING: ", 0) == 0)
        error->warning(FLERR, line.substr(9));
      else if (!line.empty())
        utils::logmesg(lmp, line + "\n");
    }
  }
  box_check();
  add_flip_check();
  // The pair list: the style builds its own from the owned and ghost atoms (issue 44), or
  // asks LAMMPS for a half list (newton on or off as set by the 'newton' command) where it
  // needs LAMMPS's (hybrid, neigh_modify exclude) or DPDNL_PAIR_LIST=lammps says so; decided in
  // Rust.
  if (dpdnl_pair_list_choice(s.substyle, neighbor->exclude, &own_list) != DPDNL_STATUS_OK)
    rust_error("Pair " + name);
  if (!own_list) dpdnl_compat::request_half_list(neighbor, this, instance_me);
}

// The momentum that fix deform's flips leak is reported in LAMMPS as in the standalone engine
// (issue 41): a run with a fix deform and no fix flip/momentum gets one, in mode check, which
// changes nothing and warns at the end of the run (fix_flip_momentum.h).
void PairDpdnl::add_flip_check()
{
  Fix *deform = nullptr;
  for (int k = 0; k < modify->nfix; k++) {
    if (strcmp(modify->fix[k]->style, "flip/momentum") == 0) return;
    if (!deform && strncmp(modify->fix[k]->style, "deform", 6) == 0) deform = modify->fix[k];
  }
  if (!deform) return;
  modify->add_fix(std::string(FixFlipMomentum::AUTO_ID) + " " + group->names[deform->igroup] +
                  " flip/momentum mode check");
}

// The box must be at least 2 rc long along every periodic dimension (dpdnl_box_check, the
// standalone engine's rule): at every init and, under a box-changing fix, at every step.
void PairDpdnl::box_check()
{
  const double len[3] = {domain->xprd, domain->yprd, domain->zprd};
  if (dpdnl_box_check(len, domain->periodicity, domain->dimension, rc_max) != DPDNL_STATUS_OK)
    rust_error("Pair " + name);
}

double PairDpdnl::init_one(int i, int j)
{
  double rc = 0.0;
  int set = 0;
  if (dpdnl_pair_cutoff(handle, i, j, &rc, &set) != DPDNL_STATUS_OK) rust_error("Pair " + name);
  if (!set)
    error->all(FLERR, "Pair " + name + ": coefficients for types " + std::to_string(i) + " " +
                          std::to_string(j) + " are not set (this style does not mix)");
  return rc;
}

void PairDpdnl::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  if (domain->box_change) box_check();

  const bool prepass = info.values_per_atom > 0;
  dpdnl_pair_call::PairCall c =
      dpdnl_pair_call::fill(lmp, own_list ? nullptr : list, eflag_global, vflag_global,
                            eflag_atom, vflag_atom, &eng_vdwl, virial, eatom, vatom);
  const std::string where = "Pair " + name + ": ";
  if (own_list) {
    // The style's own list, built in Rust when LAMMPS has re-neighboured (ncalls) or an atom
    // has moved half the skin since; its bonded neighbours from atom->special.
    DpdnlSpecial sp = {nullptr, nullptr, 0};
    if (atom->molecular && atom->maxspecial > 0 && atom->nlocal > 0 && atom->special &&
        atom->nspecial) {
      sp.nspecial = &atom->nspecial[0][0];
      sp.special = &atom->special[0][0];
      sp.maxspecial = atom->maxspecial;
    }
    if (dpdnl_pair_own_list(handle, &c.atoms, &sp, &c.st, neighbor->ncalls, neighbor->skin,
                            &c.nl) != DPDNL_STATUS_OK)
      error->one(FLERR, where + dpdnl_last_error());
  }
  // The factors in force now: under pair_style hybrid, pair_modify pair NAME special lj sets
  // this sub-style's own around its compute (after init_style).
  if (dpdnl_pair_special(handle, force->special_lj) != DPDNL_STATUS_OK)
    error->all(FLERR, where + dpdnl_last_error());
  if (prepass) {
    if (atom->nmax > nmax) {
      memory->destroy(values);
      nmax = atom->nmax;
      memory->create(values, nmax, "pair:values");
    }
    if (dpdnl_pair_prepass(handle, &c.atoms, &c.nl, force->newton_pair, values) != DPDNL_STATUS_OK)
      error->one(FLERR, where + dpdnl_last_error());
    if (force->newton_pair) dpdnl_compat::reverse_comm_pair(comm, this);
    if (dpdnl_pair_prepass_finish(handle, &c.atoms, update->ntimestep, values, &c.tally) !=
        DPDNL_STATUS_OK)
      error->one(FLERR, where + dpdnl_last_error());
    dpdnl_compat::forward_comm_pair(comm, this);
  }
  // A step of fix dpdnl/frames: this style's force goes into the fix's zeroed buffer, which the
  // fix then adds to atom->f and writes (fix_dpdnl_frames.h).
  FixDpdnlFrames *frame = (frames && frames->due(update->ntimestep)) ? frames : nullptr;
  double *f = frame ? frame->begin() : c.f;
  if (dpdnl_pair_compute(handle, &c.atoms, &c.nl, &c.st, prepass ? values : nullptr, f,
                         &c.tally) != DPDNL_STATUS_OK)
    error->one(FLERR, where + dpdnl_last_error());
  if (frame) frame->finish(handle, force->special_lj);

  if (vflag_fdotr) virial_fdotr_compute();

  dpdnl_pair_call::check_health(lmp, c, ("Pair " + name).c_str());
}

// The conservative part of one pair, as LAMMPS's pair dpd returns it (compute pair/local,
// compute group/group, pair_write), scaled by the special-bond factor.
double PairDpdnl::single(int, int, int itype, int jtype, double rsq, double, double factor_lj,
                         double &fforce)
{
  double e = 0.0;
  if (dpdnl_pair_single(handle, itype, jtype, rsq, factor_lj, &fforce, &e) != DPDNL_STATUS_OK)
    error->one(FLERR, "Pair " + name + ": " + dpdnl_last_error());
  return e;
}

// ---------------------------------------------------------------------------------------------
// Restart: the style's own restart lines (the same as a standalone restart file stores), as
// text from Rust: int length, then that many bytes.

void PairDpdnl::write_text(FILE *fp, int settings_only)
{
  const char *data = nullptr;
  int64_t len = 0;
  if (dpdnl_pair_restart(handle, settings_only, &data, &len) != DPDNL_STATUS_OK)
    rust_error("Pair " + name + ": write_restart");
  const int n = static_cast<int>(len);
  fwrite(&n, sizeof(int), 1, fp);
  fwrite(data, sizeof(char), n, fp);
}

void PairDpdnl::read_text(FILE *fp)
{
  int n = 0;
  if (comm->me == 0) utils::sfread(FLERR, &n, sizeof(int), 1, fp, nullptr, error);
  MPI_Bcast(&n, 1, MPI_INT, 0, world);
  if (n <= 0 || n > (1 << 26)) error->all(FLERR, "Pair " + name + ": corrupt restart file");
  std::vector<char> text(n);
  if (comm->me == 0) utils::sfread(FLERR, text.data(), sizeof(char), n, fp, nullptr, error);
  MPI_Bcast(text.data(), n, MPI_CHAR, 0, world);
  DpdnlPair *h = nullptr;
  if (dpdnl_pair_from_restart(text.data(), n, atom->ntypes, &h) != DPDNL_STATUS_OK)
    rust_error("Pair " + name + ": restart file");
  adopt(h);
  sync_setflag();
}

void PairDpdnl::write_restart(FILE *fp) { write_text(fp, 0); }
void PairDpdnl::read_restart(FILE *fp) { read_text(fp); }
void PairDpdnl::write_restart_settings(FILE *fp) { write_text(fp, 1); }
void PairDpdnl::read_restart_settings(FILE *fp) { read_text(fp); }

// "Pair Coeffs" (I v...) and "PairIJ Coeffs" (I J v...): the numbers of each pair from Rust
// (read_data passes a line back to coeff() as I I v... or I J v...).
void PairDpdnl::write_data_lines(FILE *fp, bool all)
{
  double v[16];
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= (all ? atom->ntypes : i); j++) {
      int n = 0;
      if (dpdnl_pair_data(handle, i, j, v, 16, &n) != DPDNL_STATUS_OK)
        rust_error("Pair " + name + ": write_data");
      if (all)
        fprintf(fp, "%d %d", i, j);
      else
        fprintf(fp, "%d", i);
      for (int k = 0; k < n; k++) fprintf(fp, " %.17g", v[k]);
      fprintf(fp, "\n");
    }
}

void PairDpdnl::write_data(FILE *fp) { write_data_lines(fp, false); }
void PairDpdnl::write_data_all(FILE *fp) { write_data_lines(fp, true); }

// ---------------------------------------------------------------------------------------------
// The pre-pass values between the passes: ghosts' partial sums to their owners (reverse), the
// owners' completed values to their ghosts (forward).

int PairDpdnl::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/, int * /*pbc*/)
{
  for (int i = 0; i < n; i++) buf[i] = values[list[i]];
  return n;
}

void PairDpdnl::unpack_forward_comm(int n, int first, double *buf)
{
  for (int i = 0; i < n; i++) values[first + i] = buf[i];
}

int PairDpdnl::pack_reverse_comm(int n, int first, double *buf)
{
  for (int i = 0; i < n; i++) buf[i] = values[first + i];
  return n;
}

void PairDpdnl::unpack_reverse_comm(int n, int *list, double *buf)
{
  for (int i = 0; i < n; i++) values[list[i]] += buf[i];
}

double PairDpdnl::memory_usage()
{
  return static_cast<double>(nmax) * sizeof(double);
}

// "rho": the pre-pass values of the last evaluation (owned atoms first): sdpd's densities.
// "dpdnl_pair": the style's handle (DpdnlPair *), for the C ABI's questions about it
// (compute sdpd/density), answered by the top-level pair style only: PairHybrid passes the
// question on to its sub-styles, and a sub-style is not the pair style a compute reads.
void *PairDpdnl::extract(const char *str, int &dim)
{
  dim = 0;
  if (std::string(str) == "dpdnl_pair")
    return force->pair == this ? reinterpret_cast<void *>(handle) : nullptr;
  if (info.values_per_atom > 0 && std::string(str) == "rho") {
    dim = 1;
    return reinterpret_cast<void *>(values);
  }
  return nullptr;
}
