// SPDX-License-Identifier: MIT
// lmp_dpdnl: the stock LAMMPS executable plus the dpdnl styles, for a LAMMPS built without the
// PLUGIN package (Debian 12's liblammps). Same command line as `lmp`.
//
// Registration survives `clear`. LAMMPS keeps its style maps in Force and Modify, which
// LAMMPS::create() allocates afresh in the constructor and again in every `clear`. Both call
// sites go through the library's PLT, so this executable interposes LAMMPS::create(): its
// definition below runs the library's original (looked up with dlsym(RTLD_NEXT)) and then adds
// the dpdnl styles. The executable exports that one symbol (--export-dynamic-symbol at link
// time) so the dynamic linker binds the library's calls to it. If the interposition ever does
// not take effect (another LAMMPS build), main() notices, registers the styles once and warns
// that they will not survive `clear`.

#include "dpdnl_styles.h"

#include "dpdnl.h"

#include "error.h"
#include "force.h"
#include "input.h"
#include "lammps.h"
#include "modify.h"

#include <mpi.h>

#include <cstdio>
#include <cstdlib>
#include <dlfcn.h>
#include <string>

using namespace LAMMPS_NS;

namespace {
bool interposed = false;

// Every style of the list (dpdnl_styles.h) into the style maps of `lmp`. The maps belong to
// Force and Modify, which LAMMPS rebuilds on `clear`: called again after that.
void register_styles(LAMMPS *lmp)
{
  std::string error;
  for (const auto &s : dpdnl_styles::all(error)) {
    if (s.pair) (*lmp->force->pair_map)[s.name] = s.pair;
    if (s.fix) (*lmp->modify->fix_map)[s.name] = s.fix;
    if (s.compute) (*lmp->modify->compute_map)[s.name] = s.compute;
  }
  if (!error.empty()) lmp->error->all(FLERR, "lmp_dpdnl: " + error);
}

// True if `lmp` currently knows the library's first pair style.
bool registered(LAMMPS *lmp)
{
  return lmp->force && lmp->force->pair_map->count(dpdnl_pair_style_name(0)) == 1;
}
}    // namespace

void LAMMPS::create()
{
  using CreateFn = void (*)(LAMMPS *);
  static CreateFn original = nullptr;
  if (!original) {
    // The library's own definition (Itanium C++ ABI name of LAMMPS_NS::LAMMPS::create()).
    original = reinterpret_cast<CreateFn>(dlsym(RTLD_NEXT, "_ZN9LAMMPS_NS6LAMMPS6createEv"));
    if (!original) {
      fprintf(stderr, "lmp_dpdnl: cannot find LAMMPS::create() in liblammps: %s\n", dlerror());
      MPI_Abort(MPI_COMM_WORLD, 1);
    }
  }
  // A non-static member function called through a plain function pointer: with the Itanium
  // C++ ABI `this` is the first argument.
  original(this);
  register_styles(this);
  interposed = true;
}

int main(int argc, char **argv)
{
  MPI_Init(&argc, &argv);
  LAMMPS *lmp = new LAMMPS(argc, argv, MPI_COMM_WORLD);
  if (!interposed || !registered(lmp)) {
    register_styles(lmp);
    int me = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &me);
    if (me == 0)
      fprintf(stderr, "lmp_dpdnl: WARNING: could not hook LAMMPS::create(); the dpdnl styles "
                      "are registered once and will be lost after 'clear'\n");
  }
  lmp->input->file();
  delete lmp;
  MPI_Finalize();
  return 0;
}
