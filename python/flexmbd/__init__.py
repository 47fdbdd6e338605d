"""flexmbd — real-time flexible multibody dynamics (U. Lugrís, 2008) from Python.

Load a scene (a RON file of ``models/``, or a dict of the same shape), override any of its
scalars, run it and get the sensor histories as NumPy arrays — the same numbers, bit for
bit, as ``flexmbd simulate ... --output x.csv`` — or step it by hand::

    import flexmbd
    result = flexmbd.simulate("models/double_four_bar.ron", formulation="relative")
    result.status            # "ok", "failed" or "interrupted"
    result.t, result["B0_x"] # NumPy arrays
    sim = flexmbd.Simulation("models/flexible_pendulum.ron")
    sim.advance_to(0.5); sim.sensor("tip_y")

Refused input raises :class:`SceneError` (a ``ValueError``) naming the file, line, field
and value; a failed step of a stepping simulation raises :class:`RunError`. Ctrl-C stops a
run or an advance between two steps and raises ``KeyboardInterrupt`` (``simulate``'s with
the rows so far as ``.result``). A stepping simulation takes the scene's named inputs
between steps (``set_input``).

``sweep`` runs a scene once per set of overrides, in a loop or on Dask distributed.

``result.animate("run.html")`` writes the run's animation (a web page, or ``.glb``) from
the frames ``simulate`` recorded, and shows it inline in Jupyter.

``equilibrium`` finds a scene's static equilibrium and ``eigen`` its linearised free
vibration about it (the ``--json`` output of ``flexmbd equilibrium`` and ``flexmbd eigen``).

"""

from __future__ import annotations

import json
import math
import os
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _native
from ._errors import FlexmbdError, RunError, SceneError
from .animation import Animation
from .animation import animate as _animate

__all__ = [
    "FlexmbdError",
    "RunError",
    "Animation",
    "Result",
    "Scene",
    "SceneError",
    "Simulation",
    "Checkpoint",
    "eigen",
    "equilibrium",
    "load",
    "modes",
    "simulate",
    "sweep",
]

Sets = Union[Mapping[str, Any], Iterable[str], None]
SceneLike = Union["Scene", str, "os.PathLike[str]", Mapping[str, Any]]


def _set_text(path: str, value: Any) -> str:
    """``PATH=VALUE`` with ``value`` written as the scene format reads it."""
    if isinstance(value, bool):
        text = "true" if value else "false"
    elif isinstance(value, float):
        text = repr(value)  # the shortest text that reads back to the same double
    else:
        text = str(value)
    return f"{path}={text}"


def _set_list(sets: Sets) -> List[str]:
    """The overrides as ``PATH=VALUE`` strings, from a dict or a list of strings."""
    if sets is None:
        return []
    if isinstance(sets, Mapping):
        return [_set_text(p, v) for p, v in sets.items()]
    if isinstance(sets, str):
        return [sets]
    return [str(s) for s in sets]


def _non_finite(tree: Any, path: str = "") -> Optional[tuple]:
    """The first non-finite float in a dict scene: (dotted path, value), else None.

    JSON has no NaN or infinity, so they are refused here, naming the field, before the
    dict is handed to Rust. Items of a list are named by their ``name`` where they have one.
    """
    if isinstance(tree, float) and not math.isfinite(tree):
        return path, tree
    if isinstance(tree, Mapping):
        for key, value in tree.items():
            found = _non_finite(value, f"{path}.{key}" if path else str(key))
            if found:
                return found
    elif isinstance(tree, (list, tuple)):
        for i, item in enumerate(tree):
            name = item.get("name") if isinstance(item, Mapping) else None
            found = _non_finite(item, f"{path}[{name if name is not None else i}]")
            if found:
                return found
    return None


def _from_dict(tree: Mapping[str, Any]) -> "_native.Scene":
    """A scene from a dict in the RON scene's shape (enums as ``{"Variant": {...}}``)."""
    found = _non_finite(tree)
    if found:
        field, value = found
        error = SceneError(f"<dict>: {field} = {value!r}: not a finite number")
        error.file, error.field, error.value = "<dict>", field, repr(value)
        error.reason = "not a finite number"
        raise error
    return _native.from_json(json.dumps(tree))


