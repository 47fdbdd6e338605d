"""The exceptions of flexmbd; the Rust extension raises them with their attributes filled."""

from __future__ import annotations

from typing import Optional


class FlexmbdError(Exception):
    """Base class of every error flexmbd raises."""


class SceneError(FlexmbdError, ValueError):
    """A scene, a ``sets`` override, a ``simulate`` option or a body model was refused, or
    an input of a running :class:`flexmbd.Simulation` (unknown name, values out of range).

    The message is the one the ``flexmbd`` program prints. The attributes are ``None``
    where the refusal does not know them:

    - ``file``: the scene or model file (``"<dict>"`` for a scene given as a dict);
    - ``line``, ``column``: 1-based position in the file;
    - ``field``: the dotted path of the refused field (``"solver.step"``);
    - ``value``: the refused value as written;
    - ``reason``: why it was refused.
    """

    file: Optional[str] = None
    line: Optional[int] = None
    column: Optional[int] = None
    field: Optional[str] = None
    value: Optional[str] = None
    reason: Optional[str] = None


class RunError(FlexmbdError):
    """A time step (or the static start, or the consistent initial conditions) failed, or
    :func:`flexmbd.equilibrium` / :func:`flexmbd.eigen` found no static equilibrium.

    ``time`` is the time of the failed step in seconds (0.0 for the static start, ``None``
    when the failure has no time). A stepping :class:`flexmbd.Simulation` stays at its last
    good state.
    """

    time: Optional[float] = None
