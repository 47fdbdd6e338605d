"""The animation of a finished run: :meth:`flexmbd.Result.animate`.

:func:`flexmbd.simulate` records the animation's frames while the run goes on — every
body's floating frame and modal coordinates at the first output row at or past each
1 / ``animation_fps`` s (default 60 frames per simulated second, as ``flexmbd animate``),
read from the state without changing it, so the rows are the same bits with or without —
so a result is animated from the states its own run went through: no second run, and a
failed or interrupted run is animated exactly up to where it stopped (marked in the file).

The files are those of ``flexmbd animate``: a glTF 2.0 binary (``.glb``) or a
self-contained web page (``.html``, the glTF and three.js embedded, opens offline). In
Jupyter the returned :class:`Animation` shows the page inline (``_repr_html_``: an iframe
whose ``srcdoc`` is the page), without importing IPython.
"""

from __future__ import annotations

import html
import math
import os
import tempfile
from typing import Optional, Union

PathLike = Union[str, "os.PathLike[str]"]


def _format_of(path: PathLike) -> str:
    """``"glb"`` or ``"html"`` from the file's extension; ``ValueError`` naming it else."""
    suffix = os.path.splitext(os.fspath(path))[1].lower()
    if suffix == ".glb":
        return "glb"
    if suffix in (".html", ".htm"):
        return "html"
    raise ValueError(
        f"{os.fspath(path)}: an animation is written as .glb (glTF binary) or .html (web page)"
    )


def _write_whole(path: PathLike, data: bytes) -> None:
    """Write ``data`` to a temporary file beside ``path``, then rename it: the file is whole
    or absent. An ``OSError`` of the same kind names ``path`` and why it cannot be
    written."""
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    temporary = None
    try:
        handle, temporary = tempfile.mkstemp(prefix=".flexmbd-", suffix=".part", dir=folder)
        with os.fdopen(handle, "wb") as f:
            f.write(data)
        os.replace(temporary, path)
    except OSError as e:
        if temporary is not None and os.path.exists(temporary):
            os.remove(temporary)
        raise type(e)(e.errno, f"the animation cannot be written: {e.strerror}", path) from None


class Animation:
    """A run's animation: ``html`` (the page's text), ``glb`` (the glTF binary's bytes),
    ``path`` (the file written, or ``None``), ``times`` (the frames' times, s), ``scale``.
    Shown inline in Jupyter (the page in an iframe)."""

    def __init__(self, native, scale: float, path: Optional[str]) -> None:
        self._native = native
        self.scale = scale
        self.path = path
        self._html: Optional[str] = None

    @property
    def html(self) -> str:
        """The self-contained page (three.js and the glTF embedded)."""
        if self._html is None:
            self._html = bytes(self._native.render("html", self.scale)).decode("utf-8")
        return self._html

    @property
    def glb(self) -> bytes:
        """The glTF 2.0 binary."""
        return bytes(self._native.render("glb", self.scale))

    @property
    def times(self):
        """The frames' times (s)."""
        return list(self._native.times)

    def _repr_html_(self) -> str:
        return (
            '<iframe style="width:100%;height:520px;border:0" '
            f'srcdoc="{html.escape(self.html, quote=True)}"></iframe>'
        )

    def __repr__(self) -> str:
        where = f" written to {self.path!r}" if self.path else ""
        return f"<flexmbd.Animation {len(self._native.times)} frames{where}>"


def animate(native, output: Optional[PathLike], scale: float) -> Animation:
    """:meth:`flexmbd.Result.animate` once the result's frames are there."""
    scale = float(scale)
    if not math.isfinite(scale):
        raise ValueError(f"deformation scale {scale}: must be a finite number")
    if output is not None:
        fmt = _format_of(output)
        data = bytes(native.render(fmt, scale))
        _write_whole(output, data)
        animation = Animation(native, scale, os.fspath(output))
        if fmt == "html":
            animation._html = data.decode("utf-8")
        return animation
    return Animation(native, scale, None)
