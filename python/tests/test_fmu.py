"""`flexmbd fmu` (issue 28): the FMI 3.0 and 2.0 co-simulation FMUs of a scene, checked with FMPy —
`fmpy validate` finds no problem; `fmpy simulate` gives the rows of `flexmbd simulate` bit
for bit, with and without an input file; a state saved, stepped on and restored replays the
same steps, in another instance too through its serialised bytes; bad calls are FMI errors with a message through the logger, not a crash."""

import csv
import math
import pathlib
import subprocess
import sys

import fmpy
from fmpy.validation import validate_fmu
import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Slave

from conftest import model, run_cli

MOTOR = """    forces: [Load(name: "motor", body: "crank1", marker: "A",
                  force: [0.0, 0.0, 0.0], torque: [0.0, 0.0, TAU])],
"""
MOTOR_INPUT = '    inputs: [(name: "motor", kind: Load(force: "motor"))],\n'


def four_bar_with_motor(tmp_path: pathlib.Path, name: str, tau: float, input: bool) -> str:
    """models/double_four_bar.ron with a torque `tau` on crank1 (an input `motor` on it when
    `input`), written to tmp_path/name."""
    text = pathlib.Path(model("double_four_bar.ron")).read_text()
    extra = MOTOR.replace("TAU", repr(tau)) + (MOTOR_INPUT if input else "")
    text = text.replace("    sensors: [", extra + "    sensors: [", 1)
    path = tmp_path / name
    path.write_text(text)
    return str(path)


def export(cli: str, scene: str, fmu: pathlib.Path, *args: str) -> str:
    done = run_cli(cli, "fmu", scene, "--output", str(fmu), *args)
    assert done.returncode == 0, done.stderr
    return str(fmu)


def read_csv(path) -> tuple[list[str], np.ndarray]:
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(v) for v in row] for row in rows[1:]])


def simulate_rows(cli: str, scene: str, tmp_path: pathlib.Path, duration: float) -> tuple[list[str], np.ndarray]:
    out = tmp_path / "cli.csv"
    done = run_cli(cli, "simulate", scene, "--duration", str(duration), "--output", str(out))
    assert done.returncode == 0, done.stderr
    return read_csv(out)


def iltis_with_road_input(tmp_path: pathlib.Path) -> str:
    """models/iltis_vehicle.ron with an input `road_offset` on its road."""
    text = pathlib.Path(model("iltis_vehicle.ron")).read_text()
    text = text.replace(
        "    sensors: [", '    inputs: [(name: "road_offset", kind: Road(road: "road"))],\n    sensors: [', 1
    )
    path = tmp_path / "iltis_road.ron"
    path.write_text(text)
    return str(path)


@pytest.mark.parametrize(
    "scene, duration, interval, count",
    [
        ("double_four_bar.ron", 1.0, 0.01, 101),
        # A flexible body imported from CalculiX: its files go into resources/data/.
        ("imported_bar_pendulum.ron", 0.05, 0.005, 11),
        # 204 coordinates, a static start, a road input left at its start values.
        ("iltis_road", 0.2, 0.005, 41),
    ],
)
@pytest.mark.parametrize("fmi", ["3", "2"])
def test_the_fmu_validates_and_gives_simulate_s_rows_bit_for_bit(cli, tmp_path, scene, duration, interval, count, fmi):
    path = iltis_with_road_input(tmp_path) if scene == "iltis_road" else model(scene)
    fmu = export(cli, path, tmp_path / "scene.fmu", "--fmi", fmi)
    assert fmpy.read_model_description(fmu).fmiVersion == fmi + ".0"
    assert validate_fmu(fmu) == []
    result = fmpy.simulate_fmu(fmu, stop_time=duration, output_interval=interval)
    names, expected = simulate_rows(cli, path, tmp_path, duration)
    assert list(result.dtype.names) == ["time", *names[1:]]
    assert len(result) == len(expected) == count
    np.testing.assert_allclose(result["time"], expected[:, 0], rtol=0, atol=1e-12)
    for k, name in enumerate(names[1:], start=1):
        assert np.array_equal(result[name], expected[:, k]), name


