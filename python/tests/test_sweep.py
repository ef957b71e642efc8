"""`Mechanism.sweep` and `Mechanism.batch` against the `mechgen` command (interfaces.md): the
same columns, statuses and values as its CSV, to the last digit written."""

import subprocess

import numpy as np
import pandas as pd
import pytest

import mechgen

NAMES = sorted(mechgen.mechanisms())


def run(mechgen_bin, *args):
    out = subprocess.run([str(mechgen_bin), *args], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr


def same_frames(got, want):
    assert list(got.columns) == list(want.columns)
    assert len(got) == len(want)
    assert (got["status"].astype(str).values == want["status"].astype(str).values).all()
    for c in want.columns:
        if c == "status":
            continue
        a, b = got[c].to_numpy(dtype=float), want[c].to_numpy(dtype=float)
        same = (a == b) | (np.isnan(a) & np.isnan(b))
        assert same.all(), f"{c}: {a[~same]} vs {b[~same]}"


def test_every_default_mechanism_is_compiled_in():
    assert NAMES == ["four_bar", "rocker_four_bar", "shaper", "sixbar", "sixbar_g", "slider_crank"]
    m = mechgen.mechanisms()["sixbar"]
    assert m.engine == "generated"
    assert m.inputs == ["q1"] and m.unknowns == ["q2", "q3", "q5", "q6"] and m.points == ["E"]
    assert set(m.params) >= {"l1", "l2", "alpha"}


@pytest.mark.parametrize("name", NAMES)
def test_sweep_frame_equals_the_csv_of_mechgen_sweep(name, mechgen_bin, tmp_path):
    csv = tmp_path / f"{name}.csv"
    run(mechgen_bin, "sweep", name, "--csv", str(csv))
    got = pd.DataFrame(mechgen.mechanisms()[name].sweep())
    same_frames(got, pd.read_csv(csv))
    assert not got.loc[got["status"] == "ok"].drop(columns="status").isna().any().any()


def test_options_are_the_commands(mechgen_bin, tmp_path):
    csv = tmp_path / "opts.csv"
    run(mechgen_bin, "sweep", "four_bar", "--from", "30", "--to", "200", "--step", "7", "--rate", "2.5",
        "--csv", str(csv))
    got = pd.DataFrame(mechgen.mechanisms()["four_bar"].sweep(start=30, stop=200, step=7, rate=2.5))
    same_frames(got, pd.read_csv(csv))


def test_held_inputs_are_columns_as_in_the_csv(mechgen_bin, tmp_path):
    """A two-input five-bar swept along q4 with q1 held: the held input is a column after the
    swept one, its value on every row, in `sweep` and `batch` as in the command's CSV."""
    from conftest import ROOT
    path = ROOT / "tests" / "data" / "sweep" / "fivebar.toml"
    csv = tmp_path / "fivebar.csv"
    run(mechgen_bin, "sweep", "fivebar", "--file", str(path), "--input", "q4", "--set", "q1=60",
        "--from", "60", "--to", "120", "--step", "5", "--csv", str(csv))
    m = mechgen.load(str(path))["fivebar"]
    # The same object swept along q1 first (its column names are kept per input swept).
    assert list(m.sweep(start=60, stop=70, step=5))[:2] == ["q1", "q4"]
    got = m.sweep(start=60, stop=120, step=5, input="q4", set={"q1": 60.0})
    assert list(got)[:2] == ["q4", "q1"]
    assert list(m.sweep(start=60, stop=70, step=5, input="q1"))[:2] == ["q1", "q4"]
    assert (got["q1"] == np.radians(60.0)).all()
    same_frames(pd.DataFrame(got), pd.read_csv(csv))
    sets = {"l1": np.array([0.1, 0.1])}
    many = m.batch(sets, start=60, stop=120, step=5, input="q4", set={"q1": 60.0})
    assert list(many)[:2] == ["q4", "q1"] and many["q1"].shape == (2, 13)
    assert (many["q1"] == np.radians(60.0)).all()


def test_a_loaded_file_runs_compiled_or_interpreted_with_the_same_api(mechgen_bin, tmp_path):
    import pickle
    from conftest import ROOT
    path = ROOT / "mechanism.toml"
    jit_csv, generic_csv = tmp_path / "jit.csv", tmp_path / "generic.csv"
    run(mechgen_bin, "sweep", "shaper", "--file", str(path), "--csv", str(jit_csv))
    run(mechgen_bin, "sweep", "shaper", "--file", str(path), "--engine", "generic", "--csv", str(generic_csv))
    # The JIT is the interpreter in machine code: the same bytes.
    assert jit_csv.read_bytes() == generic_csv.read_bytes()
    j = mechgen.load(str(path))["shaper"]
    g = mechgen.load(str(path), engine="generic")["shaper"]
    assert (j.engine, g.engine) == ("jit", "generic")
    assert mechgen.load(str(path), engine="jit")["shaper"].engine == "jit"
    same_frames(pd.DataFrame(j.sweep()), pd.read_csv(jit_csv))
    same_frames(pd.DataFrame(g.sweep()), pd.read_csv(generic_csv))
    assert pickle.loads(pickle.dumps(g)).engine == "generic"
    assert pickle.loads(pickle.dumps(j)).engine == "jit"
    with pytest.raises(ValueError, match="jit` or `generic"):
        mechgen.load(str(path), engine="generated")


@pytest.mark.parametrize(
    "name, varied, spread, step",
    [
        ("sixbar", ("l1", "l2", "l3", "l5"), 0.02, 10.0),
        # The rocker's sweep starts mid-range (rows below the start, solved downward) and its
        # sets reach their dead points at different rows; some leave the lanes.
        ("rocker_four_bar", ("l1", "l2", "l3"), 0.15, 7.0),
    ],
)
def test_batch_equals_mechgen_batch_row_for_row(name, varied, spread, step, mechgen_bin, tmp_path):
    """`Mechanism.batch` (sets in SIMD lanes) against the CSV of `mechgen batch`: every row,
    status and value."""
    rng = np.random.default_rng(7)
    m = mechgen.mechanisms()[name]
    n = 203
    sets = {p: m.params[p] * (1 + spread * rng.standard_normal(n)) for p in varied}
    pd.DataFrame(sets).to_csv(tmp_path / "sets.csv", index=False, float_format="%.17g")
    read = pd.read_csv(tmp_path / "sets.csv")
    sets = {p: read[p].to_numpy() for p in read.columns}
    csv = tmp_path / "rows.csv"
    run(mechgen_bin, "batch", name, "--params", str(tmp_path / "sets.csv"), "--step", str(step), "--csv", str(csv))
    want = pd.read_csv(csv)
    cols = m.batch(sets, step=step)
    rows = len(want) // n
    assert cols["status"].shape == (n, rows)
    got = pd.DataFrame({c: v.reshape(-1) for c, v in cols.items()})
    same_frames(got, want.drop(columns="set"))
    assert (want["set"].to_numpy() == np.repeat(np.arange(n), rows)).all()
    # Both kinds of row: solved, and past the branch's end.
    assert (want["status"] == "ok").any()
    if name == "rocker_four_bar":
        assert (want["status"] != "ok").any()


@pytest.mark.parametrize("name", ["sixbar", "slider_crank", "shaper", "rocker_four_bar"])
def test_sensitivity_frame_equals_the_csv_of_mechgen_sensitivity(name, mechgen_bin, tmp_path):
    csv = tmp_path / f"{name}-sens.csv"
    run(mechgen_bin, "sensitivity", name, "--csv", str(csv))
    got = pd.DataFrame(mechgen.mechanisms()[name].sensitivity())
    want = pd.read_csv(csv)
    same_frames(got, want)
    assert (got["status"] == "ok").any()
    # The generic engine gives the same columns and statuses, values to 1e-9 of each column.
    from conftest import ROOT
    g = pd.DataFrame(mechgen.load(str(ROOT / "mechanism.toml"))[name].sensitivity())
    assert list(g.columns) == list(got.columns)
    assert (g["status"].values == got["status"].values).all()
    ok = got["status"] == "ok"
    for c in got.columns:
        if c != "status":
            a, b = got.loc[ok, c].to_numpy(), g.loc[ok, c].to_numpy()
            assert np.abs(a - b).max() <= 1e-9 * max(1.0, np.abs(a).max()), c


@pytest.mark.parametrize("name", ["shaper", "slider_crank", "sixbar", "four_bar"])
def test_dynamics_frame_equals_the_csv_of_mechgen_dynamics(name, mechgen_bin, tmp_path):
    """`Mechanism.dynamics` against `mechgen dynamics` (loads over a range, an acceleration): the
    same columns and values, compiled in and loaded (the JIT gives the same bytes)."""
    from conftest import ROOT
    m = mechgen.mechanisms()[name]
    point = m.points[0]
    csv = tmp_path / f"{name}-dyn.csv"
    run(mechgen_bin, "dynamics", name, "--step", "5", "--rate", "4.5", "--acc", "-2",
        "--load", f"{point}=-30,12@40:250", "--csv", str(csv))
    want = pd.read_csv(csv)
    kw = dict(step=5.0, rate=4.5, acc=-2.0, loads=[(point, -30.0, 12.0, (40.0, 250.0))])
    got = pd.DataFrame(m.dynamics(**kw))
    same_frames(got, want)
    assert (got["status"] == "ok").all()
    loaded = pd.DataFrame(mechgen.load(str(ROOT / "mechanism.toml"))[name].dynamics(**kw))
    same_frames(loaded, want)


def test_dynamics_refuses_what_it_cannot_do():
    with pytest.raises(ValueError, match="has no bodies"):
        mechgen.mechanisms()["rocker_four_bar"].dynamics()
    with pytest.raises(KeyError, match="no point"):
        mechgen.mechanisms()["shaper"].dynamics(loads=[("Z", 1.0, 2.0)])
    with pytest.raises(ValueError, match="a load is"):
        mechgen.mechanisms()["shaper"].dynamics(loads=[("E", 1.0, float("nan"))])


def test_simulate_frame_equals_the_csv_of_mechgen_simulate(mechgen_bin, tmp_path):
    """`Mechanism.simulate` against `mechgen simulate`: the four-bar falling under gravity with a
    torque, the same rows to the last digit; the loaded file (JIT) too."""
    from conftest import ROOT
    csv = tmp_path / "sim.csv"
    run(mechgen_bin, "simulate", "four_bar", "--time", "0.5", "--dt", "0.01", "--torque", "0.3",
        "--rate", "1.5", "--load", "P=0,-2", "--csv", str(csv))
    want = pd.read_csv(csv)
    kw = dict(time=0.5, dt=0.01, torque=0.3, rate=1.5, loads=[("P", 0.0, -2.0)])
    got = pd.DataFrame(mechgen.mechanisms()["four_bar"].simulate(**kw))
    same_frames(got, want)
    assert len(got) == 51 and (got["status"] == "ok").all()
    loaded = pd.DataFrame(mechgen.load(str(ROOT / "mechanism.toml"))["four_bar"].simulate(**kw))
    same_frames(loaded, want)
    # A load acting over a range of the input, as `dynamics` takes it: the same rows as the CLI's.
    run(mechgen_bin, "simulate", "four_bar", "--time", "0.5", "--dt", "0.01", "--rate", "3",
        "--load", "P=0,-20@210:300", "--csv", str(csv))
    want = pd.read_csv(csv)
    kw = dict(time=0.5, dt=0.01, rate=3.0, loads=[("P", 0.0, -20.0, (210.0, 300.0))])
    ranged = pd.DataFrame(mechgen.mechanisms()["four_bar"].simulate(**kw))
    same_frames(ranged, want)
    free = pd.DataFrame(mechgen.mechanisms()["four_bar"].simulate(time=0.5, dt=0.01, rate=3.0))
    assert not np.allclose(ranged["q1"], free["q1"]), "the ranged load acts"




def test_simulate_rests_on_a_load_edge_both_sides_push_into(mechgen_bin, tmp_path):
    """A crank at rest on the edge of a load's range, turned into the range by its torque and out
    of it by the load: every row rests there with status `at-load-edge`, as the CLI's CSV says."""
    from conftest import ROOT
    path = ROOT / "tests" / "data" / "lift.toml"
    csv = tmp_path / "lift.csv"
    run(mechgen_bin, "simulate", "lift", "--file", str(path), "--time", "0.2", "--dt", "0.01",
        "--torque", "2", "--load", "Top=0,-50@0:180", "--csv", str(csv))
    want = pd.read_csv(csv)
    got = pd.DataFrame(mechgen.load(str(path))["lift"].simulate(
        time=0.2, dt=0.01, torque=2.0, loads=[("Top", 0.0, -50.0, (0.0, 180.0))]))
    same_frames(got, want)
    assert len(got) == 21 and (got["status"] == "at-load-edge").all()
    assert (got["th"] == 0.0).all() and (got["th_vel"] == 0.0).all()


SCENES = [(m, s) for m in NAMES for s in mechgen.mechanisms()[m].scenes]


@pytest.mark.parametrize("mech,scene", SCENES)
def test_a_scene_sweeps_as_mechgen_sweep_scene(mech, scene, mechgen_bin, tmp_path):
    """`Mechanism.scene(name)`: the columns and values of `mechgen sweep SCENE`'s CSV."""
    csv = tmp_path / f"{scene}.csv"
    run(mechgen_bin, "sweep", scene, "--step", "7", "--csv", str(csv))
    s = mechgen.mechanisms()[mech].scene(scene)
    assert (s.name, s.mechanism) == (scene, mech)
    same_frames(pd.DataFrame(s.sweep(step=7)), pd.read_csv(csv))


def test_a_scenes_batch_equals_mechgen_batch_scene_compiled_in_and_loaded(mechgen_bin, tmp_path):
    from conftest import ROOT

    rng = np.random.default_rng(3)
    m = mechgen.mechanisms()["sixbar"]
    n = 40
    sets = {p: m.params[p] * (1 + 0.02 * rng.standard_normal(n)) for p in ("l1", "l3")}
    pd.DataFrame(sets).to_csv(tmp_path / "sets.csv", index=False, float_format="%.17g")
    read = pd.read_csv(tmp_path / "sets.csv")
    sets = {p: read[p].to_numpy() for p in read.columns}
    file = str(ROOT / "mechanism.toml")
    for args, scene in [
        ([], m.scene("sixbar_output")),
        (["--file", file], mechgen.load(file)["sixbar"].scene("sixbar_output")),
    ]:
        rows_csv = tmp_path / "rows.csv"
        run(mechgen_bin, "batch", "sixbar_output", *args, "--params", str(tmp_path / "sets.csv"),
            "--step", "15", "--csv", str(rows_csv))
        want = pd.read_csv(rows_csv)
        cols = scene.batch(sets, step=15)
        assert list(cols) == ["q1", "q6", "q6_vel", "q6_acc", "cond", "status"]
        assert cols["status"].shape == (n, 25)
        rows = pd.DataFrame({c: v.reshape(-1) for c, v in cols.items()})
        same_frames(rows, want.drop(columns="set"))


def test_a_scene_pickles_and_leaves_whole_mechanism_methods_to_its_mechanism():
    import pickle

    m = mechgen.mechanisms()["four_bar"]
    assert m.scenes == ["coupler_curve"] and m.mechanism is None
    s = m.scene("coupler_curve")
    # A scene's unknowns and points are its outputs; its inputs and params its mechanism's.
    assert (m.unknowns, m.points, m.order) == (["q2", "q3"], ["B", "C", "P"], 2)
    assert (s.unknowns, s.points, s.order) == ([], ["P"], 1)
    assert (s.inputs, s.params) == (m.inputs, m.params)
    six = mechgen.mechanisms()["sixbar"].scene("sixbar_output")
    assert (six.unknowns, six.points, six.order) == (["q6"], [], 2)
    again = pickle.loads(pickle.dumps(s))
    assert (again.name, again.mechanism) == ("coupler_curve", "four_bar")
    assert (again.unknowns, again.points, again.order) == ([], ["P"], 1)
    same_frames(pd.DataFrame(again.sweep()), pd.DataFrame(s.sweep()))
    for call in (lambda: s.dynamics(), lambda: s.simulate(time=0.1, dt=0.01), lambda: s.sensitivity()):
        with pytest.raises(ValueError, match="`coupler_curve` is a scene of `four_bar`"):
            call()
    with pytest.raises(KeyError, match="its scenes: coupler_curve"):
        m.scene("coupler")
