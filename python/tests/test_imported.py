"""Scenes with imported FE bodies (issue 25 item 8): they load, simulate and step from Python
like any other, with the CLI's numbers bit for bit, and `flexmbd.modes` reads an imported
body's model file."""

import json

import numpy as np
import pytest

import flexmbd
from conftest import model, run_cli
from test_simulate import read_csv, same_bits


@pytest.mark.parametrize("formulation", ["absolute", "relative"])
def test_imported_scene_is_the_clis_csv_bit_for_bit(cli, tmp_path, formulation):
    out = tmp_path / "out.csv"
    scene = model("imported_bar_pendulum.ron")
    done = run_cli(cli, "simulate", scene, "--formulation", formulation, "--duration", "0.05",
                   "--output", str(out))
    assert done.returncode == 0, done.stderr
    result = flexmbd.simulate(scene, formulation=formulation, duration=0.05)
    assert result.status == "ok"
    assert same_bits(result.data, read_csv(out)[1])


def test_imported_scene_steps_by_hand():
    sets = {"solver.duration": 0.02}
    result = flexmbd.simulate(model("imported_bar_pendulum.ron"), sets=sets)
    sim = flexmbd.Simulation(model("imported_bar_pendulum.ron"), sets=sets)
    every = round(0.005 / sim.step_size)  # the scene's output interval
    for k, row in enumerate(result.data):
        if k > 0:
            for _ in range(every):
                sim.step()
        assert np.array_equal(sim.sensors(), row[1:])
    assert sim.sensor("energy") == result["energy"][-1]


def test_modes_of_an_imported_body_model_are_the_clis(cli):
    done = run_cli(cli, "modes", model("imported_bar.ron"), "--json")
    assert done.returncode == 0, done.stderr
    assert flexmbd.modes(model("imported_bar.ron")) == json.loads(done.stdout)


def test_a_missing_export_raises_scene_error_naming_it(tmp_path):
    moved = tmp_path / "imported_bar.ron"
    moved.write_text(open(model("imported_bar.ron")).read())
    with pytest.raises(flexmbd.SceneError) as err:
        flexmbd.modes(str(moved))
    assert "bar_mesh.inp" in str(err.value)
