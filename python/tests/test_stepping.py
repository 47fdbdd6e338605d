"""`flexmbd.Simulation`: stepping by hand, sensors, checkpoints; and `flexmbd.modes`."""

import json

import numpy as np
import pytest

import flexmbd
from conftest import model, run_cli


@pytest.mark.parametrize("formulation", ["absolute", "relative"])
def test_stepping_by_hand_reproduces_simulate_rows(formulation):
    sets = {"solver.duration": 0.2, "solver.formulation": formulation.capitalize()}
    result = flexmbd.simulate(model("double_four_bar.ron"), sets=sets)
    sim = flexmbd.Simulation(model("double_four_bar.ron"), sets=sets)
    assert sim.sensor_names == result.names
    every = round(0.01 / sim.step_size)  # the scene's output interval
    for k, row in enumerate(result.data):
        if k > 0:
            for _ in range(every):
                sim.step()
        assert sim.time == row[0]
        assert np.array_equal(sim.sensors(), row[1:])
    assert sim.sensor("B0_x") == result["B0_x"][-1]
    with pytest.raises(KeyError):
        sim.sensor("no_such_sensor")


def test_checkpoint_and_restore_replay_the_same_steps():
    sim = flexmbd.Simulation(model("flexible_pendulum.ron"))
    sim.advance_to(0.05)
    saved = sim.checkpoint()
    assert saved.time == sim.time
    first = []
    for _ in range(20):
        sim.step()
        first.append(sim.sensors())
    sim.restore(saved)
    assert sim.time == saved.time
    for expected in first:
        sim.step()
        assert np.array_equal(sim.sensors(), expected)
    other = flexmbd.Simulation(model("flexible_pendulum.ron"))
    with pytest.raises(ValueError, match="another simulation"):
        other.restore(saved)


def test_failed_step_raises_run_error_and_keeps_the_last_good_state():
    sim = flexmbd.Simulation(model("double_four_bar.ron"),
                             sets={"solver.step": 0.3, "solver.output_interval": 0.3})
    with pytest.raises(flexmbd.RunError) as raised:
        for _ in range(100):
            sim.step()
    assert raised.value.time > 0.3
    assert sim.time < raised.value.time
    assert np.isfinite(sim.sensors()).all()


def test_modes_is_the_clis_json(cli):
    path = model("cantilever_2d.ron")
    done = run_cli(cli, "modes", path, "--json")
    assert done.returncode == 0, done.stderr
    inventory = flexmbd.modes(path)
    assert inventory == json.loads(done.stdout)
    assert [m["frequency_hz"] for m in inventory["normal_modes"]] == \
        [m["frequency_hz"] for m in json.loads(done.stdout)["normal_modes"]]
    assert len(inventory["normal_modes"]) > 0


def test_modes_of_a_missing_model_raises_scene_error():
    with pytest.raises(flexmbd.SceneError) as raised:
        flexmbd.modes("no/such/model.ron")
    assert raised.value.file == "no/such/model.ron"


def test_a_simulation_used_and_dropped_on_another_thread_works():
    # A Python object may be used, and collected, on any thread (Dask workers, the cyclic
    # garbage collector): the simulation must not be tied to the thread that made it.
    import threading

    sim = flexmbd.Simulation(model("flexible_pendulum.ron"))
    alone = flexmbd.Simulation(model("flexible_pendulum.ron"))
    box, errors = [sim], []
    del sim

    def worker():
        try:
            for _ in range(10):
                box[0].step()
            box.append(box[0].sensors())
            box.pop(0)  # the last reference, dropped here
        except Exception as e:  # noqa: BLE001 - reported below
            errors.append(e)

    thread = threading.Thread(target=worker)
    thread.start()
    thread.join()
    assert errors == []
    for _ in range(10):
        alone.step()
    assert np.array_equal(box[0], alone.sensors())


def _four_bar_with_motor(torque, with_input):
    """The double four-bar as a dict, with a ``Load`` torque on crank1 at its pin (and an
    input ``motor`` on it)."""
    scene = flexmbd.load(model("double_four_bar.ron")).to_dict()
    scene["forces"] = scene.get("forces", []) + [
        {"Load": {"name": "motor", "body": "crank1", "marker": "A",
                  "force": [0.0, 0.0, 0.0], "torque": [0.0, 0.0, torque]}}]
    if with_input:
        scene["inputs"] = [{"name": "motor", "kind": {"Load": {"force": "motor"}}}]
    return scene


def test_torque_input_set_every_step_equals_the_scene_load():
    written = flexmbd.Simulation(_four_bar_with_motor(2.0, False))
    driven = flexmbd.Simulation(_four_bar_with_motor(2.0, True))
    assert driven.input_names == ["motor"]
    for _ in range(200):
        driven.set_input("motor", [0.0, 0.0, 0.0, 0.0, 0.0, 2.0])
        driven.step()
        written.step()
    assert np.array_equal(driven.sensors(), written.sensors())
    # The input is what acts: another torque moves the crank elsewhere.
    driven.set_input("motor", [0.0, 0.0, 0.0, 0.0, 0.0, -2.0])
    driven.advance_to(0.4)
    written.advance_to(0.4)
    assert abs(driven.sensor("B0_x") - written.sensor("B0_x")) > 1e-3


def test_bad_inputs_raise_scene_error_naming_the_field_and_value():
    sim = flexmbd.Simulation(_four_bar_with_motor(0.0, True))
    with pytest.raises(flexmbd.SceneError) as raised:
        sim.set_input("motr", [0.0] * 6)
    assert raised.value.field == "input" and raised.value.value == "motr"
    with pytest.raises(flexmbd.SceneError) as raised:
        sim.set_input("motor", [0.0, 0.0, 0.0, 0.0, 0.0, float("inf")])
    assert raised.value.field == "inputs[motor][5]"
    with pytest.raises(flexmbd.SceneError, match="takes 6 values"):
        sim.set_input("motor", [1.0])


@pytest.mark.parametrize("t", [float("nan"), float("inf"), -float("inf"), 1e12])
def test_advance_to_refuses_nan_infinite_and_too_far_targets(t):
    # Before, advance_to(inf) and advance_to(1e12) looped without end and NaN returned
    # silently: now each is a SceneError naming `t`, and the simulation goes on.
    sim = flexmbd.Simulation(model("double_four_bar.ron"))
    with pytest.raises(flexmbd.SceneError) as raised:
        sim.advance_to(t)
    assert raised.value.field == "t"
    assert sim.time == 0.0
    sim.advance_to(10 * sim.step_size)
    assert sim.time == pytest.approx(10 * sim.step_size)
