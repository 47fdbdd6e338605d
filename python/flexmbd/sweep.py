"""Parameter sweeps: independent runs of one scene, each with its own overrides, run in a
loop here or handed to Dask distributed (a ``LocalCluster`` or a scheduler's address) and
gathered in order.

Each run is :func:`flexmbd.simulate` of the scene with one case's overrides; the results are
the same numbers wherever they ran (a worker loads the scene from its dict, the data the
file holds). Dask is needed only when a client or a scheduler address is given
(``pip install "dask[distributed]"``).
"""

from __future__ import annotations

from typing import Any, Dict, List, Mapping, Optional, Sequence

from . import Result, SceneLike, load, simulate


def _run_case(scene: Dict[str, Any], sets: Mapping[str, Any], options: Dict[str, Any]) -> Result:
    """One run of a sweep (on a worker): the scene (a dict) with ``sets`` and ``options``."""
    return simulate(scene, sets=dict(sets), **options)


def sweep(
    source: SceneLike,
    cases: Sequence[Mapping[str, Any]],
    *,
    client: Any = None,
    scheduler: Optional[str] = None,
    **options: Any,
) -> List[Result]:
    """Run ``source`` once per case and return the :class:`flexmbd.Result` of each, in the
    order of ``cases``.

    ``cases`` are override mappings, as ``sets`` of :func:`flexmbd.simulate` (e.g.
    ``[{"bodies.crank1.model.Beam.material.young_modulus": e} for e in moduli]``);
    ``options`` are the other keyword arguments of :func:`flexmbd.simulate`, the same for
    every run. With neither ``client`` (a ``distributed.Client``) nor ``scheduler`` (a
    scheduler's address, e.g. ``"tcp://10.0.0.1:8786"``) the runs go one after another
    here; otherwise each is a Dask task and the workers need ``flexmbd`` installed.

    The scene and every case are checked here first, so that a refused override raises
    :class:`flexmbd.SceneError` before anything is sent; a run whose step fails has
    ``status == "failed"`` in its result, as with :func:`flexmbd.simulate`.
    """
    scene = load(source)
    for case in cases:
        scene.copy().update(case)
    tree = scene.to_dict()
    if client is None and scheduler is None:
        return [_run_case(tree, case, options) for case in cases]
    if client is None:
        from distributed import Client

        with Client(scheduler) as own:
            return _gather(own, tree, cases, options)
    return _gather(client, tree, cases, options)


def _gather(client: Any, tree: Dict[str, Any], cases: Sequence[Mapping[str, Any]],
            options: Dict[str, Any]) -> List[Result]:
    """Submit one task per case (the scene scattered once) and gather the results in order."""
    scene = client.scatter(tree, broadcast=True)
    futures = [client.submit(_run_case, scene, dict(case), options, pure=False) for case in cases]
    return client.gather(futures)
