"""dpdnl: dissipative particle dynamics with non-linear friction, from Python.

Everything that computes a number is the Rust crate's (the extension ``dpdnl._dpdnl``); this
package only moves data to and from it:

- engine: :class:`Simulation` runs the standalone engine's LAMMPS-style scripts, with NumPy
  views of the atoms and the thermo output;
- files: :func:`read_log`, :func:`read_dump`, :func:`read_ave_time`, :func:`read_ave_chunk`,
  :func:`read_ave_histo`, :func:`read_series`, :func:`read` for files of either engine;
- theory: :func:`kinetic_theory`, :func:`design`, :func:`euler_temperature`, :func:`theory`;
- analysis: :func:`mb`, :func:`nemd`, :func:`eh`, :func:`msd`, :func:`couette`,
  :func:`flowcurve` (what ``dpdnl analyze`` writes as JSON);
- LAMMPS: :func:`lammps_plugin_path`, :func:`load_into`.
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
    """The state point of an ideal DPD fluid: dimension, number density, cut-off, mass, kT."""

    dim: int
    density: float
    cutoff: float
    mass: float
    kt: float


@dataclass(frozen=True)
class Transport:
    """Kinetic-theory transport coefficients: kinetic and dissipative viscosity, their sum,
    the self-diffusion coefficient and the Schmidt number."""

    eta_k: float
    eta_d: float
    eta: float
    diffusion: float
    schmidt: float


@dataclass(frozen=True)
class DesignLimits:
    """The bounds of a design (s > 0), each with the other inputs fixed: P and P0 (the
    paper's C), the largest viscosity, the smallest Schmidt number, the gas-like window's
    upper Schmidt number (or None), the smallest density and cut-off."""

    p: float
    p0: float
    eta_max: float
    sc_min: float
    sc_gas_max: Optional[float]
    density_min: float
    cutoff_min: float


@dataclass(frozen=True)
class Design:
    """A design (``dpdnl design``): how it was obtained (``"exact"`` or ``"paper-approx"``), the
    fluid and targets, the dissipative viscosity eta0, the weight exponent ``s`` and the
    friction ``gamma``, the kinetic theory of (gamma, s), the limits, and the two input lines
    that reproduce it in both engines. :meth:`to_json` gives ``dpdnl design --json``'s object."""

    mode: str
    fluid: Fluid
    targets: Dict[str, float]
    eta0: float
    s: float
    gamma: float
    predicted: Transport
    limits: DesignLimits
    pair_style: str
    pair_coeff: str

    def to_json(self) -> Dict[str, Any]:
        """The object ``dpdnl design --json`` prints for the same arguments."""
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
    """The Euler integrator's finite-step temperature (finite-step paper eqs. 22-26): the step,
    whether it is stable, T_eq/T0 (None when unstable), the critical step dt_c and the critical
    density n_c (None when no density is stable at this step)."""

    dt: float
    stable: bool
    t_ratio: Optional[float]
    dt_c: float
    n_c: Optional[float]


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
    """Kinetic theory of the ideal DPD fluid (a = 0) with w_D = (1 - r/rc)^s for friction
    ``gamma`` (``gamma0`` of ``pair_coeff``). Raises TheoryError outside its domain."""
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
    """gamma and the weight exponent s from a target viscosity ``eta`` and Schmidt number
    ``sc`` (``dpdnl design``): the exact inversion of the kinetic theory, or with
    ``paper_approx=True`` the weighting-function paper's approximation (then ``eta`` is its
    eta0 and ``sc`` its Sc0). Raises TheoryError when the target cannot be met (the message
    names the bound to move)."""
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
    """The Euler (Hoogerbrugge-Koelman) integrator's equilibrium temperature ratio T_eq/T0 of
    the ideal fluid at step ``dt``, with the critical step and density (finite-step paper eqs.
    22-26). Velocity-Verlet has no closed form there, so none is offered."""
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
    """The object ``dpdnl theory --json`` prints: the fluid, (gamma, s), the kinetic theory
    (``predicted``) and, with ``dt``, the Euler finite-step temperature (``euler``)."""
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
    """The path of this project's LAMMPS plugin (``dpdnlplugin.so``, built by
    ``lammps-plugin/build-plugin.sh`` into ``build/``): ``$DPDNL_PLUGIN`` if set, else the first
    that exists of the package directory, ``build/`` of the repository this package was built
    from, and ``build/`` under the current directory. Raises FileNotFoundError naming the
    places searched."""
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
    """Loads the plugin into a ``lammps.lammps()`` instance (``plugin load PATH``), so that
    ``pair_style dpd/nonlinear``, ``fix nve/euler`` and ``fix pex/push`` are available in it.
    ``path`` defaults to :func:`lammps_plugin_path`. Returns the path loaded."""
    p = str(path) if path is not None else lammps_plugin_path()
    lmp.command(f"plugin load {p}")
    return p