class Scene:
    """A validated scene: bodies, joints, forces, drivers, sensors and solver settings.

    Made by :func:`load`. ``set`` changes it in place (validated again, unchanged when
    refused); ``to_ron`` and ``to_dict`` give it back as text or as a dict.
    """

    __slots__ = ("_scene",)

    def __init__(self, native: "_native.Scene") -> None:
        self._scene = native

    @property
    def name(self) -> str:
        """The scene's name."""
        return self._scene.name

    @property
    def origin(self) -> str:
        """The file it was read from (``"<dict>"`` for a dict)."""
        return self._scene.origin

    def set(self, path: str, value: Any) -> "Scene":
        """Override one scalar, as ``--set PATH=VALUE`` does (e.g.
        ``scene.set("bodies.crank1.flexible", True)``); returns the scene."""
        self._scene.set_all([_set_text(path, value)])
        return self

    def update(self, sets: Sets) -> "Scene":
        """Apply several overrides (a dict ``{path: value}`` or ``"PATH=VALUE"`` strings),
        all or none; returns the scene."""
        self._scene.set_all(_set_list(sets))
        return self

    def copy(self) -> "Scene":
        """An independent copy."""
        return Scene(self._scene.copy())

    def to_ron(self) -> str:
        """The scene as RON text; ``load`` of it gives the same scene."""
        return self._scene.to_ron()

    def to_dict(self) -> Dict[str, Any]:
        """The scene as a dict, in the shape :func:`load` reads."""
        return json.loads(self._scene.to_json())

    def __repr__(self) -> str:
        return f"<flexmbd.Scene {self.name!r} from {self.origin!r}>"


def load(source: SceneLike, sets: Sets = None) -> Scene:
    """Load and validate a scene.

    ``source`` is a path to a RON scene file, a dict in the scene's shape (as
    ``Scene.to_dict`` gives it; errors then name ``<dict>``), or a :class:`Scene` (copied).
    ``sets`` overrides scalars: a dict ``{"solver.step": 5e-4}`` or a list of
    ``"PATH=VALUE"`` strings, applied as ``flexmbd simulate --set`` applies them.

    Raises :class:`SceneError` for a refused scene or override.
    """
    if isinstance(source, Scene):
        scene = source.copy()
    elif isinstance(source, Mapping):
        scene = Scene(_from_dict(source))
    else:
        scene = Scene(_native.load_file(os.fspath(source)))
    if sets is not None:
        scene.update(sets)
    return scene


class Result:
    """The outcome of :func:`simulate`.

    - ``status``: ``"ok"``, or ``"failed"`` (a step, the static start or the initial
      conditions failed; ``failed_at`` and ``message`` say when and why, and the rows stop
      there; or the pilot run of proper orthogonal modes failed: no row, no ``failed_at``,
      the pilot's time in ``message``), or ``"interrupted"`` (Ctrl-C: the ``result`` of the
      ``KeyboardInterrupt`` that :func:`simulate` raised, with the rows so far);
    - ``summary``: the run summary, the fields of ``flexmbd simulate --json``;
    - ``data``: every row, a 2-D float64 array with the columns ``columns`` (``t``, then
      the sensors); ``t`` its first column, ``sensors`` the others, ``names`` their names;
    - ``result["name"]``: one column (``"t"`` or a sensor);
    - ``result.animate(...)``: the run's animation (see :meth:`animate`).
    """

    def __init__(
        self,
        summary: Dict[str, Any],
        columns: List[str],
        data: np.ndarray,
        animation: Optional["_native.Animation"] = None,
    ) -> None:
        self.summary = summary
        self.columns = list(columns)
        self.data = data
        self._animation = animation

    def __getstate__(self) -> Dict[str, Any]:
        # The recorded frames are a Rust object: a result sent to another process (a Dask
        # sweep's) goes without them, and says so when animated.
        state = dict(self.__dict__)
        state["_animation"] = None
        return state

    def animate(
        self, output: Optional[Union[str, "os.PathLike[str]"]] = None, scale: float = 1.0
    ) -> Animation:
        """The run's animation, from the frames :func:`simulate` recorded as it ran (every
        body's frame and modal coordinates, ``animation_fps`` frames per simulated second):
        the motion of this very run, up to its failure or interruption, which is marked.

        ``output``: a ``.html`` path (a self-contained page with a player: it opens offline
        and needs no server) or a ``.glb`` path (glTF 2.0 binary, for Blender or any glTF
        viewer), written whole (or not at all); ``None`` writes nothing. ``scale``
        multiplies the flexible bodies' deformation (any finite number; 1: true size).
        Returns an :class:`Animation`, which Jupyter shows inline.

        Raises ``ValueError`` for an extension that is neither or a scale that is not
        finite, the ``OSError`` of a path that cannot be written (naming it), and
        :class:`FlexmbdError` for a result without frames (simulated with
        ``animation_fps=None``, failed before its first row, or unpickled in another
        process).
        """
        if self._animation is None:
            raise FlexmbdError(
                "this result has no animation frames: simulate it here with animation_fps "
                "set (the default, 60), not None; a result sent from another process "
                "(a Dask sweep's) or failed before its first row has none"
            )
        return _animate(self._animation, output, scale)

    @property
    def status(self) -> str:
        """``"ok"``, ``"failed"`` or ``"interrupted"``."""
        return self.summary["status"]

    @property
    def failed_at(self) -> Optional[float]:
        """Time of the failed step (s), ``None`` for a run that did not fail."""
        return self.summary.get("failed_at")

    @property
    def message(self) -> Optional[str]:
        """Why the run failed."""
        return self.summary.get("message")

    @property
    def t(self) -> np.ndarray:
        """The output times (s)."""
        return self.data[:, 0]

    @property
    def names(self) -> List[str]:
        """The sensor names, the columns of ``sensors``."""
        return self.columns[1:]

    @property
    def sensors(self) -> np.ndarray:
        """The sensor histories, one column per sensor, one row per output time."""
        return self.data[:, 1:]

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.data[:, self.columns.index(name)]
        except ValueError:
            raise KeyError(name) from None

    def raise_for_status(self) -> "Result":
        """Raise :class:`RunError` (with ``time``) if the run failed; else return self."""
        if self.status == "failed":
            error = RunError(self.message or "the run failed")
            error.time = self.failed_at
            raise error
        return self

    def __repr__(self) -> str:
        return f"<flexmbd.Result {self.status} {self.data.shape[0]} rows × {self.columns}>"


