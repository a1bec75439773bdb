// pair_style sdpd: LAMMPS driver over the dpdnl C ABI (see pair_sdpd.h).
//
// compute(): (1) dpdnl_sdpd_density sums W over the half list (ghost entries too with newton
// on), (2) reverse_comm adds the ghosts' parts to their owners, dpdnl_sdpd_finish adds the self
// term and the Tait energy, forward_comm sends every owner's density to its ghosts, (3)
// dpdnl_sdpd_compute forms the forces. The pair noise is keyed by (seed, step, tag pair), so
// newton on/off and any number of MPI ranks draw the same random number for the same pair.

#include "pair_sdpd.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "lammps_compat.h"
#include "memory.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"
#include "utils.h"

#include "dpdnl.h"
#include "dpdnl_pair_call.h"

#include <sstream>

using namespace LAMMPS_NS;

PairSDPD::PairSDPD(LAMMPS *lmp) : Pair(lmp), handle(nullptr), rho(nullptr), nmax(0)
{
  restartinfo = 0;
  single_enable = 0;
  comm_forward = 1;
  comm_reverse = 1;
}

PairSDPD::~PairSDPD()
{
  dpdnl_sdpd_free(handle);
  memory->destroy(rho);
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
  }
}

void PairSDPD::rust_error(const std::string &context)
{
  error->all(FLERR, context + ": " + dpdnl_last_error());
}

void PairSDPD::allocate()
{
  allocated = 1;
  const int n = atom->ntypes;
  memory->create(setflag, n + 1, n + 1, "pair:setflag");
  for (int i = 1; i <= n; i++)
    for (int j = i; j <= n; j++) setflag[i][j] = 0;
  memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
}

static std::vector<const char *> c_words(const std::vector<std::string> &w)
{
  std::vector<const char *> p;
  for (const auto &s : w) p.push_back(s.c_str());
  return p;
}

// A handle for the current pair_style words and atom->ntypes, with every pair_coeff replayed.
void PairSDPD::make_handle()
{
  dpdnl_sdpd_free(handle);
  handle = nullptr;
  auto w = c_words(style_words);
  if (dpdnl_sdpd_new(static_cast<int>(w.size()), w.data(), MAX(atom->ntypes, 1), &handle) !=
      DPDNL_STATUS_OK)
    rust_error("Illegal pair_style sdpd command");
  for (const auto &c : coeff_words) apply_coeff(c);
}

void PairSDPD::apply_coeff(const std::vector<std::string> &words)
{
  auto w = c_words(words);
  if (dpdnl_sdpd_coeff(handle, static_cast<int>(w.size()), w.data()) != DPDNL_STATUS_OK)
    rust_error("Incorrect args for pair coefficients of pair_style sdpd");
}

// pair_style sdpd T rc seed [kernel K [S]]: parsed and validated in Rust
// (dpdnl::grammar::sdpd, the same function as the standalone engine's).
void PairSDPD::settings(int narg, char **arg)
{
  style_words.assign(arg, arg + narg);
  make_handle();
}

// pair_coeff I J rho0 c0 eta0 [rc] | I J rho0 c0 eta E sc S [rc R]: parsed and stored in
// Rust; setflag marks the pairs it set.
void PairSDPD::coeff(int narg, char **arg)
{
  if (!allocated) allocate();
  if (!handle || coeff_words.empty()) make_handle();    // atom->ntypes is known now
  std::vector<std::string> words(arg, arg + narg);
  apply_coeff(words);
  coeff_words.push_back(words);
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) {
      double rc = 0.0;
      int set = 0;
      if (dpdnl_sdpd_pair(handle, i, j, &rc, &set) != DPDNL_STATUS_OK) rust_error("Pair sdpd");
      setflag[i][j] = set;
    }
}

void PairSDPD::init_style()
{
  if (comm->ghost_velocity == 0)
    error->all(FLERR, std::string("Pair sdpd requires ghost atoms store velocity: use "
                                  "'comm_modify vel yes'"));
  if (atom->tag_enable == 0)
    error->all(FLERR, std::string("Pair sdpd requires atom IDs (its noise is keyed by them)"));
  if (atom->rmass_flag || !atom->mass)
    error->all(FLERR, std::string("Pair sdpd needs per-type masses (mass command)"));
  if (!handle) error->all(FLERR, std::string("Pair sdpd: no pair_coeff given"));
  const int dim = domain->dimension;
  double volume = domain->xprd * domain->yprd;
  if (dim == 3) volume *= domain->zprd;
  const double density = static_cast<double>(atom->natoms) / volume;
  double rc_max = 0.0;
  if (dpdnl_sdpd_init(handle, dim, density, atom->mass, update->dt, &rc_max) != DPDNL_STATUS_OK)
    rust_error("Pair sdpd");
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
  dpdnl_compat::request_half_list(neighbor, this, instance_me);
}

