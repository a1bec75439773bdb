// SPDX-License-Identifier: MIT
#include "dpdnl_styles.h"

#include "compute_sdpd_density.h"
#include "fix_dpdnl_frames.h"
#include "fix_flip_momentum.h"
#include "fix_nve_euler.h"
#include "fix_pex_push.h"
#include "pair_dpdnl.h"

#include "dpdnl.h"

#include <array>
#include <cstring>
#include <utility>

using namespace LAMMPS_NS;
using dpdnl_styles::ComputeCreator;
using dpdnl_styles::FixCreator;
using dpdnl_styles::PairCreator;
using dpdnl_styles::Style;

namespace {

// LAMMPS's creators take no name: pair style k gets a function of its own, make_pair<k>, from
// a table of DPDNL_PAIR_STYLE_SLOTS (a constant of the Rust library, which refuses to build with
// more styles than that).
template <int K> Pair *make_pair(LAMMPS *lmp)
{
  return new PairDpdnl(lmp, dpdnl_pair_style_name(K));
}
template <int... K>
constexpr std::array<PairCreator, sizeof...(K)> pair_creators(std::integer_sequence<int, K...>)
{
  return {&make_pair<K>...};
}
constexpr auto PAIR_CREATORS = pair_creators(std::make_integer_sequence<int, DPDNL_PAIR_STYLE_SLOTS>{});

template <typename T> Fix *make_fix(LAMMPS *lmp, int narg, char **arg)
{
  return new T(lmp, narg, arg);
}
template <typename T> Compute *make_compute(LAMMPS *lmp, int narg, char **arg)
{
  return new T(lmp, narg, arg);
}

// The C++ class of each fix and compute the library lists (dpdnl_lammps_style), checked
// against that list at every load.
struct Class {
  const char *command;
  const char *name;
  FixCreator fix;
  ComputeCreator compute;
};
const Class CLASSES[] = {
    {"fix", "nve/euler", &make_fix<FixNVEEuler>, nullptr},
    {"fix", "pex/push", &make_fix<FixPexPush>, nullptr},
    {"fix", "flip/momentum", &make_fix<FixFlipMomentum>, nullptr},
    {"compute", "sdpd/density", nullptr, &make_compute<ComputeSDPDDensity>},
    {"fix", "dpdnl/frames", &make_fix<FixDpdnlFrames>, nullptr},
};

const Class *find_class(const char *command, const char *name)
{
  for (const auto &c : CLASSES)
    if (std::strcmp(c.command, command) == 0 && std::strcmp(c.name, name) == 0) return &c;
  return nullptr;
}

}    // namespace

std::vector<Style> dpdnl_styles::all(std::string &error)
{
  std::vector<Style> styles;
  const int npair = dpdnl_pair_style_count();
  if (npair > static_cast<int>(PAIR_CREATORS.size())) {
    error = "the dpdnl library lists " + std::to_string(npair) + " pair styles, but this " +
        "build has creators for " + std::to_string(PAIR_CREATORS.size()) +
        ": rebuild the LAMMPS side against the library's dpdnl.h";
    return {};
  }
  for (int k = 0; k < npair; k++)
    styles.push_back({"pair", dpdnl_pair_style_name(k), dpdnl_pair_style_info(k),
                      PAIR_CREATORS[k], nullptr, nullptr});
  const int nother = dpdnl_lammps_style_count();
  for (int k = 0; k < nother; k++) {
    const DpdnlLammpsStyle s = dpdnl_lammps_style(k);
    const Class *c = find_class(s.command, s.name);
    if (!c) {
      error = std::string("the dpdnl library lists ") + s.command + " " + s.name +
          ", which has no C++ class in this build (lammps-plugin/src/dpdnl_styles.cpp)";
      return {};
    }
    styles.push_back({s.command, s.name, s.info, nullptr, c->fix, c->compute});
  }
  for (const auto &c : CLASSES) {
    bool listed = false;
    for (int k = 0; k < nother && !listed; k++) {
      const DpdnlLammpsStyle s = dpdnl_lammps_style(k);
      listed = std::strcmp(s.command, c.command) == 0 && std::strcmp(s.name, c.name) == 0;
    }
    if (!listed) {
      error = std::string("lammps-plugin/src/dpdnl_styles.cpp has a class for ") + c.command +
          " " + c.name + ", which the dpdnl library does not list (capi/src/pair/registry.rs)";
      return {};
    }
  }
  return styles;
}
