"""mbfx from Python: the Adams FUNCTION expression language compiled to machine code,
and a constrained-multibody core that runs `.adm` datasets.

    >>> import mbfx, numpy as np
    >>> f = mbfx.compile("k*STEP(x, 0, 0, 1, 1)", variables=("x", "k"))
    >>> f(0.5, 2.0)
    1.0
    >>> f(np.linspace(0, 1, 3), k=2.0)
    array([0., 1., 2.])

`compile` gives an `Expression` (call it with floats or numpy arrays, take its
`gradient`, hand its `address` to scipy or ctypes); `load` gives a `Model` (`check`,
`evaluate`, `run`, its `graphics`); a run gives a `Run` (its columns as arrays,
`to_pandas`, `plot`, `animate`); `Model.simulation` a `Simulation` to step with a
controller in the loop (`advance`, `outputs`, `inputs`, `state`/`restore`).
Errors are `CheckError`, `RunError` and `InternalError`, all `MbfxError`.
`mbfx.study` runs design studies of a model's variants on Dask.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Dict, Iterator, List, Optional, Sequence

import numpy as np

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

from ._mbfx import (  # noqa: F401  (re-exported)
    CheckError,
    Diagnostic,
    Expression,
    InternalError,
    MbfxError,
    Model,
    Report,
    RunError,
    Simulation,
    SimulationInputs,
    SimulationState,
    __version__,
    compile,
    load,
)
from . import study  # noqa: F401  (mbfx.study; it imports dask and pandas only when used)
from .animation import Animation

__all__ = [
    "Animation",
    "CheckError",
    "Diagnostic",
    "Expression",
    "Graphic",
    "InternalError",
    "Linearization",
    "MbfxError",
    "Model",
    "Report",
    "Run",
    "__version__",
    "RunError",
    "Simulation",
    "SimulationInputs",
    "SimulationState",
    "compile",
    "load",
    "study",
]


class Run:
    """The output of `Model.run`: one row per output time.

    `run["x"]` is a column as an ndarray (`run.time` is `run["time"]`); `columns` lists
    them: `time`, the probes in the order given, then each REQUEST's components
    (`REQ<id>.F<k>`), as `mbfx run` writes them. `stats` holds the integrator's counters
    (steps, rejected, Newton iterations, factorizations, CPU seconds, ...), `warnings`
    what the run's monitors found and the physics the model leaves out (`not modelled:
    ...`), and `summary` the text `mbfx run` prints at the end. `animate()` shows the
    mechanism moving.
    A run that failed is still a `Run`: its rows stop where the failure was.
    """

    def __init__(
        self,
        columns: Sequence[str],
        data: np.ndarray,
        stats: Dict[str, Any],
        warnings: Sequence[str] = (),
        notes: Sequence[str] = (),
        summary: str = "",
        integrator: str = "",
        dimension: str = "",
        _recording: Any = None,
    ) -> None:
        self.columns: List[str] = list(columns)
        self.data: np.ndarray = np.asarray(data, dtype=np.float64).reshape(-1, len(self.columns))
        self.stats: Dict[str, Any] = dict(stats)
        self.warnings: List[str] = list(warnings)
        self.notes: List[str] = list(notes)
        self.summary: str = summary
        self.integrator: str = integrator
        self.dimension: str = dimension
        # The animation the run recorded (mbfx._mbfx.Recording); it stays in this process.
        self._recording = _recording

    def __getstate__(self) -> Dict[str, Any]:
        # A run pickles as its arrays and figures: the recording stays behind.
        state = dict(self.__dict__)
        state["_recording"] = None
        return state

    def animate(self, fps: Optional[float] = None, glyphs: Optional[bool] = None) -> Animation:
        """The mechanism moving through this run, as an `mbfx.Animation` (shown inline
        in Jupyter; `.save("x.html")`, `.save("x.glb")`). With `fps=None` the frames are
        the run's output rows: recorded as it ran under `Model.run(animation=True)`, else
        by running the same request again (its rows come out the same); with `fps`, the
        same run runs again to record frames at that rate from the integrator's
        continuous extension. `glyphs=True` draws inertia ellipsoids, links and joint
        symbols on every part (by default only parts with nothing else to draw get
        them). A run of `Model.run(animation=False)`, or one unpickled in another
        process, has no recording."""
        rec = self._recording
        if rec is None:
            raise MbfxError(
                "this run has no animation: Model.run(animation=False) records none, and a "
                "run unpickled in another process leaves its recording behind"
            )
        glyphs = rec.glyphs if glyphs is None else bool(glyphs)
        if fps is not None:
            fps = float(fps)
            if not (fps > 0 and math.isfinite(fps)):
                raise ValueError(f"fps must be a positive number of frames per second, not {fps}")
        if not rec.recorded_frames or fps != rec.fps or glyphs != rec.glyphs:
            rec = rec.again(fps, glyphs)
        return Animation(rec, self.columns, self.data)

    @property
    def time(self) -> np.ndarray:
        """The output times."""
        return self.data[:, 0]

    def __getitem__(self, name: str) -> np.ndarray:
        """The column `name` (`time`, a probe's name, or `REQ<id>.F<k>`)."""
        try:
            k = self.columns.index(name)
        except ValueError:
            raise KeyError(f"no column {name!r}; the columns are {self.columns}") from None
        return self.data[:, k]

    def __contains__(self, name: object) -> bool:
        return name in self.columns

    def __iter__(self) -> Iterator[str]:
        return iter(self.columns)

    def __len__(self) -> int:
        """The number of output rows."""
        return self.data.shape[0]

    def __repr__(self) -> str:
        end = self.data[-1, 0] if len(self) else float("nan")
        return f"mbfx.Run({len(self)} rows to t = {end:g}, columns={self.columns})"

    def to_pandas(self) -> "pd.DataFrame":
        """The rows as a pandas DataFrame indexed by time (needs `pip install mbfx[pandas]`)."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError("Run.to_pandas needs pandas: pip install mbfx[pandas]") from e
        frame = pd.DataFrame(self.data[:, 1:], columns=self.columns[1:])
        frame.index = pd.Index(self.data[:, 0], name="time")
        return frame

    def plot(self, columns: Optional[Sequence[str]] = None, ax: "Optional[Axes]" = None) -> "Axes":
        """Draws `columns` (all but time by default) against time on `ax` (a new figure
        when None) and returns the axes (needs `pip install mbfx[plot]`)."""
        try:
            import matplotlib.pyplot as plt
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError("Run.plot needs matplotlib: pip install mbfx[plot]") from e
        names = list(columns) if columns is not None else self.columns[1:]
        if ax is None:
            _, ax = plt.subplots()
        for name in names:
            ax.plot(self.time, self[name], label=name)
        ax.set_xlabel("time")
        if names:
            ax.legend()
        return ax


@dataclass(frozen=True, eq=False)
class Graphic:
    """One GRAPHICS statement of a dataset (`Model.graphics`; docs/models.md, GRAPHICS).

    `kind` is Adams' word (`CYLINDER`, `BOX`, `FRUSTUM`, `ELLIPSOID`, `CIRCLE`, `ARC`,
    `OUTLINE`, `SPDP`, `FORCE`, `CURVE`, `EXTERNAL`); `part` is the part of its first
    marker, where it is drawn; `markers` the markers that place it (CORNER, CM, I and J,
    EMARKER, CRM, RM, an OUTLINE's list). `values` holds the kind's arguments by their
    lower-case names as the dataset writes them (`cm`, `length`, `radius`, `rm`, `sides`,
    `seg`, `rangle`; `corner`, `x`, `y`, `z`; `xscale`...; `outline`; `i`, `j`, `coils`,
    `da`...`ld`; `etype`, `eid`, `emarker`; `cid`, `crm`; `file`, `element`,
    `faceting_tolerance`): marker and element ids and counts as int, lengths in model
    units, angles in radians; an argument the dataset leaves out is None.
    """

    id: int
    kind: str
    view_name: Optional[str]
    part: Optional[int]
    markers: List[int]
    values: Dict[str, Any]

    def __repr__(self) -> str:
        given = ", ".join(f"{k}={v!r}" for k, v in self.values.items() if v is not None)
        return f"mbfx.Graphic({self.id}, {self.kind}, part={self.part}, {given})"


@dataclass(frozen=True, eq=False)
class Linearization:
    """A model linearized where a run left it (`Model.linearize()`; docs/analyses.md).

    The minimal coordinates z are the joints' own coordinates where the joints span the
    motion (`coordinates`, e.g. "JOINT/1 (REVOLUTE) rotation"), else model coordinates
    ("PART/2 rotation about z"); every coordinate of the model (`columns`) moves by
    `shapes`-weighted z.
    Modes are numbered by rising |λ|: `eigenvalues` (complex, Im ≥ 0, one per conjugate
    pair), `natural_hz` = |λ|/2π, `damped_hz` = Im λ/2π, `damping_ratio` = −Re λ/|λ|, and
    `shapes[:, k]` mode k's displacement of every column, its largest minimal coordinate
    at 1. `M`, `C`, `K`
    are the reduced mass, damping and stiffness matrices; `A` the state matrix on
    `states` (z, then ż). `moving` says the operating point was not at rest (the inertial
    partials are then left out); `text` is what `mbfx run --linear` prints.
    """

    time: float
    coordinates: List[str]
    eigenvalues: np.ndarray
    natural_hz: np.ndarray
    damped_hz: np.ndarray
    damping_ratio: np.ndarray
    shapes: np.ndarray
    columns: List[str]
    A: np.ndarray
    states: List[str]
    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    moving: bool
    text: str

    def __repr__(self) -> str:
        hz = ", ".join(f"{f:.6g}" for f in self.natural_hz)
        return f"mbfx.Linearization(t={self.time}, {len(self.coordinates)} DOF, natural Hz [{hz}])"


class _Progress:
    """A progress bar over simulated time: tqdm where installed, else a line on stderr."""

    def __init__(self, end: float) -> None:
        self.end = end
        self.shown = 0.0
        try:
            from tqdm import tqdm
        except ImportError:
            self.bar = None
        else:
            self.bar = tqdm(total=end, unit="s", unit_scale=False, desc="mbfx run", leave=True)

    def update(self, t: float) -> None:
        if self.bar is not None:
            self.bar.update(max(0.0, t - self.shown))
        else:
            import sys

            print(f"\rmbfx run: t = {t:g} of {self.end:g}", end="", file=sys.stderr)
        self.shown = max(self.shown, t)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
        else:
            import sys

            print(file=sys.stderr)
