"""The analyses: each result equals the JSON `dpdnl analyze` writes for the same input, and
known-answer cases (the synthetic data of tests/analysis.rs, drawn here with NumPy's seeded
generator; tolerances as there, with their reasons)."""

import json
import math

import numpy as np
import pytest

import dpdnl
from conftest import DATA

ANALYSIS = DATA / "analysis"


def _same_as_cli(result, cli, tmp_path, *args):
    """Runs `dpdnl analyze ARGS --out tmp --no-plot` and compares its JSON with `result`."""
    prefix = tmp_path / "cli"
    cli("analyze", *args, "--out", prefix, "--no-plot")
    ref = json.loads((tmp_path / "cli.json").read_text())
    got = {k: v for k, v in result.items() if k not in ("table", "profile")}
    assert got == ref
    return ref


def _write_series(path, names, steps, cols):
    with open(path, "w") as f:
        f.write("# Time-averaged data for fix t\n# TimeStep " + " ".join(names) + "\n")
        for k, s in enumerate(steps):
            f.write(f"{int(s)} " + " ".join(repr(float(c[k])) for c in cols) + "\n")


# ---------------------------------------------------------------- Maxwell-Boltzmann


def test_mb_histogram_file_is_the_clis(cli, tmp_path):
    p = str(ANALYSIS / "speed_one.ave_histo")
    r = dpdnl.mb(p, temp=1.0)
    _same_as_cli(r, cli, tmp_path, "mb", p, "--temp", "1.0")
    assert r["n_samples"] == 3000.0 and r["bins"] == 30
    assert len(r["table"]["pdf"]) == 30


def _mb_speeds(rng, kt, d, blocks, per_block):
    return [np.sqrt(((np.sqrt(kt) * rng.standard_normal((per_block, d))) ** 2).sum(axis=1))
            for _ in range(blocks)]


@pytest.mark.parametrize("d", [2, 3])
def test_mb_exact_samples_pass_and_a_hot_sample_fails(d):
    # 200 000 independent speeds, 150 bins on [0, 2] at kT = 0.1 (the paper's histogram):
    # p > 1e-3 fails one run in a thousand; a 3 % error in T is ~15 sigma (p < 1e-6).
    rng = np.random.default_rng(11 + d)
    kt = 0.1
    r = dpdnl.mb(speeds=_mb_speeds(rng, kt, d, 20, 10_000), temp=kt, dim=d, vmax=2.0)
    assert r["n_samples"] == 200_000.0 and r["p_value"] > 1e-3 and r["ks_p"] > 1e-3
    assert abs(r["kt_fit"] - kt) < 4 * r["kt_fit_err_iid"]
    hot = dpdnl.mb(speeds=_mb_speeds(rng, 1.03 * kt, d, 20, 10_000), temp=kt, dim=d, vmax=2.0)
    assert hot["p_value"] < 1e-6
    assert abs(hot["kt_fit"] - 1.03 * kt) < 4 * hot["kt_fit_err_iid"]
    v = np.linspace(0, 2, 5)
    assert np.all(dpdnl.mb_pdf(v, kt, dim=d) >= 0)


# ---------------------------------------------------------------- NEMD


def test_nemd_on_a_lammps_pex_run_is_the_clis(cli, tmp_path):
    # tests/analysis.rs nemd_on_a_lammps_pex_run: the viscosity lies in the band set by the
    # independent Einstein-Helfand measurement of the same fluid, [0.76, 0.92].
    prof, push = str(ANALYSIS / "pex.ave_chunk"), str(ANALYSIS / "pex_push.ave_time")
    r = dpdnl.nemd(prof, box=(10, 5, 5), dt=0.01, dp=0.2, push=push)
    _same_as_cli(
        r, cli, tmp_path, "nemd", prof, "--box", 10, 5, 5, "--dt", 0.01, "--dp", 0.2, "--push", push
    )
    assert r["stress"] == pytest.approx(r["stress_nominal"], rel=1e-9)
    assert 0.76 < r["viscosity"] < 0.92
    assert r["xlo"] == pytest.approx(-5.0)
    # The pushed total given as a series dict gives the same.
    r2 = dpdnl.nemd(prof, box=(10, 5, 5), dt=0.01, dp=0.2, push=dpdnl.read_series(push))
    assert r2["viscosity"] == r["viscosity"]


