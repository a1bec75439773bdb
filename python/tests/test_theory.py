"""Theory and design: the CLI's JSON (`dpdnl design/theory --json`) for the same arguments, and
the known answers of the exact design (tests/theory.rs: the targets come back to round-off)."""

import dataclasses
import math

import pytest

import dpdnl


@pytest.mark.parametrize(
    "kw",
    [
        dict(eta=10.0, sc=400.0, density=4.0, rc=1.0),
        dict(eta=1.5, sc=20.0, density=4.0, rc=1.0, dim=2, kt=0.1, mass=2.0),
        dict(eta=4.0, sc=400.0, density=3.0, rc=1.0, paper_approx=True, seed=7),
    ],
)
def test_design_is_the_clis(kw, cli_json):
    d = dpdnl.design(**kw)
    args = ["design"]
    for k, v in kw.items():
        if k == "paper_approx":
            args.append("--paper-approx")
        else:
            args += [f"--{k}", v]
    assert d.to_json() == cli_json(*args, "--json")
    if not kw.get("paper_approx"):
        # The exact inversion meets the targets to round-off.
        assert math.isclose(d.predicted.eta, kw["eta"], rel_tol=1e-12)
        assert math.isclose(d.predicted.schmidt, kw["sc"], rel_tol=1e-12)
        assert d.predicted.eta_d == pytest.approx(d.eta0, rel=1e-12)
    assert d.pair_coeff.startswith("pair_coeff * * 0.0 ")
    assert dataclasses.asdict(d)["fluid"]["density"] == kw["density"]


def test_theory_is_the_clis(cli_json):
    t = dpdnl.theory(4.5, 1.0, 3.0, 1.0, dt=0.04)
    assert t == cli_json(
        "theory", "--gamma", 4.5, "--s", 1.0, "--density", 3.0, "--rc", 1.0, "--dt", 0.04, "--json"
    )
    k = dpdnl.kinetic_theory(4.5, 1.0, 3.0, 1.0)
    assert dataclasses.asdict(k) == t["predicted"]
    e = dpdnl.euler_temperature(4.5, 1.0, 3.0, 1.0, 0.04)
    assert dataclasses.asdict(e) == t["euler"]
    assert e.stable and e.t_ratio > 1.0  # Euler heats the fluid
    # Beyond the critical step: unstable, no temperature.
    u = dpdnl.euler_temperature(4.5, 1.0, 3.0, 1.0, 1.1 * e.dt_c)
    assert not u.stable and u.t_ratio is None


def test_kinetic_theory_closed_form():
    # 3-D, s = 2: [w_D] = 4 pi rc^3 * 2! / (3*4*5) = 2 pi / 15 (rc = 1); eta_K = d m kT / (2 Gamma)
    g = 4.5
    gam = g * 2 * math.pi / 15
    k = dpdnl.kinetic_theory(g, 2.0, 3.0, 1.0)
    assert k.eta_k == pytest.approx(3 / (2 * gam), rel=1e-14)
    assert k.diffusion == pytest.approx(3 / (3.0 * gam), rel=1e-14)
    assert k.eta == pytest.approx(k.eta_k + k.eta_d, rel=1e-15)


def test_unreachable_design_gives_the_clis_message(cli):
    p = cli("design", "--eta", 100, "--sc", 1.0, "--density", 3, "--rc", 1, check=False)
    assert p.returncode != 0
    with pytest.raises(dpdnl.TheoryError) as e:
        dpdnl.design(eta=100, sc=1.0, density=3, rc=1)
    assert f"ERROR: {e.value}" in p.stderr
    with pytest.raises(dpdnl.TheoryError, match="dimension"):
        dpdnl.kinetic_theory(1.0, 1.0, 3.0, 1.0, dim=4)
    with pytest.raises(ValueError):  # TheoryError is a ValueError
        dpdnl.kinetic_theory(-1.0, 1.0, 3.0, 1.0)
