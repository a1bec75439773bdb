"""The readers on the repository's test data: the values the Rust tests (tests/logparse.rs,
tests/analysis.rs) assert, and every number against an independent NumPy parse of the file."""

import numpy as np
import pytest

import dpdnl
from conftest import DATA

ANALYSIS = DATA / "analysis"


def _numeric_rows(path, skip_comments=True):
    rows = []
    for line in path.read_text().splitlines():
        t = line.split()
        if not t or (skip_comments and line.lstrip().startswith("#")):
            continue
        rows.append([float(x) for x in t])
    return rows


def test_lammps_2022_log():
    (b,) = dpdnl.read_log(DATA / "diff_logs" / "log_lammps2022.lammps")
    assert list(b) == ["Step", "Temp", "E_pair", "E_mol", "TotEng", "Press"]
    assert np.array_equal(b["Step"], np.arange(11) * 100.0)
    assert [b[k][0] for k in b] == [0.0, 1.0, 25.104742, 0.0, 26.604242, 23.815478]
    assert b["Temp"][5] == 1.0085476


def test_lammps_2025_log_two_runs():
    a, b = dpdnl.read_log(DATA / "diff_logs" / "log_lammps2025.lammps")
    assert list(a) == ["Step", "Temp", "Press"] and len(a["Step"]) == 5
    assert [a[k][4] for k in a] == [200.0, 0.99704211, 23.634182]
    assert list(b)[5] == "c_pxy[4]"
    assert b["Step"][-1] == 450.0 and b["c_pxy[4]"][-1] == -0.00863709949995196
    assert b["v_eta"][-1] == -0.00148192789534372
    # The series joins runs with the last run's columns only.
    s = dpdnl.read_series(DATA / "diff_logs" / "log_lammps2025.lammps")
    assert np.array_equal(s["Step"], b["Step"])


DUMP = """\
ITEM: TIMESTEP
100
ITEM: NUMBER OF ATOMS
3
ITEM: BOX BOUNDS pp pp pp
0.0 8.0
-1.0 7.0
0 8
ITEM: ATOMS id type x y z vx
3 1 0.5 0.5 0.5 -0.1
1 1 1.5 2.5 3.5 0.2
2 2 4.0 4.0 4.0 0.0
ITEM: TIMESTEP
200
ITEM: NUMBER OF ATOMS
3
ITEM: BOX BOUNDS xy xz yz pp pp pp
0.0 8.5 0.5
0.0 8.0 0.0
0.0 8.0 0.25
ITEM: ATOMS id type x y z vx
2 2 4.1 4.0 4.0 0.01
1 1 1.6 2.5 3.5 0.2
3 1 0.4 0.5 0.5 -0.1
"""


def test_dump_frames(tmp_path):
    p = tmp_path / "dump.txt"
    p.write_text(DUMP)
    f, g = dpdnl.read_dump(p)
    assert f["step"] == 100 and f["tilt"] is None
    assert np.array_equal(f["box_bounds"], [[0.0, 8.0], [-1.0, 7.0], [0.0, 8.0]])
    assert list(f["atoms"]) == ["id", "type", "x", "y", "z", "vx"]
    assert np.array_equal(f["atoms"]["id"], [1, 2, 3])  # sorted by id
    assert [f["atoms"][k][0] for k in f["atoms"]] == [1.0, 1.0, 1.5, 2.5, 3.5, 0.2]
    assert g["step"] == 200 and g["tilt"] == (0.5, 0.0, 0.25)
    assert g["box_bounds"][0].tolist() == [0.0, 8.5]
    assert dpdnl.read_dump(text=DUMP)[1]["atoms"]["x"].tolist() == [1.6, 4.1, 0.4]
    assert dpdnl.detect_kind(p) == "dump" and len(dpdnl.read(p)) == 2


def test_ave_time_scalar():
    p = ANALYSIS / "press.ave_time"
    r = dpdnl.read_ave_time(p)
    assert r["mode"] == "scalar"
    assert list(r["data"]) == ["c_thermo_press[4]", "c_thermo_press[5]", "c_thermo_press[6]"]
    assert len(r["steps"]) == 31 and r["steps"][:3].tolist() == [0, 1, 2]
    assert [r["data"][k][1] for k in r["data"]] == [-0.0891443, 0.788304, 0.686269]
    ref = np.array(_numeric_rows(p))
    assert np.array_equal(r["steps"], ref[:, 0])
    for j, k in enumerate(r["data"]):
        assert np.array_equal(r["data"][k], ref[:, j + 1])
    s = dpdnl.read_series(p)
    assert s["c_thermo_press[5]"][30] == -0.457938 and np.array_equal(s["Step"], ref[:, 0])


def test_ave_time_vector():
    p = ANALYSIS / "msd_vector.ave_time"
    r = dpdnl.read_ave_time(p)
    assert r["mode"] == "vector" and len(r["blocks"]) == 3
    b = r["blocks"][1]
    assert b["step"] == 20 and len(b["data"]["Row"]) == 4
    assert [b["data"]["Row"][3], b["data"]["c_msd"][3]] == [4.0, 0.130877]
    with pytest.raises(dpdnl.FormatError, match="vector mode"):
        dpdnl.read_series(p)


def test_ave_chunk():
    p = ANALYSIS / "prof.ave_chunk"
    r = dpdnl.read_ave_chunk(p)
    assert r["columns"] == ["Chunk", "Coord1", "Ncount", "vz", "density/number", "temp"]
    assert len(r["blocks"]) == 3 and r["steps"].tolist() == [10, 20, 30]
    b0 = r["blocks"][0]
    assert b0["header"] == [10.0, 200.00000000000003] and b0["nchunks"] == 10
    last = r["blocks"][2]["data"]
    assert [last[c][9] for c in r["columns"]] == [10.0, 5.7, 20.6, -0.278555, 3.81481, 1.10626]
    # Every chunk line, in order, as NumPy reads it.
    rows = [x for x in _numeric_rows(p) if len(x) == 6]
    got = np.concatenate(
        [np.column_stack([b["data"][c] for c in r["columns"]]) for b in r["blocks"]]
    )
    assert np.array_equal(got, np.array(rows))
    for b in r["blocks"]:
        assert abs(b["data"]["Ncount"].sum() - b["total"]) < 1e-3


def test_ave_histo():
    r = dpdnl.read_ave_histo(ANALYSIS / "speed_one.ave_histo")
    assert len(r["blocks"]) == 3
    b = r["blocks"][0]
    assert len(b["coord"]) == 30 and b["count"].sum() == pytest.approx(b["total"])
    assert np.allclose(b["fraction"], b["count"] / b["total"], atol=1e-6)
    assert dpdnl.detect_kind(ANALYSIS / "speed_one.ave_histo") == "ave/histo"


def test_format_errors_name_file_line_and_token(tmp_path):
    bad = tmp_path / "bad.ave_chunk"
    bad.write_text((ANALYSIS / "prof.ave_chunk").read_text().replace("0.327718", "0.32x7718", 1))
    with pytest.raises(dpdnl.FormatError) as e:
        dpdnl.read_ave_chunk(bad)
    msg = str(e.value)
    assert msg.startswith(str(bad)) and "line 5" in msg and "'0.32x7718'" in msg
    with pytest.raises(dpdnl.FormatError, match="YAML"):
        dpdnl.read_ave_time(text="---\nkeywords: ['Step', 'c_t']\n")
    with pytest.raises(FileNotFoundError, match="nope"):
        dpdnl.read_log(tmp_path / "nope")
    with pytest.raises(TypeError):
        dpdnl.read_log()