def _pex_chunk_file(path, xlo, lx, g, outputs):
    nb, dx = 40, lx / 40
    with open(path, "w") as f:
        f.write("# Chunk-averaged data for fix prof and group all\n"
                "# Timestep Number-of-chunks Total-count\n"
                "# Chunk Coord1 Ncount vz density/number v_td\n")
        for k in range(outputs):
            f.write(f"{1000 * (k + 1)} {nb} {20 * nb}\n")
            for i in range(nb):
                x = xlo + (i + 0.5) * dx
                u = (x - xlo - 0.25 * lx) % lx
                v = g * (0.25 * lx - u) if u < 0.5 * lx else g * (u - 0.75 * lx)
                f.write(f"  {i + 1} {x!r} 20 {v!r} 3.0 1.0\n")


def test_nemd_exact_triangle_profile(tmp_path):
    # v_z with slope -0.3 in the centre half and +0.3 outside; nominal stress 0.1.
    p = tmp_path / "tri.ave_chunk"
    _pex_chunk_file(p, -5.0, 10.0, 0.3, 4)
    r = dpdnl.nemd(p, box=(10, 5, 5), dt=0.01, dp=0.05, xlo=-5.0)
    assert r["stress"] == pytest.approx(0.1, abs=1e-15)
    assert r["shear_rate"] == pytest.approx(0.3, abs=1e-12)
    assert r["viscosity"] == pytest.approx(0.1 / 0.3, abs=1e-12)
    assert r["density_centre"] == pytest.approx(3.0, abs=1e-12)
    assert [h["bins"] for h in r["halves"]] == [10, 10]
    assert len(r["table"]["x"]) == 40


# ---------------------------------------------------------------- Einstein-Helfand


def _ou(rng, n, dt, tau, s2):
    rho = math.exp(-dt / tau)
    kick = math.sqrt(s2 * (1 - rho * rho))
    x = np.empty(n)
    prev = math.sqrt(s2) * rng.standard_normal()
    noise = rng.standard_normal(n)
    for k in range(n):
        prev = rho * prev + kick * noise[k]
        x[k] = prev
    return x


@pytest.fixture(scope="module")
def ou_series():
    # Three OU stress series (sigma^2 = 1, tau = 0.05, sample interval 0.01, 2^18 samples):
    # the Einstein-Helfand integral has slope dt(1+rho)/(1-rho) exactly (tests/analysis.rs).
    rng = np.random.default_rng(100)
    n, dt, tau = 1 << 18, 0.01, 0.05
    comps = [_ou(rng, n, dt, tau, 1.0) for _ in range(3)]
    rho = math.exp(-dt / tau)
    return dict(steps=np.arange(n, dtype=float), comps=comps, exact=dt * (1 + rho) / (1 - rho))


def test_eh_recovers_the_ou_integral_and_is_the_clis(ou_series, cli, tmp_path):
    exact = ou_series["exact"]
    # V/kT = 2 (box 2 x 2 x 2, kT = 4); L = 2 and rho_m such that 0.1 L^2/(4 pi^2 nu) = 1.
    density = 10 * math.pi ** 2 * exact
    kw = dict(dt=0.01, box=[2.0, 2.0, 2.0], temp=4.0, density=density)
    series = {"Step": ou_series["steps"]}
    series.update(zip(["pxy", "pxz", "pyz"], ou_series["comps"]))
    r = dpdnl.eh(series, **kw)
    assert r["t_max"] == pytest.approx(1.0, abs=0.05) and not r["window_capped"]
    assert r["viscosity_err"] < 0.05 * exact
    assert abs(r["viscosity"] - exact) < 4 * r["viscosity_err"]
    # The same numbers written to a fix ave/time file, through the CLI and through Python.
    f = tmp_path / "ou.ave_time"
    _write_series(f, ["pxy", "pxz", "pyz"], ou_series["steps"], ou_series["comps"])
    rf = dpdnl.eh(str(f), **kw)
    assert rf["viscosity"] == r["viscosity"]
    _same_as_cli(
        rf, cli, tmp_path, "eh", str(f), "--dt", 0.01, "--box", 2, 2, 2, "--temp", 4,
        "--density", repr(density),
    )