@pytest.mark.parametrize("fmi", ["3", "2"])
def test_an_input_file_gives_the_scene_with_the_value_written_bit_for_bit(cli, tmp_path, fmi):
    # motor.tau_z = 2 N.m from FMPy's input file (set in initialisation mode, held through
    # every step) against `flexmbd simulate` of the scene with the torque written in it.
    driven = four_bar_with_motor(tmp_path, "driven.ron", 0.0, True)
    written = four_bar_with_motor(tmp_path, "written.ron", 2.0, False)
    fmu = export(cli, driven, tmp_path / "motor.fmu", "--fmi", fmi)
    assert validate_fmu(fmu) == []
    description = fmpy.read_model_description(fmu)
    inputs = [v.name for v in description.modelVariables if v.causality == "input"]
    assert inputs == ["motor.F_x", "motor.F_y", "motor.F_z", "motor.tau_x", "motor.tau_y", "motor.tau_z"]
    signals = tmp_path / "input.csv"
    signals.write_text('"time","motor.tau_z"\n0.0,2.0\n1.0,2.0\n')
    out = tmp_path / "fmu.csv"
    done = subprocess.run(
        [sys.executable, "-m", "fmpy", "simulate", fmu, "--input-file", str(signals),
         "--stop-time", "0.5", "--output-interval", "0.01", "--output-file", str(out)],
        capture_output=True, text=True, check=False,
    )
    assert done.returncode == 0, done.stderr
    fmu_names, fmu_rows = read_csv(out)
    names, rows = simulate_rows(cli, written, tmp_path, 0.5)
    assert fmu_names[1:] == names[1:]
    assert fmu_rows.shape == rows.shape
    assert np.array_equal(fmu_rows[:, 1:], rows[:, 1:])


def instantiate(fmu_file: str, messages: list, name: str = "instance") -> FMU3Slave:
    """An instance of the FMU, its log messages appended to `messages`, in step mode."""
    unzipped = fmpy.extract(fmu_file)
    description = fmpy.read_model_description(unzipped)
    fmu = FMU3Slave(
        guid=description.guid,
        unzipDirectory=unzipped,
        modelIdentifier=description.coSimulation.modelIdentifier,
        instanceName=name,
    )

    def log(environment, status, category, message):
        messages.append((status, message.decode()))

    fmu.instantiate(logMessage=log)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    return fmu


def test_a_state_restored_through_fmpy_replays_the_same_steps(cli, tmp_path):
    fmu_file = export(cli, four_bar_with_motor(tmp_path, "driven.ron", 0.0, True), tmp_path / "m.fmu")
    messages = []
    fmu = instantiate(fmu_file, messages)
    tau_z, outputs = 6, [7, 8, 9]
    h = 0.001
    t = 0.0
    for _ in range(10):
        fmu.doStep(t, 5 * h)
        t += 5 * h
    saved = fmu.getFMUState()

    def run(t):
        rows = []
        for k in range(20):
            fmu.setFloat64([tau_z], [math.sin(k)])
            fmu.doStep(t, 2 * h)
            t += 2 * h
            rows.append(fmu.getFloat64(outputs))
        return rows

    first = run(t)
    fmu.setFMUState(saved)
    assert fmu.getFloat64([0]) == [pytest.approx(t, abs=1e-12)]
    assert run(t) == first
    # Serialised to bytes and back, in a second instance of the FMU.
    serialised = fmu.serializeFMUState(saved)
    other = instantiate(fmu_file, messages, "other")
    state = other.deserializeFMUState(serialised)
    other.setFMUState(state)
    rows = []
    u = t
    for k in range(20):
        other.setFloat64([tau_z], [math.sin(k)])
        other.doStep(u, 2 * h)
        u += 2 * h
        rows.append(other.getFloat64(outputs))
    assert rows == first
    other.freeFMUState(state)
    other.terminate()
    other.freeInstance()
    fmu.freeFMUState(saved)
    fmu.terminate()
    fmu.freeInstance()
    assert messages == []


