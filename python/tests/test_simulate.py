"""`flexmbd.simulate` against the `flexmbd` program: the same numbers, bit for bit."""

import csv
import json
import sys
import threading
import time

import numpy as np
import pytest

import flexmbd
from conftest import model, run_cli


def read_csv(path):
    """The CLI's CSV: its header and its rows as float64 (Python's float reads `{:?}` of
    an f64 back to the same bits)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]], dtype=np.float64)


def same_bits(a, b):
    """Equal bit for bit (NaN included)."""
    return a.shape == b.shape and np.array_equal(a.view(np.int64), b.view(np.int64))


@pytest.mark.parametrize("formulation", ["absolute", "relative"])
def test_double_four_bar_is_the_clis_csv_bit_for_bit(cli, tmp_path, formulation):
    out = tmp_path / "out.csv"
    scene = model("double_four_bar.ron")
    done = run_cli(cli, "simulate", scene, "--formulation", formulation, "--json", "--output", str(out))
    assert done.returncode == 0, done.stderr
    header, rows = read_csv(out)

    result = flexmbd.simulate(scene, formulation=formulation)

    assert result.status == "ok"
    assert result.columns == header
    assert same_bits(result.data, rows)
    cli_summary = json.loads(done.stdout)
    assert result.summary.keys() == cli_summary.keys()
    for key in ["formulation", "n_coordinates", "n_constraints", "steps", "newton_iterations",
                "factorizations", "simulated_seconds", "rows", "warnings"]:
        assert result.summary[key] == cli_summary[key], key


def test_options_and_sets_are_the_clis(cli, tmp_path):
    out = tmp_path / "out.csv"
    scene = model("double_four_bar.ron")
    args = ["--step", "0.002", "--duration", "0.5", "--set", "solver.output_interval=0.01",
            "--set", "bodies.crank1.flexible=true"]
    done = run_cli(cli, "simulate", scene, *args, "--output", str(out))
    assert done.returncode == 0, done.stderr
    result = flexmbd.simulate(scene, step=0.002, duration=0.5,
                              sets={"solver.output_interval": 0.01, "bodies.crank1.flexible": True})
    assert same_bits(result.data, read_csv(out)[1])


def test_history_is_numpy_arrays_with_sensor_names():
    result = flexmbd.simulate(model("double_four_bar.ron"), duration=0.1)
    assert result.names == ["B0_x", "B0_y", "energy"]
    assert result.data.dtype == np.float64 and result.data.shape == (len(result.t), 4)
    assert result.sensors.shape == (len(result.t), 3)
    assert np.array_equal(result["B0_y"], result.sensors[:, 1])
    assert np.array_equal(result["t"], result.t)
    assert result.t[0] == 0.0 and result.t[-1] == pytest.approx(0.1)
    with pytest.raises(KeyError):
        result["no_such_sensor"]


def test_failed_run_reports_status_failed_with_its_time():
    # The four-bar's first singular passage defeats a 0.3 s step.
    result = flexmbd.simulate(model("double_four_bar.ron"), step=0.3,
                              sets={"solver.output_interval": 0.3})
    assert result.status == "failed"
    assert result.failed_at > 0.3
    assert result.t[-1] < result.failed_at  # the rows stop at the last good state
    with pytest.raises(flexmbd.RunError) as raised:
        result.raise_for_status()
    assert raised.value.time == result.failed_at


def test_scene_given_is_not_changed_by_simulate_options():
    scene = flexmbd.load(model("double_four_bar.ron"))
    flexmbd.simulate(scene, duration=0.01, sets={"solver.step": 0.002})
    assert scene.to_dict()["solver"]["step"] == 0.001
    assert scene.to_dict()["solver"]["duration"] == 5.0


def test_the_gil_is_released_during_a_run():
    # With a switch interval of 100 s, a thread holding the GIL keeps it until it blocks or
    # releases it. The worker sets "running" and enters the run without letting go in
    # between (`simulate` of a loaded scene copies it and sets its options holding the GIL), so this thread can see "running" before "done" only if the run released
    # the GIL: no count of loop turns, which depends on how a loaded machine schedules the
    # two threads. The run (the five-bar flexible four-bar, 10 s) lasts long enough (a few
    # tenths of a second) for this thread to be scheduled while it goes on.
    state = {"running": False, "done": False, "seen_inside": False}
    flexible = {f"bodies.{b}.flexible": True for b in ("crank1", "coupler1", "crank2")}

    def worker():
        # Loaded first: reading the file may let go of the GIL, the run's set-up does not.
        scene = flexmbd.load(model("double_four_bar.ron"), sets=flexible)
        state["running"] = True
        flexmbd.simulate(scene, formulation="absolute")
        state["done"] = True

    interval = sys.getswitchinterval()
    sys.setswitchinterval(100.0)
    try:
        thread = threading.Thread(target=worker)
        thread.start()
        while not state["done"]:
            if state["running"] and not state["done"]:
                state["seen_inside"] = True
            time.sleep(0)  # lets the worker take the GIL back when its run ends
        thread.join()
    finally:
        sys.setswitchinterval(interval)
    assert state["seen_inside"], state
