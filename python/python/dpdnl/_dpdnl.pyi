"""Type stubs of the extension module dpdnl._dpdnl (Rust, PyO3).

The docstrings here are the reference (scripts/pyref.py renders them into
docs/manual/python-api.md); the Rust functions carry the same text as their ``__doc__``, which
python/tests/test_docs.py checks, and it runs every example.
"""

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
    """An error in a script or command: ``str(e)`` is the CLI's ``file:line: command: message``.

    Example:
        >>> sim = dpdnl.Simulation()
        >>> try:
        ...     sim.commands(["units lj", "frobnicate 1 2"])
        ... except dpdnl.ScriptError as e:
        ...     print(e.file, e.line, e.command)
        <commands> 2 frobnicate
    """

    file: str
    """The input file (``<command>``, ``<commands>``, ``<run>`` for text given from Python)."""
    line: int
    """1-based line number (0 when not from a line of a file)."""
    command: str
    """The command word."""
    message: str
    """What is wrong."""

class FormatError(ValueError):
    """A file that is not in the format it was read as; the message names the file, the line
    and the offending token, as the CLI's.

    Example:
        >>> try:
        ...     dpdnl.read_ave_chunk(text="# Chunk Coord1 Ncount vz\\n1000 2 x\\n")
        ... except dpdnl.FormatError:
        ...     print("not an ave/chunk file")
        not an ave/chunk file
    """

class AnalysisError(ValueError):
    """An analysis that cannot be done on the given data (the message is the CLI's).

    Example:
        >>> try:
        ...     dpdnl.couette({"Step": [0, 10], "temp": [1.0, 1.0]}, rate=0.1)
        ... except dpdnl.AnalysisError:
        ...     print("no pxy column")
        no pxy column
    """

class TheoryError(ValueError):
    """Parameters outside the kinetic theory's domain, or a design target that cannot be met
    (the message says which bound to move, as the CLI's).

    Example:
        >>> try:
        ...     dpdnl.design(eta=3.0, sc=0.4, density=4.0, rc=1.0)
        ... except dpdnl.TheoryError:
        ...     print("Sc <= 1/2 is impossible")
        Sc <= 1/2 is impossible
    """

