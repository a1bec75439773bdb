// pair_style dpd/nonlinear: LAMMPS driver over the dpdnl C ABI (see pair_dpd_nonlinear.h).
//
// No physics here: compute() hands positions, velocities, tags, types, masses and the
// neighbour list to dpdnl_compute(), which accumulates forces and the LAMMPS energy/virial
// tallies. The pair noise is keyed by (seed, step, tag pair), so newton on/off and any number
// of MPI ranks draw the same random number for the same pair.
//
// LAMMPS on Debian 12 is built without C++ exceptions: an error ends the process. Errors from
// Rust come back as status codes with a message; this file turns them into error->all/one.

#include "pair_dpd_nonlinear.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "lammps_compat.h"
#include "memory.h"
#include "modify.h"
#include "fix.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"
#include "utils.h"

#include "dpdnl.h"
#include "dpdnl_pair_call.h"

#include <cstring>
#include <vector>

using namespace LAMMPS_NS;

static_assert(sizeof(tagint) == sizeof(int32_t), "dpd/nonlinear needs 32-bit tags (LAMMPS_SMALLBIG)");

PairDPDNonlinear::PairDPDNonlinear(LAMMPS *lmp) :
    Pair(lmp), style(), a0(nullptr), gamma0(nullptr), gamma1(nullptr), cut(nullptr), eta_t(nullptr),
    sc_t(nullptr), params(nullptr)
{
  writedata = 1;
  restartinfo = 1;
  single_enable = 0;
}

PairDPDNonlinear::~PairDPDNonlinear()
{
  dpdnl_params_free(params);
  if (allocated) {
    memory->destroy(setflag);
    memory->destroy(cutsq);
    memory->destroy(a0);
    memory->destroy(gamma0);
    memory->destroy(gamma1);
    memory->destroy(cut);
    memory->destroy(eta_t);
    memory->destroy(sc_t);
  }
}

void PairDPDNonlinear::rust_error(const std::string &context)
{
  error->all(FLERR, context + ": " + dpdnl_last_error());
}

void PairDPDNonlinear::allocate()
{
  allocated = 1;
  const int n = atom->ntypes;
  memory->create(setflag, n + 1, n + 1, "pair:setflag");
  for (int i = 1; i <= n; i++)
    for (int j = i; j <= n; j++) setflag[i][j] = 0;
  memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
  memory->create(a0, n + 1, n + 1, "pair:a0");
  memory->create(gamma0, n + 1, n + 1, "pair:gamma0");
  memory->create(gamma1, n + 1, n + 1, "pair:gamma1");
  memory->create(cut, n + 1, n + 1, "pair:cut");
  memory->create(eta_t, n + 1, n + 1, "pair:eta_t");
  memory->create(sc_t, n + 1, n + 1, "pair:sc_t");
  for (int i = 0; i <= n; i++)
    for (int j = 0; j <= n; j++) eta_t[i][j] = sc_t[i][j] = 0.0;
}

// pair_style dpd/nonlinear T rc seed [friction F] [noise N] [weight s]: parsed and validated
// in Rust (dpdnl::grammar::pair, the same function as the standalone engine's).
void PairDPDNonlinear::settings(int narg, char **arg)
{
  if (dpdnl_parse_pair_style(narg, arg, &style) != DPDNL_STATUS_OK)
    rust_error("Illegal pair_style dpd/nonlinear command");

  // As other pair styles do: a new pair_style resets explicitly set cutoffs to the global one.
  if (allocated) {
    for (int i = 1; i <= atom->ntypes; i++)
      for (int j = i; j <= atom->ntypes; j++)
        if (setflag[i][j]) cut[i][j] = style.rc;
  }
}

// pair_coeff I J a gamma0 gamma1 [rc]
// pair_coeff I J a eta E sc S [gamma1 G] [rc R]
// Parsed and validated in Rust (dpdnl::grammar::pair), type ranges included; stored here.
void PairDPDNonlinear::coeff(int narg, char **arg)
{
  DpdnlPairCoeffLine line;
  if (dpdnl_parse_pair_coeff(&style, atom->ntypes, narg, arg, &line) != DPDNL_STATUS_OK)
    rust_error("Incorrect args for pair coefficients of pair_style dpd/nonlinear");
  if (!allocated) allocate();
  for (int i = line.ilo; i <= line.ihi; i++) {
    for (int j = MAX(line.jlo, i); j <= line.jhi; j++) {
      a0[i][j] = line.a;
      gamma0[i][j] = line.gamma0;
      gamma1[i][j] = line.gamma1;
      cut[i][j] = line.rc;
      eta_t[i][j] = line.targets ? line.eta : 0.0;
      sc_t[i][j] = line.targets ? line.sc : 0.0;
      setflag[i][j] = 1;
    }
  }
}

