"""vpm.study and vpm.sweep: the tool's files, and their tables as rows."""
import csv
import os

import vpm
from conftest import FURNACE


def test_study_writes_the_tools_files_and_returns_their_rows(tmp_path):
    rows = vpm.study(out=tmp_path, dims=[3], k=[4, 8], trials=400, n=200, scenarios=["uniform"], as_dataframe=False)
    assert {f for f in os.listdir(tmp_path)} == {"study.csv", "study.md", "study.json"}
    with open(tmp_path / "study.csv") as f:
        on_disk = list(csv.DictReader(f))
    assert len(rows) == len(on_disk) == 2 * 3   # two k, three estimators
    assert [r["estimator"] for r in rows] == [r["estimator"] for r in on_disk]
    assert all(isinstance(r["k"], int) and isinstance(r["mean_rel_error"], float) for r in rows)
    # corrected is exactly unbiased for a uniform density: within 4 standard errors of 0
    for r in rows:
        if r["estimator"] == "corrected":
            assert abs(r["mean_rel_error"]) < 4 * r["se_mean"]


def test_study_with_no_folder_writes_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    rows = vpm.study(out=None, dims=[2], k=[4], trials=100, n=100, scenarios=["uniform"], as_dataframe=False)
    assert len(rows) == 3 and not any(tmp_path.iterdir())


def test_sweep_runs_resumes_and_returns_its_tables(tmp_path):
    sweep_file = tmp_path / "tiny.toml"
    sweep_file.write_text(
        'scene = "%s"\n'
        'set = ["render.width=8", "render.height=8", "render.spp=1", "photons.count=2000"]\n'
        'repeats = 1\n[reference]\nspp = 8\n[axes]\nk = [4, 8]\n' % FURNACE.replace("\\", "/"))
    out = tmp_path / "out"
    tables = vpm.sweep(sweep_file, out=out, log=False, as_dataframe=False)
    assert tables.outcome["ran"] == 2 and len(tables.runs) == 2 and len(tables.points) == 2
    assert sorted(r["k"] for r in tables.runs) == [4, 8]
    assert "rel_rmse" in tables.runs[0] and tables.summary
    again = vpm.sweep(sweep_file, out=out, log=False, as_dataframe=False)
    assert again.outcome["ran"] == 0 and again.outcome["skipped"] == 2 and len(again.runs) == 2


def test_bad_sweep_file_raises_with_the_message(tmp_path):
    sweep_file = tmp_path / "bad.toml"
    sweep_file.write_text('scene = "%s"\n[reference]\nspp = 4\n[axes]\nk = ["many"]\n' % FURNACE.replace("\\", "/"))
    try:
        vpm.sweep(sweep_file, out=tmp_path / "out", log=False)
    except vpm.Error as e:
        assert "bad.toml" in str(e) and "photons.k" in str(e)
    else:
        raise AssertionError("a bad axis value did not raise")