def simulate(
    source: SceneLike,
    formulation: Optional[str] = None,
    inertia: Optional[str] = None,
    stiffening: Optional[str] = None,
    step: Optional[float] = None,
    duration: Optional[float] = None,
    sets: Sets = None,
    animation_fps: Optional[float] = 60.0,
) -> Result:
    """Run a scene to its duration, as ``flexmbd simulate`` does, and return its
    :class:`Result` (the same numbers as the program's ``--output`` CSV, bit for bit).

    ``source`` is what :func:`load` takes. The options override the scene's solver settings
    like the program's: ``formulation`` ``"absolute"`` or ``"relative"``; ``inertia``
    ``"b-matrix"`` or ``"shape-integrals"``; ``stiffening`` ``"linear"``, ``"fnl1"``,
    ``"fnl2"``, ``"foreshortening"`` or ``"substructuring:N"``; ``step`` and ``duration``
    in seconds; ``sets`` as in :func:`load`, applied first. The scene given is not changed.
    ``animation_fps``: the result keeps the run's animation frames (bodies' frames and modal
    coordinates, read at the first output row at or past each 1 / ``animation_fps`` s;
    reading them leaves the rows unchanged) for :meth:`Result.animate`; ``None`` keeps none.

    The GIL is released during the run. Raises :class:`SceneError` for refused input; a
    step that fails is reported by ``status == "failed"`` (see ``Result.raise_for_status``).

    Ctrl-C stops the run between two steps and raises ``KeyboardInterrupt`` (or whatever
    exception a signal handler raised) with the rows so far as its ``result`` attribute, a
    :class:`Result` with ``status == "interrupted"``.
    """
    scene = load(source, sets)
    scene._scene.set_options(formulation, inertia, stiffening, step, duration)
    summary, columns, raw, rows, raised, animation = _native.simulate(
        scene._scene, animation_fps
    )
    data = np.frombuffer(raw, dtype=np.float64).reshape(rows, len(columns)).copy()
    result = Result(json.loads(summary), columns, data, animation)
    if raised is not None:
        raised.result = result
        raise raised
    return result


class Checkpoint:
    """A saved state of a :class:`Simulation`, to :meth:`Simulation.restore`."""

    __slots__ = ("_checkpoint",)

    def __init__(self, native: "_native.Checkpoint") -> None:
        self._checkpoint = native

    @property
    def time(self) -> float:
        """The time of the saved state (s)."""
        return self._checkpoint.time


