"""Ctrl-C during a run or an advance: it stops between two steps, keeps what was computed,
and raises KeyboardInterrupt (SIGINT sent to this process by a timer, as a terminal does)."""

import os
import signal
import threading
import time

import numpy as np
import pytest

import flexmbd
from conftest import model


def same_bits(a, b):
    """Equal bit for bit."""
    return a.shape == b.shape and np.array_equal(a.view(np.int64), b.view(np.int64))


@pytest.fixture(autouse=True)
def python_handles_sigint():
    """Python's own SIGINT handler for each test: a process started in the background by a
    non-interactive shell (`nohup … &`, some CI runners) inherits SIGINT ignored, and then
    Python never raises KeyboardInterrupt; a terminal's Ctrl-C is what these tests mean."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def sigint_after(seconds):
    """Send SIGINT to this process after `seconds`, from another thread."""
    timer = threading.Timer(seconds, os.kill, args=(os.getpid(), signal.SIGINT))
    timer.start()
    return timer


def test_ctrl_c_stops_simulate_and_keeps_the_rows_so_far():
    # 10⁴ s of the rigid four-bar is 10⁷ steps, minutes of work: the signal comes long
    # before the end.
    scene = flexmbd.load(model("double_four_bar.ron"), sets={"solver.duration": 1e4})
    timer = sigint_after(0.5)
    started = time.monotonic()
    try:
        with pytest.raises(KeyboardInterrupt) as raised:
            flexmbd.simulate(scene)
    finally:
        timer.cancel()
    assert time.monotonic() - started < 30.0
    result = raised.value.result
    assert result.status == "interrupted", result.summary
    assert len(result.t) > 1 and 0.0 < result.t[-1] < 1e4
    # The rows so far are those of a run that ends there, bit for bit.
    again = flexmbd.simulate(scene, duration=float(result.t[-1]))
    assert same_bits(result.data, again.data[: len(result.t)])


def test_ctrl_c_stops_advance_to_and_the_simulation_goes_on_from_there():
    sim = flexmbd.Simulation(model("double_four_bar.ron"))
    timer = sigint_after(0.5)
    try:
        with pytest.raises(KeyboardInterrupt):
            sim.advance_to(1e4)
    finally:
        timer.cancel()
    reached = sim.time
    assert 0.0 < reached < 1e4
    sim.step()
    fresh = flexmbd.Simulation(model("double_four_bar.ron"))
    fresh.advance_to(reached)
    fresh.step()
    assert fresh.time == sim.time
    assert same_bits(fresh.sensors(), sim.sensors())


def test_ctrl_c_stops_the_pilot_run_of_a_simulation_being_made():
    # Proper orthogonal modes from a pilot run of the scene's length, 10⁵ s: minutes.
    sets = {
        "bodies.bar.model.Beam.mode_selection": "ProperOrthogonal",
        "bodies.bar.model.Beam.normal_modes": 1,
        "solver.duration": 1e5,
    }
    timer = sigint_after(0.5)
    started = time.monotonic()
    try:
        with pytest.raises(KeyboardInterrupt):
            flexmbd.Simulation(model("flexible_pendulum.ron"), sets=sets)
    finally:
        timer.cancel()
    assert time.monotonic() - started < 30.0