# ---------------------------------------------------------------- MSD


def test_msd_of_brownian_walkers(cli, tmp_path):
    # 400 walkers, 3-D, D = 0.25, 400 frames: the single-origin MSD (what compute msd writes)
    # gives D within 4 Brownian errors (error D sqrt(3/(N d)) = 5 %).
    rng = np.random.default_rng(5)
    n, d, frames, dt, d0 = 400, 3, 400, 0.1, 0.25
    steps = np.zeros((n, d))
    m = [0.0]
    for _ in range(frames - 1):
        steps = steps + math.sqrt(2 * d0 * dt) * rng.standard_normal((n, d))
        m.append(float((steps ** 2).sum(axis=1).mean()))
    series = {"Step": np.arange(frames, dtype=float), "c_msd[4]": np.array(m)}
    r = dpdnl.msd(series, dt=dt, atoms=n)
    assert r["diffusion_err"] / d0 == pytest.approx(math.sqrt(3 / (n * d)), abs=0.01)
    assert abs(r["diffusion"] - d0) < 4 * r["diffusion_err"]
    # Schmidt number from a given viscosity: Sc = mu / (rho D).
    r2 = dpdnl.msd(series, dt=dt, atoms=n, eta=2.0, density=4.0)
    assert r2["schmidt"] == pytest.approx(2.0 / (4.0 * r2["diffusion"]), rel=1e-14)
    f = tmp_path / "msd.ave_time"
    _write_series(f, ["c_msd[4]"], series["Step"], [series["c_msd[4]"]])
    _same_as_cli(dpdnl.msd(str(f), dt=dt, atoms=n), cli, tmp_path, "msd", str(f), "--dt", dt,
                 "--atoms", n)


def test_msd_lammps_file_is_the_clis(cli, tmp_path):
    p = str(ANALYSIS / "msd_scalar.ave_time")
    _same_as_cli(dpdnl.msd(p, dt=0.005), cli, tmp_path, "msd", p, "--dt", 0.005)


# ---------------------------------------------------------------- Couette and flow curve


@pytest.fixture
def couette_files(tmp_path):
    # P_xy = -eta rate + white noise (eta = 2, rate 0.1, sigma 0.5, 4096 samples), and an exact
    # linear profile v_x = 0.1 (y - 2.5) over 10 bins.
    rng = np.random.default_rng(31)
    pxy = -0.2 + 0.5 * rng.standard_normal(4096)
    s = tmp_path / "shear.ave_time"
    _write_series(s, ["c_p[4]"], np.arange(4096) * 10, [pxy])
    prof = tmp_path / "vx.ave_chunk"
    with open(prof, "w") as f:
        f.write("# Chunk-averaged data for fix p and group all\n"
                "# Timestep Number-of-chunks Total-count\n# Chunk Coord1 Ncount vx\n")
        for k in range(1, 4):
            f.write(f"{100 * k} 10 100\n")
            for i in range(10):
                y = 0.25 + 0.5 * i
                f.write(f"{i + 1} {y!r} 10 {0.1 * (y - 2.5)!r}\n")
    return str(s), str(prof)


