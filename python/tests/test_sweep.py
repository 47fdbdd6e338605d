"""`flexmbd.sweep`: a 16-run sweep on a Dask LocalCluster gives exactly the serial loop's
results."""

import numpy as np
import pytest

import flexmbd
from conftest import model

distributed = pytest.importorskip("distributed")

# 16 runs of the double four-bar with its first crank flexible: four Young's moduli × four
# time steps.
CASES = [
    {"bodies.crank1.flexible": True, "bodies.crank1.model.Beam.material.young_modulus": e,
     "solver.step": h}
    for e in (2.1e11, 1.0e11, 7.0e10, 2.0e10)
    for h in (1e-3, 5e-4, 2e-3, 2.5e-4)
]


def test_sixteen_runs_on_a_local_cluster_are_the_serial_loops():
    scene = model("double_four_bar.ron")
    serial = [flexmbd.simulate(scene, duration=0.2, sets=case) for case in CASES]
    assert len({r.data.tobytes() for r in serial}) == len(CASES)  # the cases differ
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            swept = flexmbd.sweep(scene, CASES, client=client, duration=0.2)
    assert len(swept) == len(CASES)
    for a, b in zip(serial, swept):
        assert b.status == "ok"
        assert a.columns == b.columns
        assert np.array_equal(a.data.view(np.int64), b.data.view(np.int64))


def test_sweep_without_a_cluster_is_the_loop():
    scene = model("double_four_bar.ron")
    swept = flexmbd.sweep(scene, CASES[:2], duration=0.05)
    for case, result in zip(CASES[:2], swept):
        alone = flexmbd.simulate(scene, duration=0.05, sets=case)
        assert np.array_equal(alone.data, result.data)


def test_a_refused_case_raises_before_anything_runs():
    with pytest.raises(flexmbd.SceneError) as raised:
        flexmbd.sweep(model("double_four_bar.ron"), [{"solver.step": 1e-3}, {"solver.step": -1}],
                      scheduler="tcp://127.0.0.1:1")
    assert raised.value.field == "solver.step"
