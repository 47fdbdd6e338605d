"""Scenes from files and dicts, overrides, and refusals as SceneError with their fields."""

import math

import pytest

import flexmbd
from conftest import model, run_cli


def test_a_dict_scene_runs_as_its_file():
    from_file = flexmbd.load(model("double_four_bar.ron"))
    from_dict = flexmbd.load(from_file.to_dict())
    assert from_dict.origin == "<dict>"
    a = flexmbd.simulate(from_file, duration=0.2)
    b = flexmbd.simulate(from_dict, duration=0.2)
    assert (a.data == b.data).all()


def test_to_ron_loads_back_to_the_same_scene(tmp_path):
    scene = flexmbd.load(model("flexible_pendulum.ron")).set("solver.step", 5e-4)
    path = tmp_path / "again.ron"
    path.write_text(scene.to_ron())
    again = flexmbd.load(path)
    assert again.to_dict() == scene.to_dict()
    assert again.to_dict()["solver"]["step"] == 5e-4


def test_nan_position_via_sets_raises_scene_error_naming_field_and_value(cli):
    scene = model("double_four_bar.ron")
    with pytest.raises(flexmbd.SceneError) as raised:
        flexmbd.load(scene, sets=["bodies.crank1.markers.B.position.0=nan"])
    error = raised.value
    assert isinstance(error, ValueError)
    assert error.field == "bodies.crank1.markers.B.position.0"
    assert error.value == "nan"
    # The same text as the program's refusal.
    done = run_cli(cli, "simulate", scene, "--set", "bodies.crank1.markers.B.position.0=nan")
    assert done.returncode == 3
    assert str(error) in done.stderr


def test_nan_in_a_dict_raises_scene_error_naming_field_and_value():
    tree = flexmbd.load(model("double_four_bar.ron")).to_dict()
    tree["bodies"][1]["markers"][0]["position"][1] = math.nan
    with pytest.raises(flexmbd.SceneError) as raised:
        flexmbd.load(tree)
    name = tree["bodies"][1]["name"]
    assert raised.value.field == f"bodies[{name}].markers[A].position[1]"
    assert raised.value.value == "nan"
    assert raised.value.file == "<dict>"


def test_typo_in_a_dict_raises_scene_error_naming_the_field():
    tree = flexmbd.load(model("double_four_bar.ron")).to_dict()
    tree["solver"]["stpe"] = tree["solver"].pop("step")
    with pytest.raises(flexmbd.SceneError) as raised:
        flexmbd.load(tree)
    assert raised.value.field == "solver.stpe"
    assert "unknown field `stpe`" in str(raised.value)
    assert "line" not in str(raised.value)  # no position in JSON text the user never saw


def test_bad_value_in_a_dict_names_field_and_value():
    tree = flexmbd.load(model("double_four_bar.ron")).to_dict()
    tree["solver"]["step"] = -1.0
    with pytest.raises(flexmbd.SceneError) as raised:
        flexmbd.load(tree)
    assert (raised.value.field, raised.value.value) == ("solver.step", "-1")
    assert raised.value.line is None


def test_bad_value_in_a_file_names_file_line_field_and_value(cli, tmp_path):
    text = open(model("double_four_bar.ron")).read()
    assert "step: 1e-3" in text or "step: 0.001" in text
    bad = text.replace("step: 1e-3", "step: -1e-3").replace("step: 0.001", "step: -0.001")
    path = tmp_path / "bad.ron"
    path.write_text(bad)
    with pytest.raises(flexmbd.SceneError) as raised:
        flexmbd.load(path)
    error = raised.value
    line = next(i for i, l in enumerate(bad.splitlines(), 1) if "step: -" in l)
    assert (error.file, error.line, error.field) == (str(path), line, "solver.step")
    assert error.value.startswith("-")
    done = run_cli(cli, "simulate", str(path))
    assert str(error) in done.stderr


def test_scene_set_refused_leaves_the_scene_unchanged():
    scene = flexmbd.load(model("double_four_bar.ron"))
    with pytest.raises(flexmbd.SceneError) as raised:
        scene.update({"solver.step": 5e-4, "solver.duration": -1.0})
    assert raised.value.field == "solver.duration"
    assert scene.to_dict()["solver"]["step"] == 0.001


def test_bad_simulate_option_raises_scene_error():
    with pytest.raises(flexmbd.SceneError) as raised:
        flexmbd.simulate(model("double_four_bar.ron"), formulation="lagrangian")
    assert (raised.value.field, raised.value.value) == ("formulation", "lagrangian")


def test_a_body_model_is_not_a_scene():
    with pytest.raises(flexmbd.SceneError, match="this is a body model, not a scene"):
        flexmbd.load(model("cantilever_2d.ron"))


def test_missing_file_raises_scene_error_naming_it():
    with pytest.raises(flexmbd.SceneError) as raised:
        flexmbd.load("no/such/scene.ron")
    assert raised.value.file == "no/such/scene.ron"
