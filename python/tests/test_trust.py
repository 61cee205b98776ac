"""The Python package as a careless or unlucky user meets it: values that would crash the
interpreter, outputs named like inputs, key paths that say the same thing twice, arguments of
the wrong type. Each is refused with an exception that names the argument or key path."""

import shutil
from pathlib import Path

import numpy as np
import pytest

import foldsim

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "sweep-paper-1panel.toml"
PANEL = ROOT / "examples" / "paper-1panel.toml"


def test_self_containing_and_deep_values_are_refused_not_a_crash():
    d = {"run": {"duration": 1.0}}
    d["run"]["again"] = d
    with pytest.raises(ValueError, match="contains itself"):
        foldsim.from_dict(d)
    loop = []
    loop.append(loop)
    with pytest.raises(ValueError, match=r"run\.x\[0\]: this value contains itself"):
        foldsim.from_dict({"run": {"x": loop}})
    deep = x = {}
    for _ in range(20000):
        x["k"] = {}
        x = x["k"]
    with pytest.raises(ValueError, match="deeper than 64"):
        foldsim.from_dict(deep)
    deep_list = y = []
    for _ in range(20000):
        y.append([])
        y = y[0]
    with pytest.raises(ValueError, match="deeper than 64"):
        foldsim.from_dict({"run": {"x": deep_list}})
    # The same dict twice side by side is not a cycle.
    shared = [1.0, 2.0, 3.0]
    base = foldsim.load(PANEL)
    s = base.with_values({"body.hub.inertia": shared, "body.panel.inertia": shared})
    assert s.get("body.panel.inertia") == shared


def test_numpy_values_are_taken():
    s = foldsim.load(PANEL)
    a = s.with_values({"body.hub.inertia": np.array([100.0, 100.0, 100.0]), "body.panel.mass": np.float64(10.0)})
    b = s.with_values({"body.hub.inertia": [100.0, 100.0, 100.0], "body.panel.mass": 10.0})
    assert a.text == b.text


def test_one_value_by_two_paths_is_refused():
    s = foldsim.load(PANEL)
    with pytest.raises(ValueError, match="'body.1.mass'.*'body.panel.mass'|'body.panel.mass'.*'body.1.mass'"):
        s.with_values({"body.panel.mass": 9.0, "body.1.mass": 11.0})
    with pytest.raises(ValueError, match="both set"):
        s.with_values({"hinge.h1.law.k_theta": 9.0, "hinge.*.law.k_theta": 11.0})


def test_get_of_a_missing_key_raises_key_error_and_takes_a_default():
    s = foldsim.load(PANEL)
    with pytest.raises(KeyError, match="hinge.h1.law.nothing"):
        s.get("hinge.h1.law.nothing")
    with pytest.raises(KeyError, match="no entry named 'h9'"):
        s.get("hinge.h9.law.k_theta")
    assert s.get("hinge.h1.law.nothing", 1.5) == 1.5
    assert s.get("hinge.h1.law.k_theta") == 10.0


def test_wrong_argument_types_name_the_argument():
    with pytest.raises(TypeError, match="path"):
        foldsim.load(None)
    with pytest.raises(TypeError, match="dict"):
        foldsim.from_dict([1, 2])
    with pytest.raises(TypeError, match="text"):
        foldsim.from_toml(b"title = 'x'")


def test_run_takes_columns_as_a_string_as_the_command_line_does():
    s = foldsim.load(PANEL).with_values({"run.duration": 0.5})
    assert s.run(columns="t,h1_yaw", progress=False).columns == ["t", "h1_yaw"]
    assert s.run(columns=["t", "h1_*"], progress=False).columns[:2] == ["t", "h1_delta_x"]


def test_sweep_arguments_and_outputs_are_checked(tmp_path: Path):
    for bad in [{"workers": 0}, {"chunk_size": 0}, {"workers": -3}]:
        with pytest.raises(ValueError, match=next(iter(bad))):
            foldsim.sweep(EXAMPLE, runs=2, progress=False, **bad)
    with pytest.raises(TypeError, match="workers"):
        foldsim.sweep(EXAMPLE, runs=2, workers=1.5, progress=False)
    # An output that is the scenario, or in a directory that does not exist: refused before any run.
    copy = tmp_path / "s.toml"
    shutil.copy(EXAMPLE, copy)
    before = copy.read_bytes()
    with pytest.raises(ValueError, match="is an input"):
        foldsim.sweep(copy, runs=2, output=copy, progress=False)
    assert copy.read_bytes() == before
    with pytest.raises(ValueError, match="does not exist"):
        foldsim.sweep(copy, runs=2, output=tmp_path / "nodir" / "t.csv", progress=False)
    with pytest.raises(ValueError, match="is a directory"):
        foldsim.sweep(copy, runs=2, output=tmp_path, progress=False)
    # More workers than runs: capped, and said.
    with pytest.warns(UserWarning, match="using 2"):
        t = foldsim.sweep(EXAMPLE, runs=2, workers=100000, progress=False)
    assert len(t) == 2