class Simulation:
    """The standalone DPD engine, driven by commands of its LAMMPS-style script language
    (``units lj`` by default: mass m, distance σ, energy ε, time τ, k_B = 1; ``units real`` and
    ``metal`` as in LAMMPS).

    ``Simulation(dimension=3)`` starts empty, as a script before its first line;
    :meth:`from_script` runs a script as ``dpdnl run PATH -var NAME VALUE`` does. Then
    :meth:`command`, :meth:`commands`, :meth:`file` and :meth:`run` issue more commands, with
    the same bits as the CLI. Per-atom arrays are copies sorted by atom id; ``thermo`` holds the
    thermo output of each run. The examples of the methods continue this one (``sim``).

    Example:
        >>> sim = dpdnl.Simulation()
        >>> sim.commands([
        ...     "region box block 0 5 0 5 0 5", "create_box 1 box",
        ...     "create_atoms 1 random 375 8675 box", "mass 1 1.0",
        ...     "velocity all create 1.0 4928 mom yes",
        ...     "pair_style dpd/nonlinear 1.0 1.0 7919 friction cross",
        ...     "pair_coeff * * 25.0 4.5 0.5",
        ...     "fix 1 all nve", "timestep 0.01",
        ...     "thermo 50", "thermo_style custom step temp press pxy",
        ... ])
        >>> sim.run(100)
        >>> sim.step, sim.natoms, sim.positions.shape
        (100, 375, (375, 3))
        >>> sim.thermo[-1]["Step"].tolist()
        [0.0, 50.0, 100.0]
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
        """A fresh engine, with no box yet.

        Args:
            dimension: 2 or 3 (the ``dimension`` command).
            variables: index-style variables, name → value, as ``-var NAME VALUE`` on the
                command line; None: none.
            log: path of a log file to write, as ``-log``; None: no log file.
            threads: worker threads of the engine; None: ``RAYON_NUM_THREADS``, else all
                cores. The results are the same bits for any number. The first Simulation of
                the process that gives a number fixes it; a different number later raises
                ValueError.
            echo: also print every output line to standard output.
        """
    @staticmethod
    def from_script(
        path: _Path,
        variables: Optional[Mapping[str, str]] = None,
        *,
        log: Optional[_Path] = None,
        threads: Optional[int] = None,
        echo: bool = False,
    ) -> "Simulation":
        """Runs a script as ``dpdnl run PATH -var NAME VALUE …`` does.

        Paths inside the script are relative to the current directory, as in LAMMPS.

        Args:
            path: the input script.
            variables: index-style variables, name → value (``-var NAME VALUE``); None: none.
            log: path of a log file to write; None: no log file.
            threads: worker threads, as for ``Simulation()``.
            echo: also print every output line to standard output.

        Returns:
            The simulation in the state the script left it.

        Raises:
            ScriptError: a command of the script is wrong (file and line of the script).
            OSError: the script cannot be read.

        Example:
            >>> with open("in.short", "w") as f:
            ...     _ = f.write("\\n".join([
            ...         "region box block 0 4 0 4 0 4", "create_box 1 box",
            ...         "create_atoms 1 random 192 1234 box", "mass 1 1.0",
            ...         "velocity all create 1.0 87287 mom yes",
            ...         "pair_style dpd/nonlinear 1.0 1.0 4242", "pair_coeff * * 25.0 4.5 0.0",
            ...         "fix 1 all nve", "timestep 0.01", "run ${n}"]))
            >>> s = dpdnl.Simulation.from_script("in.short", {"n": "20"})
            >>> s.step
            20
        """
    def command(self, text: str) -> None:
        """Runs one command, or several lines, of the script language.

        Args:
            text: the command line(s), as in a script.

        Raises:
            ScriptError: the command is wrong (file ``<command>``, the line within ``text``).

        Example:
            >>> sim.command("thermo_style custom step temp ke pe")
            >>> sim.command("run 10")
            >>> sorted(sim.thermo[-1])
            ['KinEng', 'PotEng', 'Step', 'Temp']
        """
    def commands(self, lines: Sequence[str]) -> None:
        """Runs a list of commands in order, as the lines of one script named ``<commands>``.

        Args:
            lines: the commands, one per item.

        Raises:
            ScriptError: a command is wrong (file ``<commands>``, its 1-based position).

        Example:
            >>> sim.commands(["variable n equal 10", "run ${n}"])
            >>> sim.step
            120
        """
    def file(self, path: _Path) -> None:
        """Runs a script file in this simulation, as ``include PATH`` does.

        Args:
            path: the script; paths inside it are relative to the current directory.

        Raises:
            ScriptError: a command of the file is wrong (its file and line).
            OSError: the file cannot be read.

        Example:
            >>> with open("more.in", "w") as f:
            ...     _ = f.write("thermo 5\\nrun 10\\n")
            >>> sim.file("more.in")
            >>> sim.step
            130
        """
    def run(self, n: int, upto: bool = False) -> None:
        """Runs ``n`` steps: the ``run N`` command (``upto=True``: ``run N upto``).

        The GIL is released while it runs. Ctrl-C stops it at a step boundary with
        KeyboardInterrupt, the system left as it was after that step, so it can go on.

        Args:
            n: number of steps, or with ``upto`` the step to run to.
            upto: run up to step ``n`` instead of ``n`` more steps.

        Raises:
            ScriptError: the run cannot start (no box, no pair style, …).
            KeyboardInterrupt: Ctrl-C during the run.

        Example:
            >>> sim.run(200, upto=True)
            >>> sim.step
            200
        """
    @property
    def step(self) -> int:
        """The current time step number."""
    @property
    def natoms(self) -> int:
        """Number of atoms."""
    @property
    def dimension(self) -> Optional[int]:
        """The dimension of the box, 2 or 3 (None before the box exists)."""
    @property
    def dt(self) -> Optional[float]:
        """The time step δt, time units (lj: τ); None before the box exists."""
    @property
    def box(
        self,
    ) -> Optional[Tuple[Tuple[float, float, float], Tuple[float, float, float], Tuple[float, float, float]]]:
        """``(lo, hi, (xy, xz, yz))``: the box bounds and the tilt factors as thermo and dumps report them (all 0 for an orthogonal box), distance units (lj: σ); None before the box exists."""
    @property
    def masses(self) -> List[Optional[float]]:
        """Per-type masses, mass units (lj: m); index 0 unused, None for a type without a mass."""
    @property
    def ids(self) -> npt.NDArray[np.int64]:
        """Atom ids, ascending (int64)."""
    @property
    def types(self) -> npt.NDArray[np.int32]:
        """Atom types (1-based, int32), by atom id."""
    @property
    def positions(self) -> npt.NDArray[np.float64]:
        """Positions, shape (N, 3), by atom id, wrapped into the box as dumps write them (``x y z``), distance units (lj: σ). Settable with an (N, 3) array ((N, 2) in 2-D), by atom id; the image counters are kept."""
    @positions.setter
    def positions(self, value: npt.ArrayLike) -> None: ...
    @property
    def velocities(self) -> npt.NDArray[np.float64]:
        """Velocities, shape (N, 3), by atom id, velocity units (lj: σ/τ). Settable like ``positions``."""
    @velocities.setter
    def velocities(self, value: npt.ArrayLike) -> None: ...
    @property
    def forces(self) -> npt.NDArray[np.float64]:
        """Forces of the last force evaluation, shape (N, 3), by atom id, force units (lj: ε/σ)."""
    @property
    def unwrapped_positions(self) -> npt.NDArray[np.float64]:
        """Unwrapped positions x + image · L (dumps' ``xu yu zu``), shape (N, 3), by atom id, distance units (lj: σ)."""
    @property
    def images(self) -> npt.NDArray[np.int32]:
        """Periodic image counters of ``positions`` (dumps' ``ix iy iz``), shape (N, 3), int32, by atom id."""
    @property
    def output(self) -> List[str]:
        """Every line the interpreter printed (what ``dpdnl run`` shows and logs)."""
    @property
    def thermo(self) -> List[Dict[str, npt.NDArray[np.float64]]]:
        """The thermo output, one dict per run (per thermo header): column name as in the log header (``Step``, ``Temp``, ``Press``, …) → array, in the units of the thermo keyword (lj). Parsed from the printed lines with the crate's log parser, so it holds exactly what the log holds."""
    @property
    def dump_files(self) -> List[str]:
        """The file names of the dumps currently defined."""
    @property
    def threads(self) -> int:
        """Worker threads the runs use."""

# ---------------------------------------------------------------- files

def read_log(path: Optional[_Path] = None, *, text: Optional[str] = None) -> List[Dict[str, npt.NDArray[np.float64]]]:
    """The thermo blocks of a LAMMPS or dpdnl log.

    Args:
        path: the log file; give this or ``text``.
        text: the log's text instead of a file.

    Returns:
        A list with one dict per run (per thermo header): column name as in the header
        (``Step``, ``Temp``, …) → float array, in the units of the thermo keyword.

    Raises:
        FormatError: the text is not a log with thermo output (file, line, token).
        OSError: the file cannot be read.

    Example:
        >>> log = '''LAMMPS (22 Jul 2025)
        ... Step Temp Press
        ...        0   1.0   2.5
        ...       10   0.98  2.4
        ... Loop time of 0.01 on 1 procs for 10 steps with 500 atoms
        ... '''
        >>> runs = dpdnl.read_log(text=log)
        >>> runs[0]["Temp"].tolist()
        [1.0, 0.98]
    """
def read_dump(path: Optional[_Path] = None, *, text: Optional[str] = None) -> List[Dict[str, Any]]:
    """The frames of a text dump (``dump custom`` or ``dump atom``) of either engine.

    Args:
        path: the dump file; give this or ``text``.
        text: the dump's text instead of a file.

    Returns:
        A list with one dict per frame:

        - ``step`` (int): the time step;
        - ``box_bounds``: array (3, 2) of the lo and hi bounds (distance units);
        - ``tilt``: ``(xy, xz, yz)`` for a triclinic box, else None;
        - ``atoms``: dict column name (as in ``ITEM: ATOMS``) → float array, rows sorted by
          id when there is an ``id`` column.

    Raises:
        FormatError: the text is not a dump (file, line, token).
        OSError: the file cannot be read.

    Example:
        >>> dump = '''ITEM: TIMESTEP
        ... 100
        ... ITEM: NUMBER OF ATOMS
        ... 2
        ... ITEM: BOX BOUNDS pp pp pp
        ... 0 5
        ... 0 5
        ... 0 5
        ... ITEM: ATOMS id type x y z vx vy vz
        ... 2 1 1.0 1.0 1.0 0.1 0.0 0.0
        ... 1 1 2.0 2.0 2.0 -0.1 0.0 0.0
        ... '''
        >>> frame = dpdnl.read_dump(text=dump)[0]
        >>> frame["step"], frame["atoms"]["id"].tolist(), frame["atoms"]["vx"].tolist()
        (100, [1.0, 2.0], [-0.1, 0.1])
    """
def read_ave_time(path: Optional[_Path] = None, *, text: Optional[str] = None) -> Dict[str, Any]:
    """A ``fix ave/time`` file, in scalar or vector mode.

    Args:
        path: the file; give this or ``text``.
        text: the file's text instead of a file.

    Returns:
        A dict. Scalar mode: ``mode`` = ``"scalar"``, ``steps`` (int array), ``data`` (column
        name → float array). Vector mode: ``mode`` = ``"vector"``, ``steps`` (int array),
        ``blocks``: one dict per output with ``step``, ``header`` (the numbers of the output's
        first line after the step) and ``data`` (``Row`` and each column → float array).
        Values are in the units of the averaged quantities.

    Raises:
        FormatError: the text is not an ave/time file (file, line, token).
        OSError: the file cannot be read.

    Example:
        >>> text = '''# Time-averaged data for fix avg
        ... # TimeStep c_msd[4] v_t
        ... 100 0.52 1.01
        ... 200 1.04 0.99
        ... '''
        >>> r = dpdnl.read_ave_time(text=text)
        >>> r["mode"], r["steps"].tolist(), r["data"]["c_msd[4]"].tolist()
        ('scalar', [100, 200], [0.52, 1.04])
    """
def read_ave_chunk(path: Optional[_Path] = None, *, text: Optional[str] = None) -> Dict[str, Any]:
    """A ``fix ave/chunk`` file (profiles).

    Args:
        path: the file; give this or ``text``.
        text: the file's text instead of a file.

    Returns:
        A dict: ``columns`` (the names of the chunk lines: ``Chunk``, ``Coord1``, ``Ncount``,
        the values), ``steps`` (int array), ``blocks``: one dict per output with ``step``,
        ``header`` (the output line's numbers after the step), ``nchunks`` (int), ``total``
        (the total count) and ``data`` (column → float array, one value per chunk; ``Coord1``
        in distance units, or reduced with ``units reduced``).

    Raises:
        FormatError: the text is not an ave/chunk file (file, line, token).
        OSError: the file cannot be read.

    Example:
        >>> text = '''# Chunk-averaged data for fix prof and group all
        ... # Timestep Number-of-chunks Total-count
        ... # Chunk Coord1 Ncount vz
        ... 1000 2 500
        ...   1 0.25 250 0.1
        ...   2 0.75 250 -0.1
        ... '''
        >>> block = dpdnl.read_ave_chunk(text=text)["blocks"][0]
        >>> block["step"], block["nchunks"], block["data"]["vz"].tolist()
        (1000, 2, [0.1, -0.1])
    """
def read_ave_histo(path: Optional[_Path] = None, *, text: Optional[str] = None) -> Dict[str, Any]:
    """A ``fix ave/histo`` file (histograms).

    Args:
        path: the file; give this or ``text``.
        text: the file's text instead of a file.

    Returns:
        A dict: ``steps`` (int array) and ``blocks``, one dict per output with ``step``,
        ``total`` (counts), ``missing`` (counts outside the range), ``min`` and ``max`` (the
        extreme values seen, units of the histogrammed quantity), ``coord`` (bin centres,
        same units), ``count`` and ``fraction`` (float arrays, one per bin).

    Raises:
        FormatError: the text is not an ave/histo file (file, line, token).
        OSError: the file cannot be read.

    Example:
        >>> text = '''# Histogrammed data for fix h
        ... # TimeStep Number-of-bins Total-counts Missing-counts Min-value Max-value
        ... # Bin Coord Count Count/Total
        ... 1000 2 100 0 0.01 1.9
        ... 1 0.5 60 0.6
        ... 2 1.5 40 0.4
        ... '''
        >>> block = dpdnl.read_ave_histo(text=text)["blocks"][0]
        >>> block["total"], block["coord"].tolist(), block["fraction"].tolist()
        (100.0, [0.5, 1.5], [0.6, 0.4])
    """
def read_series(path: Optional[_Path] = None, *, text: Optional[str] = None) -> Dict[str, npt.NDArray[np.float64]]:
    """A time series from a scalar-mode ``fix ave/time`` file or a log, the input the analyses
    take.

    A log's runs are joined with the last run's columns, repeated steps dropped.

    Args:
        path: the file; give this or ``text``.
        text: the file's text instead of a file.

    Returns:
        ``{"Step": steps, column: values, …}``, float arrays of equal length.

    Raises:
        FormatError: neither a scalar ave/time file nor a log (file, line, token).
        OSError: the file cannot be read.

    Example:
        >>> text = '''# Time-averaged data for fix avg
        ... # TimeStep c_msd[4]
        ... 100 0.52
        ... 200 1.04
        ... '''
        >>> s = dpdnl.read_series(text=text)
        >>> list(s), s["Step"].tolist()
        (['Step', 'c_msd[4]'], [100.0, 200.0])
    """
def detect_kind(path: Optional[_Path] = None, *, text: Optional[str] = None) -> str:
    """The kind of a file, from its first lines.

    Args:
        path: the file; give this or ``text``.
        text: the file's text instead of a file.

    Returns:
        ``"ave/time"``, ``"ave/chunk"``, ``"ave/histo"``, ``"dump"`` or ``"log"``.

    Raises:
        OSError: the file cannot be read.

    Example:
        >>> dpdnl.detect_kind(text="ITEM: TIMESTEP\\n0\\n")
        'dump'
    """
def read(path: Optional[_Path] = None, *, text: Optional[str] = None) -> Any:
    """Reads any of the above by its kind (:func:`detect_kind`).

    Args:
        path: the file; give this or ``text``.
        text: the file's text instead of a file.

    Returns:
        A log gives :func:`read_log`'s list, a dump :func:`read_dump`'s list, the others
        their reader's dict.

    Raises:
        FormatError: the text is not in the format of its kind (file, line, token).
        OSError: the file cannot be read.

    Example:
        >>> r = dpdnl.read(text="# Time-averaged data\\n# TimeStep v_a\\n0 1.5\\n10 2.5\\n")
        >>> r["mode"], r["data"]["v_a"].tolist()
        ('scalar', [1.5, 2.5])
    """

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
    """The speed distribution against Maxwell–Boltzmann, as ``dpdnl analyze mb``
    (non-linear paper eq. 53, in d dimensions).

    Each ``fix ave/histo`` output, dump frame or array of ``speeds`` is one block of the error
    analysis. Expected counts are the exact integrals of the Maxwell–Boltzmann density over the
    bins; the χ² test merges bins until each expects ≥ 5 counts.

    Args:
        files: ``fix ave/histo`` files of the speed, or text dumps with ``vx vy [vz]``
            columns (a path or a list of paths); None: give ``speeds``.
        temp: the set temperature kT, an energy (lj: ε).
        mass: the particle mass, mass units (lj: m).
        dim: the dimension; None: 3 for histograms, for dumps 2 when there is no ``vz`` or
            it is all 0, 3 for ``speeds``.
        bins: dumps and ``speeds``: the number of bins on [0, vmax] (the paper: 150).
        vmax: dumps and ``speeds``: upper end of the histogram, velocity units (lj: σ/τ);
            None: 2·sqrt(10 kT/m), the paper's 2 at kT = 0.1.
        from_step: skip dump frames and histogram outputs before this step.
        speeds: instead of files, a list of 1-D arrays of speeds (velocity units), one per
            frame or block.

    Returns:
        The dict ``dpdnl analyze mb`` writes to ``PREFIX.json``; energies in ε, speeds in σ/τ
        (lj):

        - ``analysis`` (``"mb"``), ``inputs`` (names of the inputs), ``source`` (what the
          histogram came from), ``dim``, ``mass``, ``kt_set`` (= ``temp``);
        - ``n_samples`` (speeds counted), ``n_blocks``, ``bins``, ``v_lo`` and ``v_hi``
          (range of the histogram), ``outside`` and ``outside_expected`` (counts beyond it,
          measured and expected);
        - ``kt_fit``: maximum-likelihood kT of the counts; ``kt_fit_err_iid`` its error for
          independent samples, ``kt_fit_err_blocks`` from the spread between blocks;
          ``inefficiency`` = (err_blocks/err_iid)², correlated samples per independent one;
        - ``chi2``, ``dof``, ``p_value``: Pearson χ² against ``temp``; ``p_value_corrected``
          with χ² divided by the inefficiency; ``chi2_fit``, ``dof_fit``, ``p_value_fit``:
          against ``kt_fit``;
        - ``ks_d``, ``ks_p``: Kolmogorov–Smirnov distance of the cumulative distributions and
          its probability for the independent samples;
        - ``table``: per bin, arrays ``v_lo``, ``v_hi``, ``v_mid``, ``count``,
          ``expected_count``, ``pdf`` and ``pdf_err`` (measured density, 1/velocity),
          ``pdf_mb_set`` and ``pdf_mb_fit`` (Maxwell–Boltzmann at ``temp`` and at
          ``kt_fit``), ``residual_sigma`` ((pdf − pdf_mb_set)/pdf_err).

    Raises:
        AnalysisError: no histogram or frame, both files and speeds, a bad parameter.
        FormatError: an input is not an ave/histo file or a dump.
        OSError: a file cannot be read.

    Example:
        >>> rng = np.random.default_rng(1)
        >>> v = np.linalg.norm(rng.normal(0.0, 1.0, (20000, 3)), axis=1)  # kT = m = 1
        >>> r = dpdnl.mb(speeds=[v[:10000], v[10000:]], temp=1.0)
        >>> round(r["kt_fit"], 2), r["n_blocks"], len(r["table"]["pdf"])
        (0.99, 2, 150)
    """
def mb_pdf(v: npt.ArrayLike, temp: float, *, mass: float = 1.0, dim: int = 3) -> npt.NDArray[np.float64]:
    """The Maxwell–Boltzmann speed density P(v) in d dimensions, the curve ``dpdnl analyze mb``
    draws: P(v) = 2 (m/2kT)^(d/2) / Γ(d/2) · v^(d−1) exp(−m v²/2kT).

    Args:
        v: speeds, velocity units (lj: σ/τ), a 1-D float array.
        temp: kT, an energy (lj: ε).
        mass: the particle mass, mass units (lj: m).
        dim: the dimension, 2 or 3.

    Returns:
        P at each speed of ``v``, 1/velocity units (lj: τ/σ); its integral over v ≥ 0 is 1.

    Example:
        >>> v = np.linspace(0.0, 10.0, 100001)
        >>> p = dpdnl.mb_pdf(v, 1.0)
        >>> round(float(np.sum(p) * (v[1] - v[0])), 6)
        1.0
    """
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
    """The viscosity of reverse NEMD with the PeX push (``fix pex/push``), as ``dpdnl analyze
    nemd``: profiles, the fits of v_z(x) in the middle of each half, the stress Π_xz (non-linear
    paper eq. 55), the viscosity μ = Π_xz / shear rate (eq. 56) and T_d (eq. 58).

    The stress is nominal, dp / (2 Ly Lz every dt), with ``dp``, or measured from the pushed
    total with ``push`` (then skipped exchanges are accounted for); give one of the two.

    Args:
        profile: the ``fix ave/chunk`` file of the profiles (``bin/1d`` along x, ``units box``),
            with a v_z column and, optionally, the number density and T_d.
        box: the box lengths (Lx, Ly, Lz), distance units (lj: σ).
        dt: the time step, time units (lj: τ).
        xlo: the lower x bound of the box, distance units; None: from the bins, when they
            tile [xlo, xlo + Lx).
        dp: the momentum of one push (``fix pex/push`` dp), mass·velocity (lj: m σ/τ), for the
            nominal stress.
        every: steps between pushes (``fix pex/push`` every).
        push: a log or ``fix ave/time`` file, or a series dict, holding the pushed total
            ``f_ID``; the stress is then the fitted rate of that total.
        push_col: the column of the total in ``push``; None: the only column starting with
            ``f_``.
        from_step: use only outputs at or after this step (the steady state).
        fit_fraction: the fraction of each half, centred between the slabs, that the fit uses.
        vz_col: the profile's v_z column.
        density_col: the profile's number-density column (if absent: Ncount per bin volume).
        td_col: the profile's column of the per-particle mean of (p_x² + p_y²)/2m, k_B T_d
            (eq. 58); if absent, no T_d.
        label: the label of this result in :func:`flowcurve`; None: the profile's file name
            without its extension.

    Returns:
        The dict ``dpdnl analyze nemd`` writes to ``PREFIX.json`` (units: lj):

        - ``analysis`` (``"nemd"``), ``label``, ``input``, ``box``, ``xlo``, ``dt``,
          ``from_step``, ``n_outputs``, ``first_step``, ``last_step``, ``fit_fraction``;
        - ``stress``, ``stress_err``: Π_xz, momentum per area and time (lj: ε/σ³);
          ``stress_source`` (nominal or measured from which column), ``stress_nominal``
          (dp/(2 Ly Lz every dt), or None without ``dp``);
        - ``shear_rate``, ``shear_rate_err`` (1/time), ``shear_rate_blocks``,
          ``shear_rate_converged`` (False: too few blocks at the chosen level, so the error is a
          lower bound; docs/analysis.md, "How the errors are formed"), ``shear_rate_n_eff``
          (the effective number of independent samples behind the error);
        - ``viscosity``, ``viscosity_err``: μ, mass/(distance·time) (lj: m/(σ τ));
        - ``density_centre``, ``density_centre_err`` (1/volume) and ``td_centre``,
          ``td_centre_err`` (energy; None without T_d): averaged over the fit windows;
          ``density_source``, ``td_source``: the columns used;
        - ``halves``: for ``central`` and ``outer``, ``name``, ``window`` ([lo, hi], distance),
          ``bins`` (count), ``slope`` and ``slope_err`` (block-averaged, 1/time),
          ``slope_fit_mean_profile``, ``slope_fit_err_regression``, ``intercept``, ``r2``
          (the fit of the mean profile);
        - ``table``: per bin, arrays ``x``, ``vz``, ``vz_err``, ``vz_fit`` (NaN outside the
          windows), ``td``, ``td_err``, ``density``, ``density_err``.

    Raises:
        AnalysisError: neither ``dp`` nor ``push``, a missing column, too few outputs.
        FormatError: the profile is not an ave/chunk file.
        OSError: a file cannot be read.

    Example:
        >>> sim = dpdnl.Simulation()
        >>> sim.commands([
        ...     "region box block 0 8 0 4 0 4", "create_box 1 box",
        ...     "create_atoms 1 random 384 8675 box", "mass 1 1.0",
        ...     "velocity all create 1.0 4928 mom yes",
        ...     "pair_style dpd/nonlinear 1.0 1.0 7919", "pair_coeff * * 0.0 4.5 0.0",
        ...     "fix 1 all nve", "timestep 0.01",
        ...     "fix push all pex/push 0.05",
        ...     "compute slab all chunk/atom bin/1d x lower 0.4 units box",
        ...     "fix prof all ave/chunk 10 10 100 slab vz density/number file prof.chunk",
        ...     "thermo 100", "thermo_style custom step temp f_push",
        ... ])
        >>> sim.run(2000)
        >>> r = dpdnl.nemd("prof.chunk", box=(8, 4, 4), dt=0.01, dp=0.05, from_step=500)
        >>> r["stress"], r["n_outputs"], [h["name"] for h in r["halves"]]
        (0.15625, 16, ['central', 'outer'])
        >>> m = dpdnl.nemd("prof.chunk", box=(8, 4, 4), dt=0.01, push=sim.thermo[-1],
        ...                from_step=500)
        >>> m["stress_source"].startswith("measured")
        True
    """
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
    """The Einstein–Helfand viscosity (non-linear paper eq. 59), as ``dpdnl analyze eh``:
    μ = V/(2 kT t) ⟨(∫_0^t Π_ab dt')²⟩, averaged over time origins and the off-diagonal
    components, from the slope over a fit window.

    Sample the stress every step (or average it over every step of the interval): the
    random stress is uncorrelated between steps. The default window follows the paper's
    condition t ≪ L²/(4π² ν): t_max = ``window_factor`` · L²/(4π² ν), t_min = t_max/4.

    Args:
        source: a scalar ``fix ave/time`` file or a log with the off-diagonal pressure
            components, or a series dict such as ``Simulation.thermo[-1]``.
        dt: the time step, time units (lj: τ); the sample interval is dt times the step
            spacing of the series.
        box: the box lengths (2 in 2-D, 3 in 3-D), distance units (lj: σ): the volume, and
            the smallest length L of the window rule.
        temp: kT, an energy (lj: ε).
        density: the number density n, 1/volume (lj: σ⁻³; σ⁻² in 2-D), for ν = μ/(n m) in the
            window rule.
        mass: the particle mass, mass units (lj: m).
        cols: the stress columns; None: ``pxy pxz pyz`` or ``c_X[4] c_X[5] c_X[6]`` (only xy
            in 2-D). Pressure units (lj: ε/σ³).
        from_step: use only samples at or after this step.
        window_factor: t_max = factor · L²/(4π² ν) (automatic window).
        tmin: the start of the fit window, time units; with ``tmax``, overrides the automatic
            window.
        tmax: the end of the fit window, time units.
        blocks: the number of consecutive blocks for the error (fewer when a block would be
            shorter than 4 t_max).

    Returns:
        The dict ``dpdnl analyze eh`` writes to ``PREFIX.json`` (units: lj):

        - ``analysis`` (``"eh"``), ``input``, ``components`` (the columns used), ``dt``,
          ``sample_interval`` (time), ``n_samples``, ``from_step``, ``volume``, ``kt``,
          ``box_len`` (L), ``mass_density`` (n m);
        - ``viscosity``, ``viscosity_err``: μ, mass/(distance·time) (lj: m/(σ τ); in 2-D
          mass/time); ``per_component``: μ of each component; ``blocks``: μ of each block
          (the error is their standard error);
        - ``t_min``, ``t_max`` (the fit window, time), ``tau_l`` (L²/(4π² ν), time),
          ``window_source`` (how the window was set), ``window_capped`` (True: the run was too
          short for the window);
        - ``slope``, ``intercept``: the fit of ⟨(∫Π dt)²⟩ against t;
        - ``window_drift``, ``window_drift_err``, ``window_not_linear``: μ on the second half
          of the window minus μ on the first, its error, and whether it is significant (more
          than 3 errors: the window is still in the transient);
        - ``table``: arrays ``t`` (lags), ``msd_integral`` (⟨(∫Π dt)²⟩), ``mu_running``
          (V⟨(∫Π)²⟩/(2kT t)), ``msd_fit``.

    Raises:
        AnalysisError: a missing column, a series too short, a bad parameter.
        FormatError: the file is not an ave/time file or a log.
        OSError: the file cannot be read.

    Example:
        >>> rng = np.random.default_rng(2)
        >>> n = 20000           # white-noise stress: mu = V var(P) dt / (2 kT) = 5
        >>> p = {"Step": np.arange(n), "pxy": rng.standard_normal(n),
        ...      "pxz": rng.standard_normal(n), "pyz": rng.standard_normal(n)}
        >>> r = dpdnl.eh(p, dt=0.01, box=[10, 10, 10], temp=1.0, density=3.0)
        >>> abs(r["viscosity"] - 5.0) < 3 * r["viscosity_err"]
        True
    """
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
    """The self-diffusion coefficient D = MSD/(2 d t) from the slope of the mean-squared
    displacement, as ``dpdnl analyze msd``; with a viscosity and the density, the Schmidt
    number Sc = μ/(n m D).

    From a series (a ``compute msd`` column): one time origin, default window the last 80 %.
    From a dump with unwrapped positions (``xu yu zu``, or ``x y z ix iy iz``): all time
    origins and atoms, lags up to half the trajectory, default window 20–100 % of that, the
    error from 8 groups of atoms.

    Args:
        source: a ``fix ave/time`` file or log with a ``compute msd`` column, a dump with
            unwrapped positions (a path), or a series dict.
        dt: the time step, time units (lj: τ).
        dim: the dimension d, 2 or 3.
        col: the MSD column of a series; None: the only column named like ``c_*[4]`` or
            ``msd``. Squared distance units (lj: σ²).
        atoms: the number of atoms (series only): gives the Brownian error estimate; None:
            the regression error only (an underestimate).
        tmin: the start of the fit window, time units; None: the default window.
        tmax: the end of the fit window, time units; None: the default window.
        from_step: use only samples or frames at or after this step.
        eta: the shear viscosity μ for the Schmidt number, mass/(distance·time) (lj:
            m/(σ τ)); needs ``density``.
        eta_err: the error of ``eta``, same units.
        eta_from: instead of ``eta``, a result of :func:`eh` or :func:`nemd` (a dict, or its
            JSON file) to take μ and its error from.
        density: the number density n, 1/volume (lj: σ⁻³), for ρ = n m.
        mass: the particle mass, mass units (lj: m).

    Returns:
        The dict ``dpdnl analyze msd`` writes to ``PREFIX.json`` (units: lj):

        - ``analysis`` (``"msd"``), ``input``, ``dim``, ``dt``, ``method`` (one origin or all
          origins), ``t_min``, ``t_max`` (the fit window, time);
        - ``diffusion``, ``diffusion_err``: D, distance²/time (lj: σ²/τ);
          ``diffusion_err_method`` (how the error was estimated); ``diffusion_groups`` (D of
          each group of atoms, dumps only);
        - ``viscosity``, ``viscosity_source`` (the μ used, or None); ``schmidt``,
          ``schmidt_err`` (a pure number, or None without a viscosity);
        - ``table``: arrays ``t``, ``msd`` (σ²), ``msd_err`` (NaN where there is none),
          ``msd_fit``.

    Raises:
        AnalysisError: no MSD column, a window outside the data, a viscosity without a density.
        FormatError: the file is not a series or a dump.
        OSError: a file cannot be read.

    Example:
        >>> t = np.arange(0, 5000, 50)            # steps; D = 0.05 at dt = 0.01
        >>> r = dpdnl.msd({"Step": t, "c_msd[4]": 6 * 0.05 * t * 0.01}, dt=0.01,
        ...               eta=1.0, density=3.0)
        >>> round(r["diffusion"], 6), round(r["schmidt"], 6)
        (0.05, 6.666667)
    """
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
    """The viscosity of Couette flow under Lees–Edwards boundaries (``fix deform … xy erate``),
    as ``dpdnl analyze couette``: η* = −⟨P_xy⟩ / shear rate, the mean and its error from
    block averaging.

    Give the imposed ``rate``, or a velocity ``profile`` to measure it from.

    Args:
        source: a ``fix ave/time`` file or log with P_xy, or a series dict such as
            ``Simulation.thermo[-1]``.
        col: the P_xy column, pressure units (lj: ε/σ³); None: ``pxy``, else ``c_X[4]``.
        rate: the imposed shear rate (``fix deform`` erate), 1/time (lj: 1/τ).
        profile: instead of ``rate``, a ``fix ave/chunk`` profile of v_x along y, whose
            block-averaged slope is the shear rate.
        v_col: the profile's velocity column.
        y_col: the profile's coordinate column.
        y_scale: multiply the profile coordinate by this (L_y when the chunks use ``units
            reduced``, which LAMMPS requires for triclinic boxes).
        from_step: use only samples and outputs at or after this step.
        label: the label of this result in :func:`flowcurve`; None: the file name without its
            extension, or ``"couette"`` for a dict.

    Returns:
        The dict ``dpdnl analyze couette`` writes to ``PREFIX.json`` (units: lj):

        - ``analysis`` (``"couette"``), ``label``, ``input``, ``column``, ``n_samples``,
          ``from_step``;
        - ``pxy``, ``pxy_err``: ⟨P_xy⟩ and its block error, pressure units; ``pxy_n_eff`` (the
          effective number of independent samples behind the error) and ``pxy_converged``
          (False: too few blocks at the chosen level, so the error is a lower bound;
          docs/analysis.md, "How the errors are formed");
        - ``shear_rate``, ``shear_rate_err`` (1/time), ``shear_rate_source`` (imposed or
          measured), ``shear_rate_imposed`` (``rate``, or None);
        - ``viscosity``, ``viscosity_err``: η*, mass/(distance·time) (lj: m/(σ τ); in 2-D
          mass/time);
        - ``table``: arrays ``step``, ``pxy``, ``pxy_running_mean``;
        - ``profile`` (with ``profile`` only): arrays ``y``, ``v``, ``v_err``, ``v_fit``.

    Raises:
        AnalysisError: no P_xy column, neither rate nor profile, a series too short.
        FormatError: a file is not in the expected format.
        OSError: a file cannot be read.

    Example:
        >>> rng = np.random.default_rng(3)
        >>> steps = np.arange(0, 20000, 10)
        >>> s = {"Step": steps, "pxy": -0.5 + 0.05 * rng.standard_normal(steps.size)}
        >>> r = dpdnl.couette(s, rate=0.25)
        >>> round(r["viscosity"], 1), r["shear_rate_source"]
        (2.0, 'imposed')
    """
def flowcurve(results: Sequence[Union[_Path, Mapping[str, Any]]]) -> Dict[str, Any]:
    """The viscosity against the shear rate, as ``dpdnl analyze flowcurve``: the points of
    several results grouped by their label and sorted by rate.

    Args:
        results: results of :func:`nemd` or :func:`couette` (dicts, or their JSON files), or
            CSV files with the columns ``label,rate,eta,eta_err``.

    Returns:
        A dict: ``analysis`` (``"flowcurve"``); ``groups``, one dict per label with ``label``
        and the arrays ``rate`` (1/time), ``eta`` and ``eta_err`` (viscosity units); ``csv``,
        the text of the CSV file the CLI writes.

    Raises:
        AnalysisError: a result without a shear rate or viscosity.
        OSError: a file cannot be read.

    Example:
        >>> steps = np.arange(0, 2000, 10)
        >>> a = dpdnl.couette({"Step": steps, "pxy": np.full(steps.size, -0.5)}, rate=0.25,
        ...                   label="cross")
        >>> b = dpdnl.couette({"Step": steps, "pxy": np.full(steps.size, -0.8)}, rate=0.5,
        ...                   label="cross")
        >>> g = dpdnl.flowcurve([b, a])["groups"][0]
        >>> g["label"], g["rate"].tolist(), g["eta"].round(6).tolist()
        ('cross', [0.25, 0.5], [2.0, 1.6])
    """
