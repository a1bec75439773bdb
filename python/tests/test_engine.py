"""The engine from Python: the same bits as `dpdnl run`, arrays by id, errors, Ctrl-C."""

import _thread
import os
import signal
import threading
import time

import numpy as np
import pytest

import dpdnl

# Cross-engine golden cases (tests/data/crosscheck): 3-D velocity-Verlet, 2-D two-step noise,
# 2-D Euler with (eta, sc) targets resolved at init.
CASES = ["dot_plain_3d", "dot_twostep_2d", "design_euler_2d"]


@pytest.mark.parametrize("case", CASES)
def test_same_thermo_and_dump_as_dpdnl_run(case, crosscheck_dir, cli, monkeypatch):
    monkeypatch.chdir(crosscheck_dir)
    cli("run", f"in.{case}", "-var", "engine", "cli", "-log", "log.cli", "--quiet")
    sim = dpdnl.Simulation.from_script(f"in.{case}", variables={"engine": "py"}, log="log.py")
    cli_blocks = dpdnl.read_log("log.cli")
    assert len(cli_blocks) == 1 and len(sim.thermo) == 1
    for got in (sim.thermo, dpdnl.read_log("log.py")):
        assert got[0].keys() == cli_blocks[0].keys()
        for k, v in cli_blocks[0].items():
            assert np.array_equal(got[0][k], v), k
    # The dump of the last step: byte for byte.
    a = (crosscheck_dir / f"dump.{case}.cli").read_bytes()
    b = (crosscheck_dir / f"dump.{case}.py").read_bytes()
    assert a == b
    # The state the arrays show is the one dumped (dump format %20.15g: 15 digits).
    frame = dpdnl.read_dump(f"dump.{case}.py")[-1]
    assert frame["step"] == sim.step == 100
    at = frame["atoms"]
    assert np.array_equal(sim.ids, at["id"].astype(np.int64))
    assert np.array_equal(sim.types, at["type"].astype(np.int32))
    x = np.column_stack([at["x"], at["y"], at["z"]])
    v = np.column_stack([at["vx"], at["vy"], at["vz"]])
    f = np.column_stack([at["fx"], at["fy"], at["fz"]])
    np.testing.assert_allclose(sim.positions, x, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(sim.velocities, v, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(sim.forces, f, rtol=1e-12, atol=1e-12)


def test_thermo_of_a_continued_run_matches_one_script(crosscheck_dir, cli, monkeypatch):
    # The script's run 100 then `run 50` from Python = the same script with a second run 50.
    monkeypatch.chdir(crosscheck_dir)
    text = (crosscheck_dir / "in.dot_plain_3d").read_text()
    (crosscheck_dir / "in.two").write_text(text + "run 50\n")
    cli("run", "in.two", "-var", "engine", "cli", "-log", "log.cli", "--quiet")
    sim = dpdnl.Simulation.from_script("in.dot_plain_3d", variables={"engine": "py"})
    sim.run(50)
    ref = dpdnl.read_log("log.cli")
    assert len(sim.thermo) == len(ref) == 2
    for a, b in zip(sim.thermo, ref):
        for k in b:
            assert np.array_equal(a[k], b[k]), k
    assert sim.step == 150


def _small(dim=3, n=200):
    sim = dpdnl.Simulation(dimension=dim)
    z = "-2 2" if dim == 3 else "-0.5 0.5"
    sim.commands(
        [
            "units lj",
            "atom_style atomic",
            f"region box block -2 2 -2 2 {z}",
            "create_box 1 box",
            f"create_atoms 1 random {n} 4321 box",
            "mass 1 1.0",
            "velocity all create 1.0 87287 mom yes dist gaussian",
            "pair_style dpd/nonlinear 1.0 1.0 5 friction cross",
            "pair_coeff 1 1 25.0 4.5 0.5",
            "timestep 0.01",
            "fix 1 all nve",
            "thermo 10",
            "thermo_style custom step temp press pxy",
        ]
        + (["fix 2 all enforce2d"] if dim == 2 else [])
    )
    return sim


def test_arrays_by_id_box_and_step():
    sim = _small()
    assert sim.natoms == 200 and sim.dimension == 3 and sim.step == 0
    lo, hi, tilt = sim.box
    assert lo == (-2.0, -2.0, -2.0) and hi == (2.0, 2.0, 2.0) and tilt == (0.0, 0.0, 0.0)
    assert sim.dt == 0.01 and sim.masses[1] == 1.0
    sim.run(20)
    assert sim.step == 20
    ids = sim.ids
    assert ids.dtype == np.int64 and np.array_equal(ids, np.arange(1, 201))
    for a in (sim.positions, sim.velocities, sim.forces):
        assert a.shape == (200, 3) and a.dtype == np.float64
    assert sim.images.shape == (200, 3) and sim.types.dtype == np.int32
    assert np.all(sim.positions >= -2.0) and np.all(sim.positions <= 2.0)
    # Momentum is conserved (F_ji = -F_ij exactly, mom yes).
    assert np.abs(sim.velocities.sum(axis=0)).max() < 1e-10
    t = sim.thermo[-1]
    assert list(t) == ["Step", "Temp", "Press", "Pxy"]
    assert np.array_equal(t["Step"], [0, 10, 20])
    # Arrays are copies: changing one does not change the engine.
    x = sim.positions
    x[:] = 0.0
    assert np.abs(sim.positions).max() > 0.1


def test_2d_simulation():
    sim = _small(dim=2, n=100)
    sim.run(10)
    assert sim.dimension == 2
    assert np.all(sim.velocities[:, 2] == 0.0)


def test_positions_and_velocities_round_trip():
    sim = _small()
    sim.run(10)
    x, v = sim.positions, sim.velocities
    rng = np.random.default_rng(3)
    v2 = v + rng.normal(0, 0.01, v.shape)
    v2 -= v2.mean(axis=0)
    sim.velocities = v2
    assert np.array_equal(sim.velocities, v2)
    sim.positions = x[::-1].copy()  # by id: atom k gets atom (N+1-k)'s position
    assert np.array_equal(sim.positions, x[::-1])
    sim.run(10)
    assert sim.step == 20
    with pytest.raises(ValueError, match="shape"):
        sim.velocities = v[:10]


def test_bad_command_raises_script_error_with_file_and_line():
    sim = dpdnl.Simulation()
    with pytest.raises(dpdnl.ScriptError) as e:
        sim.commands(["units lj", "atom_style atomic", "frobnicate 1 2"])
    err = e.value
    assert isinstance(err, RuntimeError)
    assert (err.file, err.line, err.command) == ("<commands>", 3, "frobnicate")
    assert str(err) == f"<commands>:3: frobnicate: {err.message}"
    with pytest.raises(dpdnl.ScriptError, match="needs a simulation box") as e:
        sim.run(10)
    assert e.value.command == "run"


def test_bad_script_gives_the_clis_message(tmp_path, cli, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "in.bad").write_text(
        "units lj\natom_style atomic\nregion box block 0 1 0 1 0 1\ncreate_box 1 box\n"
        "pair_style dpd/nonlinear 1.0 1.0 0\n"
    )
    p = cli("run", "in.bad", "-log", "none", check=False)
    assert p.returncode != 0
    with pytest.raises(dpdnl.ScriptError) as e:
        dpdnl.Simulation.from_script("in.bad")
    assert (e.value.file, e.value.line, e.value.command) == ("in.bad", 5, "pair_style")
    assert f"ERROR: {e.value}" in p.stderr
    with pytest.raises(dpdnl.ScriptError, match="cannot read input file"):
        dpdnl.Simulation.from_script("no-such-file")


def test_variables_are_index_style(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "in.v").write_text('variable n index 5\nprint "n = ${n}"\n')
    assert "n = 7" in dpdnl.Simulation.from_script("in.v", variables={"n": "7"}).output
    assert "n = 5" in dpdnl.Simulation.from_script("in.v").output


def _interrupt_after(delay, how):
    def go():
        time.sleep(delay)
        if how == "interrupt_main":
            _thread.interrupt_main()
        else:
            os.kill(os.getpid(), signal.SIGINT)

    t = threading.Thread(target=go, daemon=True)
    t.start()
    return t


@pytest.fixture
def sigint_raises():
    """Python's own SIGINT handler, for the length of one test.

    A process started with SIGINT ignored (a background job of a non-interactive shell,
    `nohup ... &`, some CI runners) inherits SIG_IGN, and Python then installs no handler:
    neither a real SIGINT nor `_thread.interrupt_main()` reaches the run. The test is about
    what the engine does when Python sees the signal, so it installs the handler it needs
    and puts back what was there.
    """
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("signal handlers can only be installed from the main thread")
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, before)


@pytest.mark.parametrize("how", ["interrupt_main", "sigint"])
def test_ctrl_c_stops_a_long_run_at_a_step(how, sigint_raises):
    sim = _small()
    sim.command("thermo 0")
    sim.run(10)  # set up once, so that the timed run below only steps
    # A run that lasts about 10 s at this machine's speed: long enough that the interrupt
    # at 0.5 s finds it running, short enough that a lost signal costs seconds, not hours.
    t0 = time.monotonic()
    sim.run(2000)
    per_step = max((time.monotonic() - t0) / 2000, 1e-7)
    n = int(10.0 / per_step)
    start = sim.step
    t0 = time.monotonic()
    _interrupt_after(0.5, how)
    with pytest.raises(KeyboardInterrupt):
        sim.run(n)
    latency = time.monotonic() - t0 - 0.5
    # Console::interrupted is asked after every step and looks at Python's signals at most
    # every 20 ms; a step of 200 atoms takes well under a millisecond. 0.5 s leaves room for a
    # loaded machine.
    assert latency < 0.5, latency
    stopped = sim.step
    assert start < stopped < start + n
    # The state is a step's: finite, and the simulation goes on from it.
    assert np.isfinite(sim.positions).all() and np.isfinite(sim.velocities).all()
    sim.run(5)
    assert sim.step == stopped + 5


def test_run_releases_the_gil():
    # Another Python thread makes progress while a run is in Rust.
    sim = _small()
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    before = len(ticks)
    sim.run(2000)
    during = len(ticks) - before
    stop.set()
    t.join()
    assert during > 5, during
