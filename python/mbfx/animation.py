"""`Run.animate()`'s result: the mechanism moving, as a glTF 2.0 binary or a
self-contained HTML page (the viewer and the .glb inline, nothing from the network),
shown inline in Jupyter and VS Code through an iframe."""

from __future__ import annotations

import html as _html
import os
from pathlib import Path
from typing import Any, List, Optional, Sequence, Union

import numpy as np

# The iframe's height in pixels in a notebook: the viewer's canvas and its chart pane.
HEIGHT = 560


class Animation:
    """A run's animation (`Run.animate()`): `glb()` the glTF binary, `html()` the
    self-contained page (its chart holds the run's columns), `save(path)` either by
    suffix, and inline display in Jupyter. `frames` is the number of frames, `notes`
    what the scene and recording want said once (placeholders, glyphs, a coarsened
    frame rate)."""

    def __init__(self, recording: Any, columns: Sequence[str], data: np.ndarray) -> None:
        self._recording = recording
        self._columns: List[str] = list(columns)
        self._data = np.ascontiguousarray(data, dtype=np.float64)
        self._page: Optional[str] = None

    @property
    def frames(self) -> int:
        """How many frames the animation holds."""
        return self._recording.frames

    @property
    def notes(self) -> List[str]:
        """What the user should hear once about what is drawn and recorded."""
        return list(self._recording.notes)

    @property
    def fps(self) -> Optional[float]:
        """The frame rate asked for; None: a frame at each output row of the run."""
        return self._recording.fps

    @property
    def glyphs(self) -> bool:
        """Whether every part has glyphs, not only those with nothing to draw."""
        return self._recording.glyphs

    def glb(self) -> bytes:
        """The glTF 2.0 binary (a `.glb` file's bytes)."""
        return self._recording.glb()

    def html(self) -> str:
        """The self-contained page: the viewer, the .glb and the run's chart."""
        if self._page is None:
            self._page = self._recording.html(self._columns, self._data)
        return self._page

    def save(self, path: Union[str, "os.PathLike[str]"]) -> Path:
        """Writes the page (`.html`, `.htm`) or the binary (`.glb`), by the suffix of
        `path`, and returns the path; another suffix raises ValueError."""
        p = Path(path)
        suffix = p.suffix.lower()
        if suffix in (".html", ".htm"):
            p.write_text(self.html(), encoding="utf-8")
        elif suffix == ".glb":
            p.write_bytes(self.glb())
        else:
            raise ValueError(f"save writes .html or .glb, not {p.name!r}")
        return p

    def _repr_html_(self) -> str:
        # The page in `srcdoc`, so its scripts run inside the notebook's output (a data:
        # URL would be refused by some front ends); escaped as an attribute value.
        page = _html.escape(self.html(), quote=True)
        return (
            f'<iframe srcdoc="{page}" title="mbfx animation" '
            f'style="width: 100%; height: {HEIGHT}px; border: 0"></iframe>'
        )

    def __repr__(self) -> str:
        rate = "at each output row" if self.fps is None else f"at {self.fps:g} per second"
        return f"mbfx.Animation({self.frames} frames {rate}, glyphs={self.glyphs})"
