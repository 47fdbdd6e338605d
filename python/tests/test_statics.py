"""`flexmbd.equilibrium` and `flexmbd.eigen`: the physics of a hanging pendulum, the
`flexmbd equilibrium/eigen --json` output of the program, the pendulum released horizontal
found hanging, and no equilibrium (a falling free body) as RunError."""

import json
import math

import pytest

import flexmbd
from conftest import model, run_cli

G = 9.81  # models/flexible_pendulum.ron's gravity (m/s²)
LENGTH = 1.0  # its bar (m)
HANGING = {"bodies.bar.orientation.Angle": -math.pi / 2}


def oscillatory(vibration):
    """The undamped frequencies (Hz) of the oscillatory modes, in order."""
    return [m["frequency_hz"] for m in vibration["modes"] if m["kind"] == "oscillatory"]


def test_hanging_flexible_pendulum_swings_near_the_rigid_bar_frequency_in_both_formulations():
    rigid = math.sqrt(3 * G / (2 * LENGTH)) / (2 * math.pi)
    found = {}
    for formulation in ["absolute", "relative"]:
        vibration = flexmbd.eigen(model("flexible_pendulum.ron"), formulation=formulation,
                                  sets=HANGING)
        assert vibration["equilibrium"]["formulation"].lower() == formulation
        f = oscillatory(vibration)
        assert len(f) == 5, (formulation, f)
        assert abs(f[0] - rigid) / rigid < 1e-3, (formulation, f[0], rigid)
        found[formulation] = f
    for a, b in zip(found["absolute"], found["relative"]):
        assert abs(a - b) / abs(b) < 1e-6, found


@pytest.mark.parametrize("command, function", [("equilibrium", flexmbd.equilibrium),
                                               ("eigen", flexmbd.eigen)])
def test_spin_up_beam_is_the_clis_json(cli, command, function):
    scene = model("spin_up_beam_2d.ron")
    done = run_cli(cli, command, scene, "--json")
    assert done.returncode == 0, done.stderr
    assert function(scene) == json.loads(done.stdout)


def test_options_and_sets_are_the_clis(cli):
    scene = model("flexible_pendulum.ron")
    angle = HANGING["bodies.bar.orientation.Angle"]
    done = run_cli(cli, "eigen", scene, "--formulation", "relative",
                   "--set", f"bodies.bar.orientation.Angle={angle!r}", "--json")
    assert done.returncode == 0, done.stderr
    assert flexmbd.eigen(scene, formulation="relative", sets=HANGING) == json.loads(done.stdout)


@pytest.mark.parametrize("function", [flexmbd.equilibrium, flexmbd.eigen])
def test_a_falling_free_body_has_no_static_equilibrium(function):
    # The floating platform under gravity: a free body, nothing holds it up.
    scene = model("floating_platform_3d.ron")
    with pytest.raises(flexmbd.RunError, match="no static equilibrium") as raised:
        function(scene, sets={"gravity.2": -9.81})
    assert "floating_platform_3d.ron" in str(raised.value)
    assert raised.value.time == 0.0


def test_pendulum_released_horizontal_is_found_hanging():
    equilibrium = flexmbd.equilibrium(model("flexible_pendulum.ron"))
    sensors = {s["name"]: s["value"] for s in equilibrium["sensors"]}
    assert abs(sensors["tip_x"]) < 1e-9 and abs(sensors["tip_y"] + LENGTH) < 1e-6, sensors


def test_hanging_flexible_pendulum_pin_carries_its_weight_in_both_formulations():
    mass = 7850.0 * 1.2739e-4 * LENGTH  # models/flexible_pendulum.ron: density, area, length
    for formulation in ["absolute", "relative"]:
        reactions = flexmbd.equilibrium(model("flexible_pendulum.ron"),
                                        formulation=formulation)["reactions"]
        assert not reactions["redundant"]
        [pin] = reactions["joints"]
        assert (pin["name"], pin["kind"], pin["body"]) == ("pin", "Revolute", "bar")
        fx, fy, _ = pin["force"]
        assert abs(fx) < 1e-9 and abs(fy - mass * G) < 1e-9 * mass * G, (formulation, pin)
        assert all(abs(m) < 1e-9 for m in pin["moment"]), (formulation, pin)


def test_a_refused_option_is_a_scene_error():
    with pytest.raises(flexmbd.SceneError) as raised:
        flexmbd.equilibrium(model("spin_up_beam_2d.ron"), formulation="floating")
    assert raised.value.field is not None and "formulation" in raised.value.field