def test_bad_calls_are_fmi_errors_with_a_logged_message(cli, tmp_path):
    fmu_file = export(cli, four_bar_with_motor(tmp_path, "driven.ron", 0.0, True), tmp_path / "m.fmu")
    messages = []
    fmu = instantiate(fmu_file, messages)
    tau_z = 6

    def refused(call, *words):
        messages.clear()
        with pytest.raises(FMICallException) as raised:
            call()
        assert raised.value.status == 3  # fmi3Error
        assert len(messages) == 1 and messages[0][0] == 3, messages
        for word in words:
            assert word in messages[0][1], messages[0][1]

    refused(lambda: fmu.setFloat64([tau_z], [float("nan")]), "motor.tau_z", "NaN")
    refused(lambda: fmu.setFloat64([tau_z], [float("inf")]), "motor.tau_z", "inf")
    refused(lambda: fmu.getFloat64([999]), "unknown value reference 999")
    refused(lambda: fmu.doStep(0.0, 0.0), "communicationStepSize = 0")
    refused(lambda: fmu.doStep(0.0, -0.01), "communicationStepSize = -0.01")
    refused(lambda: fmu.doStep(0.0, 0.0015), "whole number")
    refused(lambda: fmu.getInt32([1]), "Float64")
    refused(lambda: fmu.enterEventMode(), "not supported")
    fmu.doStep(0.0, 0.01)  # still usable
    # A step that fails (1e7 N.m on a 1 kg crank): an error naming the time, and every
    # doStep after it refused.
    fmu.setFloat64([tau_z], [1e7])
    refused(lambda: fmu.doStep(0.01, 0.01), "failed")
    refused(lambda: fmu.doStep(0.01, 0.01), "a step failed")
    fmu.terminate()
    fmu.freeInstance()


def test_a_missing_resource_or_a_wrong_token_is_logged_and_instantiation_fails(cli, tmp_path):
    fmu_file = export(cli, model("double_four_bar.ron"), tmp_path / "dfb.fmu")
    unzipped = pathlib.Path(fmpy.extract(fmu_file))
    description = fmpy.read_model_description(str(unzipped))
    messages = []

    def log(environment, status, category, message):
        messages.append((status, message.decode()))

    for guid, remove in [("{wrong}", False), (description.guid, True)]:
        if remove:
            (unzipped / "resources" / "scene.ron").unlink()
        fmu = FMU3Slave(guid=guid, unzipDirectory=str(unzipped),
                        modelIdentifier=description.coSimulation.modelIdentifier, instanceName="x")
        messages.clear()
        with pytest.raises(Exception, match="Failed to instantiate"):
            fmu.instantiate(logMessage=log)
        assert len(messages) == 1 and messages[0][0] == 3, messages
        assert ("cannot read the scene" if remove else "instantiation token {wrong}") in messages[0][1]


def test_fmi_2_restores_states_and_refuses_bad_calls_with_a_logged_message(cli, tmp_path):
    from fmpy.fmi2 import (FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE,
                           fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE)
    from fmpy import calloc, free

    scene = four_bar_with_motor(tmp_path, "driven.ron", 0.0, True)
    unzipped = fmpy.extract(export(cli, scene, tmp_path / "m2.fmu", "--fmi", "2"))
    description = fmpy.read_model_description(unzipped)
    messages = []

    def log(environment, name, status, category, message):
        messages.append((status, message.decode()))

    callbacks = fmi2CallbackFunctions()
    callbacks.logger = fmi2CallbackLoggerTYPE(log)
    callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    fmu = FMU2Slave(guid=description.guid, unzipDirectory=unzipped,
                    modelIdentifier=description.coSimulation.modelIdentifier, instanceName="m2")
    fmu.instantiate(callbacks=callbacks)
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    tau_z, outputs, h = 6, [7, 8, 9], 0.001
    fmu.doStep(0.0, 50 * h)
    saved = fmu.getFMUstate()

    def run():
        rows, t = [], 50 * h
        for k in range(10):
            fmu.setReal([tau_z], [math.cos(k)])
            fmu.doStep(t, 3 * h)
            t += 3 * h
            rows.append(fmu.getReal(outputs))
        return rows

    first = run()
    fmu.setFMUstate(saved)
    assert run() == first
    state = fmu.deSerializeFMUstate(fmu.serializeFMUstate(saved))
    fmu.setFMUstate(state)
    assert run() == first
    fmu.freeFMUstate(state)
    fmu.freeFMUstate(saved)
    assert messages == []
    for call, words in [
        (lambda: fmu.setReal([tau_z], [float("nan")]), ["motor.tau_z", "NaN"]),
        (lambda: fmu.getReal([999]), ["unknown value reference 999"]),
        (lambda: fmu.doStep(0.08, -0.01), ["communicationStepSize = -0.01"]),
        (lambda: fmu.getInteger([1]), ["Real"]),
    ]:
        messages.clear()
        with pytest.raises(FMICallException):
            call()
        assert len(messages) == 1 and messages[0][0] == 3, messages
        for word in words:
            assert word in messages[0][1], messages[0][1]
    fmu.terminate()
    fmu.freeInstance()


