"""Type stubs of the extension module dpdnl._dpdnl (Rust, PyO3)."""

import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, "os.PathLike[str]"]
#: A time series: ``{"Step": steps, column: values, ...}`` (``read_series``, ``Simulation.thermo[k]``).
_Series = Mapping[str, npt.ArrayLike]
_Source = Union[_Path, _Series]

_source_root: str

class ScriptError(RuntimeError):
    """An error in a script or command; ``str(e)`` is the CLI's ``file:line: command: message``."""

    file: str
    """The input file (``<command>``, ``<commands>``, ``<run>`` for text given from Python)."""
    line: int
    """1-based line number (0 when not from a line of a file)."""
    command: str
    """The command word."""
    message: str
    """What is wrong."""

class FormatError(ValueError):
    """A file that is not in the format it was read as (names the file, line and token)."""

class AnalysisError(ValueError):
    """An analysis that cannot be done on the given data (the CLI's message)."""

class TheoryError(ValueError):
    """Parameters outside the theory's domain or an unreachable design target."""

class Simulation:
    """The standalone DPD engine, driven by commands of its LAMMPS-style script language.

    Per-atom arrays are sorted by atom id; ``thermo`` holds the thermo output of each run.
    """

    def __init__(
        self,
        dimension: int = 3,
        *,
        variables: Optional[Mapping[str, str]] = None,
        log: Optional[_Path] = None,
        threads: Optional[int] = None,
        echo: bool = False,
    ) -> None:
        """A fresh engine; ``variables`` as ``-var NAME VALUE``, ``log`` a log file, ``threads``
        the worker threads (fixed by the first Simulation that gives it), ``echo`` prints the
        output lines."""
    @staticmethod
    def from_script(
        path: _Path,
        variables: Optional[Mapping[str, str]] = None,
        *,
        log: Optional[_Path] = None,
        threads: Optional[int] = None,
        echo: bool = False,
    ) -> "Simulation":
        """Runs a script as ``dpdnl run PATH -var NAME VALUE ...`` does."""
    def command(self, text: str) -> None:
        """Runs one command (or several lines) of the script language."""
    def commands(self, lines: Sequence[str]) -> None:
        """Runs a list of commands in order."""
    def file(self, path: _Path) -> None:
        """Runs a script file in this simulation (as ``include PATH``)."""
    def run(self, n: int, upto: bool = False) -> None:
        """``run N`` (``run N upto``), with the GIL released; Ctrl-C raises KeyboardInterrupt at
        a step boundary."""
    @property
    def step(self) -> int:
        """The current time step."""
    @property
    def natoms(self) -> int:
        """Number of atoms."""
    @property
    def dimension(self) -> Optional[int]:
        """2 or 3 (None before the box exists)."""
    @property
    def dt(self) -> Optional[float]:
        """The time step (None before the box exists)."""
    @property
    def box(
        self,
    ) -> Optional[Tuple[Tuple[float, float, float], Tuple[float, float, float], Tuple[float, float, float]]]:
        """``(lo, hi, (xy, xz, yz))``, or None before the box exists."""
    @property
    def masses(self) -> List[Optional[float]]:
        """Per-type masses (index 0 unused)."""
    @property
    def ids(self) -> npt.NDArray[np.int64]:
        """Atom ids, ascending."""
    @property
    def types(self) -> npt.NDArray[np.int32]:
        """Atom types by id."""
    @property
    def positions(self) -> npt.NDArray[np.float64]:
        """Positions (N, 3) by id, wrapped as dumps write them; settable (image counters kept)."""
    @positions.setter
    def positions(self, value: npt.ArrayLike) -> None: ...
    @property
    def velocities(self) -> npt.NDArray[np.float64]:
        """Velocities (N, 3) by id; settable."""
    @velocities.setter
    def velocities(self, value: npt.ArrayLike) -> None: ...
    @property
    def forces(self) -> npt.NDArray[np.float64]:
        """Forces (N, 3) of the last evaluation, by id."""
    @property
    def unwrapped_positions(self) -> npt.NDArray[np.float64]:
        """Unwrapped positions x + image * L (N, 3) by id (dumps' ``xu yu zu``)."""
    @property
    def images(self) -> npt.NDArray[np.int32]:
        """Periodic image counters of ``positions`` (N, 3) by id (dumps' ``ix iy iz``)."""
    @property
    def output(self) -> List[str]:
        """Every line the interpreter printed."""
    @property
    def thermo(self) -> List[Dict[str, npt.NDArray[np.float64]]]:
        """One dict per run: log column name -> values."""
    @property
    def dump_files(self) -> List[str]:
        """File names of the dumps defined."""
    @property
    def threads(self) -> int:
        """Worker threads of the engine."""

# ---------------------------------------------------------------- files

def read_log(path: Optional[_Path] = None, *, text: Optional[str] = None) -> List[Dict[str, npt.NDArray[np.float64]]]:
    """Thermo blocks of a LAMMPS or dpdnl log, one dict per run."""
def read_dump(path: Optional[_Path] = None, *, text: Optional[str] = None) -> List[Dict[str, Any]]:
    """Frames of a text dump: ``step``, ``box_bounds``, ``tilt``, ``atoms`` (column -> array)."""