class Simulation:
    """A scene under way, stepped by the host: at t = 0 in consistent initial conditions
    (after the static equilibrium when the scene asks for one) when made.

    ``step()`` advances one time step, ``advance_to(t)`` to a time; ``sensors()`` and
    ``sensor(name)`` read the sensors in between. A failed pilot run of proper orthogonal
    modes raises :class:`RunError` (``time`` None) when it is made. A failed step raises
    :class:`RunError` and leaves the simulation at its last good state; ``checkpoint()`` / ``restore()``
    return to a saved one. ``set_input(name, values)`` sets one of the scene's inputs for
    the steps that follow. The simulation runs on a thread of its own; a call waits for it
    with the GIL released, so other Python threads run meanwhile. Ctrl-C stops a pilot run
    while the simulation is made, or an ``advance_to`` between two steps, and raises
    ``KeyboardInterrupt``.
    """

    __slots__ = ("_sim",)

    def __init__(self, source: SceneLike, sets: Sets = None) -> None:
        self._sim = _native.Simulation(load(source, sets)._scene)

    def step(self) -> None:
        """Advance one time step."""
        self._sim.step()

    def advance_to(self, t: float) -> None:
        """Step until the time reaches ``t`` (s). Ctrl-C stops it between two steps and
        raises ``KeyboardInterrupt``; the simulation stays usable at the time reached."""
        self._sim.advance_to(t)

    @property
    def time(self) -> float:
        """The current time (s)."""
        return self._sim.time

    @property
    def step_size(self) -> float:
        """The time step h (s)."""
        return self._sim.step_size

    @property
    def sensor_names(self) -> List[str]:
        """The sensor names, in the order of ``sensors()``."""
        return self._sim.sensor_names

    @property
    def input_names(self) -> List[str]:
        """The names of the scene's inputs."""
        return self._sim.input_names

    def set_input(self, name: str, values: Sequence[float]) -> None:
        """Set the input ``name`` to ``values`` for the steps that follow; a refused name
        or value raises :class:`SceneError` (``field``, ``value``, ``reason``) and changes
        nothing."""
        self._sim.set_input(name, [float(v) for v in values])

    def sensors(self) -> np.ndarray:
        """The sensors now, a float64 array in ``sensor_names`` order."""
        return np.array(self._sim.sensors(), dtype=np.float64)

    def sensor(self, name: str) -> float:
        """One sensor now; ``KeyError`` for a name the scene does not have."""
        return self._sim.sensor(name)

    def checkpoint(self) -> Checkpoint:
        """Save the current state."""
        return Checkpoint(self._sim.checkpoint())

    def restore(self, checkpoint: Checkpoint) -> None:
        """Return to a state saved by this simulation's ``checkpoint()``; the steps from
        there are the steps taken from there before. Another simulation's is refused
        (``ValueError``)."""
        self._sim.restore(checkpoint._checkpoint)

    @property
    def counters(self) -> Dict[str, int]:
        """Steps, Newton iterations and factorisations so far."""
        steps, iterations, factorizations = self._sim.counters()
        return {"steps": steps, "newton_iterations": iterations, "factorizations": factorizations}


def _static_scene(
    source: SceneLike,
    formulation: Optional[str],
    inertia: Optional[str],
    stiffening: Optional[str],
    sets: Sets,
) -> Scene:
    """The scene of :func:`equilibrium` and :func:`eigen`: loaded, overridden, validated."""
    scene = load(source, sets)
    scene._scene.set_options(formulation, inertia, stiffening, None, None)
    return scene


def equilibrium(
    source: SceneLike,
    formulation: Optional[str] = None,
    inertia: Optional[str] = None,
    stiffening: Optional[str] = None,
    sets: Sets = None,
) -> Dict[str, Any]:
    """The static equilibrium of a scene at t = 0, as ``flexmbd equilibrium`` finds it, as
    a dict: the program's ``--json`` output (the coordinates, the constraint multipliers,
    the sensors and every force element's force at the equilibrium — a spring–damper's or
    link's tension and length, a tyre's normal force and deflection — every joint's and scene
    constraint's reaction under ``reactions`` — the force and moment it exerts on its
    ``body2`` at its marker, ground components, with ``redundant`` when the constraints do
    not determine them — and the solver's counters).

    ``source``, ``formulation``, ``inertia``, ``stiffening`` and ``sets`` are as in
    :func:`simulate`; the scene given is not changed. Solved with the GIL released.
    Raises :class:`SceneError` for refused input and :class:`RunError` (``time`` 0.0) when
    no static equilibrium is found.
    """
    scene = _static_scene(source, formulation, inertia, stiffening, sets)
    return json.loads(_native.equilibrium(scene._scene))


def eigen(
    source: SceneLike,
    formulation: Optional[str] = None,
    inertia: Optional[str] = None,
    stiffening: Optional[str] = None,
    sets: Sets = None,
) -> Dict[str, Any]:
    """The linearised free vibration of a scene about its static equilibrium, as
    ``flexmbd eigen`` computes it, as a dict: the program's ``--json`` output (the
    equilibrium, the number of degrees of freedom, and per mode its frequency in Hz, damped
    frequency, damping ratio, kind — ``"oscillatory"``, ``"rigid"``, … — and the sensors
    it moves).

    Arguments as in :func:`equilibrium`. Solved with the GIL released. Raises
    :class:`SceneError` for refused input and :class:`RunError` when no static
    equilibrium is found or the modes cannot be computed.
    """
    scene = _static_scene(source, formulation, inertia, stiffening, sets)
    return json.loads(_native.eigen(scene._scene))


def modes(model: Union[str, "os.PathLike[str]"]) -> Dict[str, Any]:
    """The mode inventory of a flexible body model (e.g. ``models/cantilever_2d.ron``) as a
    dict: the ``--json`` output of ``flexmbd modes``. Reduced with the GIL released.
    Raises :class:`SceneError` for a refused model."""
    return json.loads(_native.modes(os.fspath(model)))


from .sweep import sweep  # noqa: E402  (it imports the names above)