def test_fmu_refuses_an_unknown_fmi_version_and_a_name_without_fmu(cli, tmp_path):
    done = run_cli(cli, "fmu", model("double_four_bar.ron"), "--output", str(tmp_path / "a.fmu"), "--fmi", "1")
    assert done.returncode != 0 and "--fmi 1" in done.stderr
    done = run_cli(cli, "fmu", model("double_four_bar.ron"), "--output", str(tmp_path / "a.zip"))
    assert done.returncode != 0 and ".fmu" in done.stderr


def test_fmu_for_another_platform_puts_its_library_in_that_platform_s_folder(cli, tmp_path):
    import zipfile

    scene = model("double_four_bar.ron")
    # A library cross-built for 64-bit ARM Linux (here the host's, which only its place in the
    # archive tells apart): binaries/aarch64-linux/ in FMI 3.0, which alone names it.
    host_library = pathlib.Path(cli).with_name("libflexmbd_fmi.so")
    arm = export(cli, scene, tmp_path / "arm.fmu", "--target", "aarch64-unknown-linux-gnu", "--library", str(host_library))
    names = zipfile.ZipFile(arm).namelist()
    assert "binaries/aarch64-linux/arm.so" in names and not any("x86_64" in n for n in names), names
    done = run_cli(cli, "fmu", scene, "--output", str(tmp_path / "arm2.fmu"), "--fmi", "2",
                   "--target", "aarch64-unknown-linux-gnu", "--library", str(host_library))
    assert done.returncode != 0 and "FMI 2.0 has no platform name for aarch64-linux" in done.stderr
    # Without --library: cargo's folder for the triple, named when the library is not there.
    done = run_cli(cli, "fmu", scene, "--output", str(tmp_path / "arm3.fmu"), "--target", "aarch64-unknown-linux-gnu")
    assert done.returncode != 0 and "aarch64-unknown-linux-gnu/release/libflexmbd_fmi.so" in done.stderr
    done = run_cli(cli, "fmu", scene, "--output", str(tmp_path / "v.fmu"), "--target", "riscv64gc-unknown-linux-gnu")
    assert done.returncode != 0 and "--target riscv64gc-unknown-linux-gnu" in done.stderr


@pytest.mark.parametrize("fmi", ["3", "2"])
def test_a_parameter_set_before_the_start_gives_simulate_with_it(cli, tmp_path, fmi):
    # `--parameter solver.step`: FMPy's start value 5e-4 gives `flexmbd simulate --step 5e-4`
    # bit for bit; the density of crank1, a second parameter, left at the scene's.
    fmu = export(cli, model("double_four_bar.ron"), tmp_path / "p.fmu", "--fmi", fmi,
                 "--parameter", "solver.step", "--parameter", "bodies.crank1.model.Beam.material.density")
    assert validate_fmu(fmu) == []
    parameters = {v.name: v for v in fmpy.read_model_description(fmu).modelVariables
                  if v.causality == "parameter"}
    assert float(parameters["solver.step"].start) == 1e-3
    assert float(parameters["bodies.crank1.model.Beam.material.density"].start) == 7850.0
    result = fmpy.simulate_fmu(fmu, stop_time=0.2, output_interval=0.01, start_values={"solver.step": 5e-4})
    out = tmp_path / "cli.csv"
    done = run_cli(cli, "simulate", model("double_four_bar.ron"), "--duration", "0.2", "--step", "5e-4",
                   "--output", str(out))
    assert done.returncode == 0, done.stderr
    names, expected = read_csv(out)
    assert len(result) == len(expected) == 21
    for k, name in enumerate(names[1:], start=1):
        assert np.array_equal(result[name], expected[:, k]), name
    done = run_cli(cli, "fmu", model("double_four_bar.ron"), "--output", str(tmp_path / "q.fmu"),
                   "--parameter", "solver.max_iterations")
    assert done.returncode != 0 and "solver.max_iterations" in done.stderr