def test_couette_and_flowcurve_are_the_clis(couette_files, cli, tmp_path):
    s, prof = couette_files
    r = dpdnl.couette(s, rate=0.1)
    assert abs(r["viscosity"] - 2.0) < 4 * r["viscosity_err"]
    assert r["pxy_err"] == pytest.approx(0.5 / 64, rel=0.25)
    (tmp_path / "a").mkdir()
    _same_as_cli(r, cli, tmp_path / "a", "couette", s, "--rate", 0.1)
    rp = dpdnl.couette(s, profile=prof, label="profile")
    assert rp["shear_rate"] == pytest.approx(0.1, abs=1e-12)
    assert rp["profile"]["v_fit"] == pytest.approx(rp["profile"]["v"], abs=1e-12)
    (tmp_path / "b").mkdir()
    _same_as_cli(rp, cli, tmp_path / "b", "couette", s, "--profile", prof, "--label", "profile")
    # Flow curve from the two results (dicts) = the CLI's from their JSON files.
    fc = dpdnl.flowcurve([r, rp])
    assert [g["label"] for g in fc["groups"]] == ["shear", "profile"]
    cli("analyze", "flowcurve", tmp_path / "a" / "cli.json", tmp_path / "b" / "cli.json",
        "--out", tmp_path / "fc", "--no-plot")
    # Same CSV, to the last digit but one: the CLI reads its JSON files back with serde_json's
    # default float parser, which is not correctly rounded (1 ulp here); Python's is.
    def rows(text):
        return [line.split(",") for line in text.splitlines()]

    ours, theirs = rows(fc["csv"]), rows((tmp_path / "fc.csv").read_text())
    assert ours[0] == theirs[0] and len(ours) == len(theirs) == 3
    for a, b in zip(ours[1:], theirs[1:]):
        assert a[0] == b[0]
        assert [float(x) for x in a[1:]] == pytest.approx([float(x) for x in b[1:]], rel=1e-15)
    g = dpdnl.flowcurve([tmp_path / "a" / "cli.json", tmp_path / "fc.csv"])["groups"][0]
    assert g["label"] == "shear"
    assert g["eta"] == pytest.approx([r["viscosity"], r["viscosity"]], rel=1e-15)


def test_thermo_of_a_simulation_is_a_series():
    sim = dpdnl.Simulation()
    sim.commands([
        "region box block 0 4 0 4 0 4", "create_box 1 box",
        "create_atoms 1 random 192 99 box", "mass 1 1.0",
        "velocity all create 1.0 5 mom yes", "pair_style dpd/nonlinear 1.0 1.0 3",
        "pair_coeff 1 1 25 4.5 0", "fix 1 all nve", "timestep 0.01",
        "thermo 1", "thermo_style custom step temp pxy",
    ])
    sim.run(200)
    r = dpdnl.couette(sim.thermo[-1], rate=0.5)
    assert r["input"] == "<series>" and r["n_samples"] == 201 and r["column"] == "pxy"


# ---------------------------------------------------------------- errors


def test_analysis_errors_are_the_clis(cli, tmp_path):
    bad = tmp_path / "bad.ave_chunk"
    bad.write_text((ANALYSIS / "prof.ave_chunk").read_text().replace("17.8", "17..8", 1))
    p = cli("analyze", "nemd", bad, "--box", 6, 3, 3, "--dt", 0.01, "--dp", 0.1, check=False)
    assert p.returncode != 0
    with pytest.raises(dpdnl.AnalysisError) as e:
        dpdnl.nemd(str(bad), box=(6, 3, 3), dt=0.01, dp=0.1)
    msg = str(e.value)
    assert "bad.ave_chunk" in msg and "line 5" in msg and "'17..8'" in msg
    assert f"ERROR: {msg}" in p.stderr
    with pytest.raises(dpdnl.AnalysisError, match="give --rate"):
        dpdnl.couette(str(ANALYSIS / "press.ave_time"))
    with pytest.raises(FileNotFoundError):
        dpdnl.eh(str(tmp_path / "nope"), dt=0.01, box=[5, 5, 5], temp=1, density=3)
