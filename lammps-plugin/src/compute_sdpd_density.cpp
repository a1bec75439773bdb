// SPDX-License-Identifier: MIT
// compute sdpd/density (see compute_sdpd_density.h). The densities are pair_style sdpd's,
// computed in Rust; this file copies the owned atoms' values and does the MPI sums.

#include "compute_sdpd_density.h"

#include "dpdnl.h"

#include "atom.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "pair.h"
#include "update.h"

#include <cmath>
#include <cstring>
#include <string>

using namespace LAMMPS_NS;

ComputeSDPDDensity::ComputeSDPDDensity(LAMMPS *lmp, int narg, char **arg) :
    Compute(lmp, narg, arg), nmax(0), density(nullptr)
{
  if (narg != 3)
    error->all(FLERR, std::string("compute sdpd/density takes no argument '") +
                          (narg > 3 ? arg[3] : "") + "'; usage: compute ID all sdpd/density");
  if (std::strcmp(arg[1], "all") != 0)
    error->all(FLERR, std::string("compute sdpd/density: group '") + arg[1] +
                          "' not supported: only 'all'");
  peratom_flag = 1;
  size_peratom_cols = 0;
  vector_flag = 1;
  size_vector = 2;
  extvector = 0;
  vector = new double[2];
}

ComputeSDPDDensity::~ComputeSDPDDensity()
{
  delete[] vector;
  memory->destroy(density);
}

void ComputeSDPDDensity::init()
{
  // Any of this library's pair styles with a per-atom pre-pass (the rule of the standalone
  // engine's compute): the pair style's handle, if it is one of them ("dpdnl_pair", answered by
  // the top-level style only), asked through the C ABI; no style's name or class is tested.
  int dim = 0;
  auto *handle = force->pair ? static_cast<DpdnlPair *>(force->pair->extract("dpdnl_pair", dim))
                             : nullptr;
  if (!handle || dpdnl_pair_info(handle).values_per_atom <= 0)
    error->all(FLERR, std::string("compute sdpd/density needs pair_style sdpd (define it first)"));
}

const double *ComputeSDPDDensity::pair_rho()
{
  int dim = 0;
  void *p = force->pair ? force->pair->extract("rho", dim) : nullptr;
  if (!p || dim != 1)
    error->all(FLERR, std::string("compute sdpd/density: the pair style is no longer sdpd"));
  return static_cast<const double *>(p);
}

void ComputeSDPDDensity::compute_peratom()
{
  invoked_peratom = update->ntimestep;
  if (atom->nmax > nmax) {
    memory->destroy(density);
    nmax = atom->nmax;
    memory->create(density, nmax, "sdpd/density:density");
    vector_atom = density;
  }
  const double *rho = pair_rho();
  for (int i = 0; i < atom->nlocal; i++) density[i] = rho[i];
}

// Two passes over the owned atoms (mean, then the squared deviations), each summed over ranks.
void ComputeSDPDDensity::compute_vector()
{
  invoked_vector = update->ntimestep;
  const double *rho = pair_rho();
  const int n = atom->nlocal;
  double local = 0.0, sum = 0.0;
  for (int i = 0; i < n; i++) local += rho[i];
  MPI_Allreduce(&local, &sum, 1, MPI_DOUBLE, MPI_SUM, world);
  const double natoms = static_cast<double>(atom->natoms);
  const double mean = natoms > 0 ? sum / natoms : 0.0;
  local = 0.0;
  for (int i = 0; i < n; i++) local += (rho[i] - mean) * (rho[i] - mean);
  double dev = 0.0;
  MPI_Allreduce(&local, &dev, 1, MPI_DOUBLE, MPI_SUM, world);
  vector[0] = mean;
  vector[1] = natoms > 0 ? std::sqrt(dev / natoms) / mean : 0.0;
}

double ComputeSDPDDensity::memory_usage()
{
  return static_cast<double>(nmax) * sizeof(double);
}
