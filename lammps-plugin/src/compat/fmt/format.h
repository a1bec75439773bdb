// SPDX-License-Identifier: MIT
// Compatibility shim for the LAMMPS 29Sep2021 headers shipped by Debian 12 (liblammps-dev).
//
// Those headers include "fmt/format.h" (not shipped: upstream LAMMPS issue 2751) and refer to
// fmt::make_args_checked, which exists in fmt 7 (the version the library embeds, as namespace
// fmt::v7_lmp) but not in Debian's libfmt-dev (fmt 9). This file shadows the header through the
// include path, pulls in the system fmt for the types the declarations name, and declares
// make_args_checked so the LAMMPS templates parse.
//
// The fmt-templated LAMMPS calls (error->all(FLERR, "fmt {}", x), utils::logmesg(lmp, "{}", x))
// can NOT be used from this code: their out-of-line halves live in liblammps.so under fmt::v7_lmp
// mangled names, which fmt 9 types cannot link against. Any such call fails at compile time
// below. Always pass a std::string (error->all(FLERR, std::string(...)) picks the non-template
// overload, which the library exports).
#ifndef DPDNL_COMPAT_FMT_FORMAT_H
#define DPDNL_COMPAT_FMT_FORMAT_H

#include_next <fmt/format.h>

namespace fmt {
template <typename... Args, typename S>
fmt::format_arg_store<fmt::format_context, Args...> make_args_checked(const S &, const Args &...)
{
  static_assert(sizeof(S) == 0,
                "dpdnl: fmt-templated LAMMPS calls cannot link against Debian's liblammps "
                "(it embeds fmt 7 as fmt::v7_lmp); pass a std::string instead");
  return {};
}
}    // namespace fmt

#endif