// Hand the current settings and coefficients to Rust (types may have been added since).
void PairDPDNonlinear::build_params()
{
  dpdnl_params_free(params);
  params = nullptr;
  if (dpdnl_params_from_style(&style, atom->ntypes, &params) != DPDNL_STATUS_OK)
    rust_error("Pair dpd/nonlinear");
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++)
      if (setflag[i][j] &&
          dpdnl_params_set_coeff(params, i, j, a0[i][j], gamma0[i][j], gamma1[i][j], cut[i][j]) !=
              DPDNL_STATUS_OK)
        rust_error("Pair dpd/nonlinear");
  if (dpdnl_params_check_complete(params) != DPDNL_STATUS_OK)
    rust_error("Pair dpd/nonlinear (no mixing: every type pair needs a pair_coeff)");
}

void PairDPDNonlinear::init_style()
{
  if (comm->ghost_velocity == 0)
    error->all(FLERR, std::string("Pair dpd/nonlinear requires ghost atoms store velocity: use "
                                  "'comm_modify vel yes'"));
  if (atom->tag_enable == 0)
    error->all(FLERR, std::string("Pair dpd/nonlinear requires atom IDs (its noise is keyed by "
                                  "them)"));
  resolve_targets();
  build_params();
  box_check();
  euler_check();
  // The default request: a half list (newton on or off as set by the 'newton' command).
  dpdnl_compat::request_half_list(neighbor, this, instance_me);
}

// The box must be at least 2 rc long along every periodic dimension (dpdnl_box_check, the
// standalone engine's rule): at every init and, under a box-changing fix, at every step.
void PairDPDNonlinear::box_check()
{
  double rc_max = 0.0;
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++)
      if (setflag[i][j]) rc_max = MAX(rc_max, cut[i][j]);
  const double len[3] = {domain->xprd, domain->yprd, domain->zprd};
  if (dpdnl_box_check(len, domain->periodicity, domain->dimension, rc_max) != DPDNL_STATUS_OK)
    rust_error("Pair dpd/nonlinear");
}

// pair_coeff ... eta E sc S: gamma0 and the weight exponent from the targets at the current
// number density (dpdnl::init::resolve_design, the same as the standalone engine).
void PairDPDNonlinear::resolve_targets()
{
  std::vector<int> ti, tj;
  std::vector<double> sv;
  const int ntypes = atom->ntypes;
  bool any = false;
  for (int i = 1; i <= ntypes; i++)
    for (int j = i; j <= ntypes; j++)
      if (setflag[i][j] && eta_t[i][j] > 0.0) any = true;
  if (!any) return;
  if (atom->rmass_flag || !atom->mass)
    error->all(FLERR, std::string("pair_coeff dpd/nonlinear eta ... sc ...: needs per-type masses"));
  const double mass = atom->mass[1];
  for (int t = 2; t <= ntypes; t++)
    if (atom->mass[t] != mass)
      error->all(FLERR, std::string("pair_coeff … eta … sc …: the kinetic theory behind the design is for one "
                        "particle mass, but the atom types have different masses"));
  const int dim = domain->dimension;
  double volume = domain->xprd * domain->yprd;
  if (dim == 3) volume *= domain->zprd;
  const double density = static_cast<double>(atom->natoms) / volume;
  for (int i = 1; i <= ntypes; i++) {
    for (int j = i; j <= ntypes; j++) {
      if (!setflag[i][j] || eta_t[i][j] <= 0.0) continue;
      double g = 0.0, s = 0.0;
      if (dpdnl_design_pair(i, j, dim, density, cut[i][j], mass, style.kt, eta_t[i][j],
                            sc_t[i][j], &g, &s) != DPDNL_STATUS_OK)
        rust_error("Pair dpd/nonlinear");
      gamma0[i][j] = g;
      if (comm->me == 0) utils::logmesg(lmp, std::string(dpdnl_last_message()) + "\n");
      ti.push_back(i);
      tj.push_back(j);
      sv.push_back(s);
    }
  }
  double s_out = style.weight_s;
  if (dpdnl_common_exponent(static_cast<int>(sv.size()), ti.data(), tj.data(), sv.data(),
                            style.weight_s, &s_out) != DPDNL_STATUS_OK)
    rust_error("Pair dpd/nonlinear");
  style.weight_s = s_out;
  const std::string note = dpdnl_last_message();
  if (comm->me == 0 && !note.empty()) utils::logmesg(lmp, note + "\n");
}

