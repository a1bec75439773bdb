// SPDX-License-Identifier: MIT
#include "dpdnl_styles.h"

#include "compute_sdpd_density.h"
#include "fix_flip_momentum.h"
#include "fix_nve_euler.h"
#include "fix_pex_push.h"
#include "pair_dpdnl.h"

#include "force.h"
#include "lammps.h"
#include "modify.h"

using namespace LAMMPS_NS;

namespace {
template <typename T> Fix *make_fix(LAMMPS *lmp, int narg, char **arg)
{
  return new T(lmp, narg, arg);
}
template <typename T> Compute *make_compute(LAMMPS *lmp, int narg, char **arg)
{
  return new T(lmp, narg, arg);
}
}    // namespace

void dpdnl_register_styles(LAMMPS *lmp)
{
  for (int k = 0; k < dpdnl_pair_styles(); k++)
    (*lmp->force->pair_map)[dpdnl_pair_style_name(k)] = dpdnl_pair_creator(k);
  (*lmp->modify->fix_map)["nve/euler"] = &make_fix<FixNVEEuler>;
  (*lmp->modify->fix_map)["pex/push"] = &make_fix<FixPexPush>;
  (*lmp->modify->fix_map)["flip/momentum"] = &make_fix<FixFlipMomentum>;
  (*lmp->modify->compute_map)["sdpd/density"] = &make_compute<ComputeSDPDDensity>;
}

bool dpdnl_styles_registered(LAMMPS *lmp)
{
  // Registered when the registry's first style is in LAMMPS's map (no style named here).
  return lmp->force && lmp->force->pair_map->count(dpdnl_pair_style_name(0)) == 1;
}