// The box must be at least 2 rc long along every periodic dimension (dpdnl_box_check).
void PairSDPD::box_check()
{
  double rc_max = 0.0;
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++) {
      double rc = 0.0;
      int set = 0;
      if (dpdnl_sdpd_pair(handle, i, j, &rc, &set) != DPDNL_STATUS_OK) rust_error("Pair sdpd");
      if (set) rc_max = MAX(rc_max, rc);
    }
  const double len[3] = {domain->xprd, domain->yprd, domain->zprd};
  if (dpdnl_box_check(len, domain->periodicity, domain->dimension, rc_max) != DPDNL_STATUS_OK)
    rust_error("Pair sdpd");
}

double PairSDPD::init_one(int i, int j)
{
  double rc = 0.0;
  int set = 0;
  if (dpdnl_sdpd_pair(handle, i, j, &rc, &set) != DPDNL_STATUS_OK) rust_error("Pair sdpd");
  if (!set)
    error->all(FLERR, "Pair sdpd: coefficients for types " + std::to_string(i) + " " +
                          std::to_string(j) + " are not set (this style does not mix)");
  return rc;
}

void PairSDPD::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  if (domain->box_change) box_check();
  if (atom->nmax > nmax) {
    memory->destroy(rho);
    nmax = atom->nmax;
    memory->create(rho, nmax, "pair:rho");
  }

  // Per-type masses only (sdpd refuses per-atom masses at init).
  dpdnl_pair_call::PairCall c =
      dpdnl_pair_call::fill(lmp, list, false, eflag_global, vflag_global, eflag_atom, vflag_atom,
                            &eng_vdwl, virial, eatom, vatom);

  // Pass 1: densities.
  if (dpdnl_sdpd_density(handle, &c.atoms, &c.nl, force->newton_pair, rho) != DPDNL_STATUS_OK)
    error->one(FLERR, std::string("Pair sdpd: ") + dpdnl_last_error());
  if (force->newton_pair) dpdnl_compat::reverse_comm_pair(comm, this);
  if (dpdnl_sdpd_finish(handle, &c.atoms, update->ntimestep, rho, &c.tally) != DPDNL_STATUS_OK)
    error->one(FLERR, std::string("Pair sdpd: ") + dpdnl_last_error());
  dpdnl_compat::forward_comm_pair(comm, this);

  // Pass 2: forces.
  if (dpdnl_sdpd_compute(handle, &c.atoms, &c.nl, &c.st, rho, c.f, &c.tally) != DPDNL_STATUS_OK)
    error->one(FLERR, std::string("Pair sdpd: ") + dpdnl_last_error());

  if (vflag_fdotr) virial_fdotr_compute();

  dpdnl_pair_call::check_health(lmp, c, "Pair sdpd");
}

int PairSDPD::pack_forward_comm(int n, int *list, double *buf, int /*pbc_flag*/, int * /*pbc*/)
{
  for (int i = 0; i < n; i++) buf[i] = rho[list[i]];
  return n;
}

void PairSDPD::unpack_forward_comm(int n, int first, double *buf)
{
  for (int i = 0; i < n; i++) rho[first + i] = buf[i];
}

int PairSDPD::pack_reverse_comm(int n, int first, double *buf)
{
  for (int i = 0; i < n; i++) buf[i] = rho[first + i];
  return n;
}

void PairSDPD::unpack_reverse_comm(int n, int *list, double *buf)
{
  for (int i = 0; i < n; i++) rho[list[i]] += buf[i];
}

double PairSDPD::memory_usage()
{
  return static_cast<double>(nmax) * sizeof(double);
}

// "rho": the per-atom number densities of the last evaluation (owned atoms first).
void *PairSDPD::extract(const char *name, int &dim)
{
  dim = 0;
  if (std::string(name) == "rho") {
    dim = 1;
    return reinterpret_cast<void *>(rho);
  }
  return nullptr;
}