// Warn when fix nve/euler runs at a step that heats the fluid (finite-step paper eqs. 22, 25),
// with the same text as the standalone engine (dpdnl::init::euler_warning).
void PairDPDNonlinear::euler_check()
{
  bool euler = false;
  for (int k = 0; k < modify->nfix; k++)
    if (strcmp(modify->fix[k]->style, "nve/euler") == 0) euler = true;
  if (!euler || atom->natoms == 0) return;
  const int ntypes = atom->ntypes;
  double gmax = -1.0, rc = style.rc, mass = 0.0;
  bool conservative = false;
  for (int i = 1; i <= ntypes; i++)
    for (int j = i; j <= ntypes; j++) {
      if (!setflag[i][j]) continue;
      if (a0[i][j] != 0.0) conservative = true;
      if (gamma0[i][j] > gmax) {
        gmax = gamma0[i][j];
        rc = cut[i][j];
      }
    }
  if (atom->rmass_flag || !atom->mass) return;
  mass = atom->mass[1];
  for (int t = 2; t <= ntypes; t++) mass = MIN(mass, atom->mass[t]);
  const int dim = domain->dimension;
  double volume = domain->xprd * domain->yprd;
  if (dim == 3) volume *= domain->zprd;
  const double density = static_cast<double>(atom->natoms) / volume;
  if (dpdnl_euler_warning(dim, density, rc, mass, style.kt, gmax, style.weight_s, update->dt,
                          conservative ? 1 : 0, style.friction != 0 ? 1 : 0) != DPDNL_STATUS_OK)
    rust_error("Pair dpd/nonlinear (Euler step check)");
  const std::string text = dpdnl_last_message();
  if (comm->me == 0 && !text.empty()) error->warning(FLERR, text);
}

double PairDPDNonlinear::init_one(int i, int j)
{
  if (setflag[i][j] == 0)
    error->all(FLERR, "Pair dpd/nonlinear: coefficients for types " + std::to_string(i) + " " +
                          std::to_string(j) + " are not set (this style does not mix)");
  a0[j][i] = a0[i][j];
  gamma0[j][i] = gamma0[i][j];
  gamma1[j][i] = gamma1[i][j];
  cut[j][i] = cut[i][j];
  return cut[i][j];
}

void PairDPDNonlinear::compute(int eflag, int vflag)
{
  ev_init(eflag, vflag);
  if (domain->box_change) box_check();

  dpdnl_pair_call::PairCall c =
      dpdnl_pair_call::fill(lmp, list, true, eflag_global, vflag_global, eflag_atom, vflag_atom,
                            &eng_vdwl, virial, eatom, vatom);
  if (dpdnl_compute(params, &c.atoms, &c.nl, &c.st, c.f, &c.tally) != DPDNL_STATUS_OK)
    error->one(FLERR, std::string("Pair dpd/nonlinear: ") + dpdnl_last_error());

  if (vflag_fdotr) virial_fdotr_compute();

  dpdnl_pair_call::check_health(lmp, c, "Pair dpd/nonlinear");
}

// ---------------------------------------------------------------------------------------------
// Restart and data files. Binary restart layout (settings, then one record per type pair I <= J):
//   double T, double rc, bigint seed, double s, string friction, string noise
//   (a string is an int length followed by that many chars)
//   per pair: int setflag, and if set: double a, gamma0, gamma1, rc

static void write_string(FILE *fp, const std::string &s)
{
  const int n = static_cast<int>(s.size());
  fwrite(&n, sizeof(int), 1, fp);
  fwrite(s.data(), sizeof(char), n, fp);
}

static std::string read_string(FILE *fp, int me, MPI_Comm world, Error *error)
{
  int n = 0;
  if (me == 0) utils::sfread(FLERR, &n, sizeof(int), 1, fp, nullptr, error);
  MPI_Bcast(&n, 1, MPI_INT, 0, world);
  if (n < 0 || n > 64) error->all(FLERR, std::string("Pair dpd/nonlinear: corrupt restart file"));
  std::string s(n, '\0');
  if (me == 0 && n > 0) utils::sfread(FLERR, &s[0], sizeof(char), n, fp, nullptr, error);
  MPI_Bcast(&s[0], n, MPI_CHAR, 0, world);
  return s;
}

void PairDPDNonlinear::write_restart_settings(FILE *fp)
{
  const bigint seed = style.seed;
  fwrite(&style.kt, sizeof(double), 1, fp);
  fwrite(&style.rc, sizeof(double), 1, fp);
  fwrite(&seed, sizeof(bigint), 1, fp);
  fwrite(&style.weight_s, sizeof(double), 1, fp);
  write_string(fp, dpdnl_model_keyword(0, style.friction));
  write_string(fp, dpdnl_model_keyword(1, style.noise));
}

