// SPDX-License-Identifier: MIT
// The one list of the styles the LAMMPS side registers, for both builds: the launcher
// build/lmp_dpdnl (lmp_dpdnl.cpp, into LAMMPS's style maps) and the plugin dpdnlplugin.so
// (dpdnl_plugin.cpp, as plugin records). The names come from the Rust library
// (dpdnl_pair_style_*, dpdnl_lammps_style*: capi/src/pair/registry.rs); this file adds the
// C++ class of each.

#ifndef DPDNL_STYLES_H
#define DPDNL_STYLES_H

#include <string>
#include <vector>

namespace LAMMPS_NS {
class LAMMPS;
class Pair;
class Fix;
class Compute;
}    // namespace LAMMPS_NS

namespace dpdnl_styles {

using PairCreator = LAMMPS_NS::Pair *(*) (LAMMPS_NS::LAMMPS *);
using FixCreator = LAMMPS_NS::Fix *(*) (LAMMPS_NS::LAMMPS *, int, char **);
using ComputeCreator = LAMMPS_NS::Compute *(*) (LAMMPS_NS::LAMMPS *, int, char **);

// One style: its kind ("pair", "fix" or "compute"), name and the line LAMMPS prints on loading
// (the library's static strings), and the creator of its kind (the others null).
struct Style {
  const char *command;
  const char *name;
  const char *info;
  PairCreator pair;
  FixCreator fix;
  ComputeCreator compute;
};

// Every style the library lists: each pair style (the one driver PairDpdnl), then each fix and
// compute with its C++ class. An empty list and `error` set when the C++ classes and the
// library's list disagree (a name without a class, a class without a name) or the library lists
// more pair styles than this build has creators for: the caller stops LAMMPS with it.
std::vector<Style> all(std::string &error);

}    // namespace dpdnl_styles

#endif