def test_swept_paths_are_checked_before_the_first_run():
    s = foldsim.load(PANEL)
    u = {"distribution": "uniform", "low": 1.0, "high": 2.0}
    for params, says in [
        ({"hinge.h1.law.k_theta": u, "hinge.*.law.k_theta": u}, "both set"),
        ({"run.integrator": u}, "a sweep draws numbers"),
        ({"hinge.h1.law.k_thetaa": u}, "not in the scenario"),
        ({"sweep.runs": u}, r"inside \[sweep\]"),
    ]:
        with pytest.raises(ValueError, match=says):
            foldsim.sweep(s, params, runs=2, seed=1, progress=False)


def test_a_sweep_in_which_every_run_fails_raises_with_the_first_error(tmp_path: Path):
    s = foldsim.load(PANEL).with_values({"run.duration": 0.5})
    bad = {"hinge.h1.law.k_theta": {"distribution": "uniform", "low": -2.0, "high": -1.0}}
    out = tmp_path / "t.csv"
    with pytest.raises(RuntimeError, match="every run of the sweep failed.*run 0:.*k_theta"):
        foldsim.sweep(s, bad, runs=3, seed=1, output=out, progress=False)
    assert out.exists(), "the table of failures is kept"


def test_save_never_replaces_a_table_the_scenario_reads(tmp_path: Path):
    shutil.copytree(ROOT / "examples" / "tables", tmp_path / "tables")
    shutil.copy(ROOT / "examples" / "zfold-tape-latch.toml", tmp_path / "z.toml")
    s = foldsim.load(tmp_path / "z.toml")
    table = tmp_path / "tables" / "tape-spring-increasing.csv"
    before = table.read_bytes()
    with pytest.raises(ValueError, match="is an input"):
        s.save(table)
    assert table.read_bytes() == before
    s.save(tmp_path / "copy.toml")
    assert (tmp_path / "copy.toml").read_text() == s.text


def test_generator_errors_name_the_argument():
    for call, kind, says in [
        (lambda: foldsim.generate.flasher(6, 3, k_fold="x"), TypeError, "option k_fold"),
        (lambda: foldsim.generate.flasher(6, 3, hub_inertia=[1.0, 2.0]), ValueError, "option hub_inertia"),
        (lambda: foldsim.generate.flasher(6, 3, hub_radius=-1.0), ValueError, "hub_radius must be a positive number in m; got -1"),
        (lambda: foldsim.generate.flasher(6, 3, release_at=99.0), ValueError, "release_at must lie strictly between 0 and duration"),
        (lambda: foldsim.generate.flasher(6, 3, areal_density=1e-300), ValueError, "these options give a scenario that foldsim refuses"),
        (lambda: foldsim.generate.zfold("3"), TypeError, "panels must be a whole number"),
        (lambda: foldsim.generate.zfold(-3), ValueError, "panels must be a whole number"),
        (lambda: foldsim.generate.grid(3, 2.5), TypeError, "cols must be a whole number"),
        (lambda: foldsim.generate.zfold(3, panel_mass=1e300 * 1e300), ValueError, "panel_mass must be a positive number in kg; got inf"),
    ]:
        with pytest.raises(kind, match=says):
            call()


def test_progress_off_a_terminal_is_a_line_at_the_interval(monkeypatch, capsys):
    monkeypatch.setenv("FOLDSIM_PROGRESS_EVERY", "0.05")
    s = foldsim.load(ROOT / "examples" / "paper-3panel.toml").with_values({"run.rtol": 1e-13, "run.atol": 1e-13, "run.duration": 200.0, "run.output_step": 1.0})
    s.run()
    err = capsys.readouterr().err
    assert "foldsim: " in err and " of 200 s (" in err, err
    s.run(progress=False)
    assert capsys.readouterr().err == ""