// The settings read back are parsed again by the same grammar as a pair_style line.
void PairDPDNonlinear::read_restart_settings(FILE *fp)
{
  const int me = comm->me;
  double kt = 0.0, rc = 0.0, s = 0.0;
  bigint seed = 0;
  if (me == 0) {
    utils::sfread(FLERR, &kt, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, &rc, sizeof(double), 1, fp, nullptr, error);
    utils::sfread(FLERR, &seed, sizeof(bigint), 1, fp, nullptr, error);
    utils::sfread(FLERR, &s, sizeof(double), 1, fp, nullptr, error);
  }
  MPI_Bcast(&kt, 1, MPI_DOUBLE, 0, world);
  MPI_Bcast(&rc, 1, MPI_DOUBLE, 0, world);
  MPI_Bcast(&seed, 1, MPI_LMP_BIGINT, 0, world);
  MPI_Bcast(&s, 1, MPI_DOUBLE, 0, world);
  const std::string friction = read_string(fp, me, world, error);
  const std::string noise = read_string(fp, me, world, error);
  char buf[4][32];
  snprintf(buf[0], sizeof(buf[0]), "%.17g", kt);
  snprintf(buf[1], sizeof(buf[1]), "%.17g", rc);
  snprintf(buf[2], sizeof(buf[2]), BIGINT_FORMAT, seed);
  snprintf(buf[3], sizeof(buf[3]), "%.17g", s);
  const char *words[9] = {buf[0],     buf[1],  buf[2], "friction", friction.c_str(),
                          "noise", noise.c_str(), "weight", buf[3]};
  if (dpdnl_parse_pair_style(9, words, &style) != DPDNL_STATUS_OK)
    rust_error("Pair dpd/nonlinear: restart file settings");
}

void PairDPDNonlinear::write_restart(FILE *fp)
{
  write_restart_settings(fp);
  for (int i = 1; i <= atom->ntypes; i++) {
    for (int j = i; j <= atom->ntypes; j++) {
      fwrite(&setflag[i][j], sizeof(int), 1, fp);
      if (setflag[i][j]) {
        fwrite(&a0[i][j], sizeof(double), 1, fp);
        fwrite(&gamma0[i][j], sizeof(double), 1, fp);
        fwrite(&gamma1[i][j], sizeof(double), 1, fp);
        fwrite(&cut[i][j], sizeof(double), 1, fp);
      }
    }
  }
}

void PairDPDNonlinear::read_restart(FILE *fp)
{
  read_restart_settings(fp);
  allocate();
  const int me = comm->me;
  for (int i = 1; i <= atom->ntypes; i++) {
    for (int j = i; j <= atom->ntypes; j++) {
      if (me == 0) utils::sfread(FLERR, &setflag[i][j], sizeof(int), 1, fp, nullptr, error);
      MPI_Bcast(&setflag[i][j], 1, MPI_INT, 0, world);
      if (setflag[i][j]) {
        if (me == 0) {
          utils::sfread(FLERR, &a0[i][j], sizeof(double), 1, fp, nullptr, error);
          utils::sfread(FLERR, &gamma0[i][j], sizeof(double), 1, fp, nullptr, error);
          utils::sfread(FLERR, &gamma1[i][j], sizeof(double), 1, fp, nullptr, error);
          utils::sfread(FLERR, &cut[i][j], sizeof(double), 1, fp, nullptr, error);
        }
        MPI_Bcast(&a0[i][j], 1, MPI_DOUBLE, 0, world);
        MPI_Bcast(&gamma0[i][j], 1, MPI_DOUBLE, 0, world);
        MPI_Bcast(&gamma1[i][j], 1, MPI_DOUBLE, 0, world);
        MPI_Bcast(&cut[i][j], 1, MPI_DOUBLE, 0, world);
      }
    }
  }
}

// "Pair Coeffs" section: I a gamma0 gamma1 rc (read_data passes it to coeff() as I I ...).
void PairDPDNonlinear::write_data(FILE *fp)
{
  for (int i = 1; i <= atom->ntypes; i++)
    fprintf(fp, "%d %.17g %.17g %.17g %.17g\n", i, a0[i][i], gamma0[i][i], gamma1[i][i],
            cut[i][i]);
}

// "PairIJ Coeffs" section: I J a gamma0 gamma1 rc.
void PairDPDNonlinear::write_data_all(FILE *fp)
{
  for (int i = 1; i <= atom->ntypes; i++)
    for (int j = i; j <= atom->ntypes; j++)
      fprintf(fp, "%d %d %.17g %.17g %.17g %.17g\n", i, j, a0[i][j], gamma0[i][j], gamma1[i][j],
              cut[i][j]);
}