def read_ave_time(path: Optional[_Path] = None, *, text: Optional[str] = None) -> Dict[str, Any]:
    """A ``fix ave/time`` file (``mode`` "scalar" with ``data``, or "vector" with ``blocks``)."""
def read_ave_chunk(path: Optional[_Path] = None, *, text: Optional[str] = None) -> Dict[str, Any]:
    """A ``fix ave/chunk`` file: ``columns``, ``steps``, ``blocks``."""
def read_ave_histo(path: Optional[_Path] = None, *, text: Optional[str] = None) -> Dict[str, Any]:
    """A ``fix ave/histo`` file: ``steps``, ``blocks`` (coord, count, fraction, ...)."""
def read_series(path: Optional[_Path] = None, *, text: Optional[str] = None) -> Dict[str, npt.NDArray[np.float64]]:
    """A time series (scalar ave/time file or log): ``{"Step": ..., column: ...}``."""
def detect_kind(path: Optional[_Path] = None, *, text: Optional[str] = None) -> str:
    """"ave/time", "ave/chunk", "ave/histo", "dump" or "log"."""
def read(path: Optional[_Path] = None, *, text: Optional[str] = None) -> Any:
    """Any of the above, by the file's kind."""

# ---------------------------------------------------------------- theory (wrapped in dpdnl)

def _kinetic_theory(gamma: float, s: float, density: float, rc: float, *, kt: float = 1.0, mass: float = 1.0, dim: int = 3) -> Dict[str, float]: ...
def _design(eta: float, sc: float, density: float, rc: float, *, kt: float = 1.0, mass: float = 1.0, dim: int = 3, paper_approx: bool = False, seed: int = 12345) -> Dict[str, Any]: ...
def _theory(gamma: float, s: float, density: float, rc: float, *, kt: float = 1.0, mass: float = 1.0, dim: int = 3, dt: Optional[float] = None) -> Dict[str, Any]: ...
def _euler_temperature(gamma: float, s: float, density: float, rc: float, dt: float, *, kt: float = 1.0, mass: float = 1.0, dim: int = 3) -> Dict[str, Any]: ...

# ---------------------------------------------------------------- analysis

def mb(
    files: Optional[Union[_Path, Sequence[_Path]]] = None,
    *,
    temp: float,
    mass: float = 1.0,
    dim: Optional[int] = None,
    bins: int = 150,
    vmax: Optional[float] = None,
    from_step: int = 0,
    speeds: Optional[Sequence[npt.ArrayLike]] = None,
) -> Dict[str, Any]:
    """Speed distribution against Maxwell-Boltzmann (``dpdnl analyze mb``)."""
def mb_pdf(v: npt.ArrayLike, temp: float, *, mass: float = 1.0, dim: int = 3) -> npt.NDArray[np.float64]:
    """The Maxwell-Boltzmann speed density at each speed of ``v``."""
def nemd(
    profile: _Path,
    *,
    box: Tuple[float, float, float],
    dt: float,
    xlo: Optional[float] = None,
    dp: Optional[float] = None,
    every: int = 1,
    push: Optional[_Source] = None,
    push_col: Optional[str] = None,
    from_step: int = 0,
    fit_fraction: float = 0.5,
    vz_col: str = "vz",
    density_col: str = "density/number",
    td_col: str = "v_td",
    label: Optional[str] = None,
) -> Dict[str, Any]:
    """Reverse NEMD (PeX) viscosity (``dpdnl analyze nemd``)."""
def eh(
    source: _Source,
    *,
    dt: float,
    box: Sequence[float],
    temp: float,
    density: float,
    mass: float = 1.0,
    cols: Optional[Sequence[str]] = None,
    from_step: int = 0,
    window_factor: float = 0.1,
    tmin: Optional[float] = None,
    tmax: Optional[float] = None,
    blocks: int = 10,
) -> Dict[str, Any]:
    """Einstein-Helfand viscosity (``dpdnl analyze eh``)."""
def msd(
    source: _Source,
    *,
    dt: float,
    dim: int = 3,
    col: Optional[str] = None,
    atoms: Optional[int] = None,
    tmin: Optional[float] = None,
    tmax: Optional[float] = None,
    from_step: int = 0,
    eta: Optional[float] = None,
    eta_err: float = 0.0,
    eta_from: Optional[Union[_Path, Mapping[str, Any]]] = None,
    density: Optional[float] = None,
    mass: float = 1.0,
) -> Dict[str, Any]:
    """Self-diffusion and Schmidt number (``dpdnl analyze msd``)."""
def couette(
    source: _Source,
    *,
    col: Optional[str] = None,
    rate: Optional[float] = None,
    profile: Optional[_Path] = None,
    v_col: str = "vx",
    y_col: str = "Coord1",
    y_scale: float = 1.0,
    from_step: int = 0,
    label: Optional[str] = None,
) -> Dict[str, Any]:
    """Couette viscosity under Lees-Edwards (``dpdnl analyze couette``)."""
def flowcurve(results: Sequence[Union[_Path, Mapping[str, Any]]]) -> Dict[str, Any]:
    """Viscosity against shear rate, grouped by label (``dpdnl analyze flowcurve``)."""
