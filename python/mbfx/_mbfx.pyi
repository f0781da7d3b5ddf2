"""Type stubs of the native module mbfx._mbfx (PyO3)."""

from os import PathLike
from typing import Any, Dict, Iterator, List, Mapping, Optional, Sequence, Tuple, Union, final, overload

import numpy as np
import numpy.typing as npt

from . import Graphic, Linearization, Run

__version__: str
__all__ = [
    "CheckError",
    "Diagnostic",
    "Expression",
    "InternalError",
    "MbfxError",
    "Model",
    "Recording",
    "Report",
    "RunError",
    "Simulation",
    "SimulationInputs",
    "SimulationState",
    "__version__",
    "_load_text",
    "_panic_for_tests",
    "_rebuild_diagnostic",
    "_rebuild_expression",
    "_rebuild_report",
    "compile",
    "load",
]

_ArrayLike = Union[float, int, npt.ArrayLike]

class MbfxError(Exception):
    """Base class of every error mbfx raises."""

class CheckError(MbfxError):
    """An expression or dataset has errors; `str()` is the rendered text with carets."""

    diagnostics: List[Diagnostic]

class RunError(MbfxError):
    """A run failed: where, why, and the rows computed before the failure."""

    time: Optional[float]
    element: Optional[str]
    cause: str
    code: str
    diagnostics: List[Diagnostic]
    run: Optional[Run]

class InternalError(MbfxError):
    """A bug in mbfx (a panic inside Rust), reported instead of crashing the interpreter."""

@final
class Diagnostic:
    """One diagnostic: a stable code, a message and where it points."""

    code: str
    severity: str
    message: str
    span: Tuple[int, int]
    line: int
    column: int
    source: str
    help: Optional[str]
    text: str
    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...]]: ...

@final
class Expression:
    """A compiled expression over named variables."""

    @property
    def text(self) -> str: ...
    @property
    def variables(self) -> Tuple[str, ...]: ...
    @property
    def engine(self) -> str: ...
    @property
    def threads(self) -> Optional[int]:
        """The threads a call over big arrays uses (None: every core)."""
    @property
    def units(self) -> Dict[str, str]:
        """The dimension of each variable given one (`units=` of `compile`)."""
    @property
    def dimension(self) -> Optional[str]:
        """The expression's dimension when variables have dimensions and it has one."""
    @property
    def outputs(self) -> int: ...
    @property
    def wrt(self) -> Tuple[str, ...]: ...
    @property
    def warnings(self) -> List[Diagnostic]: ...
    @property
    def address(self) -> int:
        """The C entry of the machine code (JIT only); see `signature`."""
    @property
    def signature(self) -> str:
        """`double (int, double *, void *)`: variables then TIME in x, outputs in out."""
    # Floats give a float (a vector expression or a gradient gives its outputs as a 1-D
    # array even then: type those calls as the second overload); arrays give an array.
    @overload
    def __call__(  # type: ignore[overload-overlap]  # a float is array-like too
        self, *args: float, time: float = ..., **kwargs: float
    ) -> float: ...
    @overload
    def __call__(
        self, *args: _ArrayLike, time: _ArrayLike = ..., **kwargs: _ArrayLike
    ) -> npt.NDArray[np.float64]: ...
    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...]]: ...
    def gradient(self, wrt: Optional[Sequence[str]] = None) -> Expression:
        """The value, then its partials with respect to `wrt` (default: every variable)."""

@final
class Report:
    """What `Model.check()` reports; `str()` is `mbfx check`'s report."""

    dimension: int
    dimension_reason: str
    dof: int
    gruebler: int
    equations: int
    redundant: List[str]
    advice: List[str]
    warnings: List[Diagnostic]
    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...]]: ...

@final
class Model:
    """A dataset read, built, assembled and analysed."""

    @property
    def title(self) -> str: ...
    @property
    def text(self) -> str: ...
    @property
    def name(self) -> str: ...
    @property
    def parts(self) -> List[int]: ...
    @property
    def markers(self) -> Dict[int, int]: ...
    @property
    def graphics(self) -> List[Graphic]:
        """The GRAPHICS statements in file order (a new list each time)."""
    def check(self) -> Report: ...
    def evaluate(self, expr: str, engine: str = "jit") -> Union[float, np.ndarray]: ...
    def run(
        self,
        end: Optional[float] = None,
        output_step: Optional[float] = None,
        integrator: Optional[str] = None,
        error: Optional[float] = None,
        probes: Optional[Mapping[str, str]] = None,
        progress: bool = False,
        *,
        hmax: Optional[float] = None,
        hinit: Optional[float] = None,
        hmin: Optional[float] = None,
        fixed_step: Optional[float] = None,
        alpha: Optional[float] = None,
        rho_inf: Optional[float] = None,
        kmax: Optional[int] = None,
        formulation: Optional[str] = None,
        error_per: str = "step",
        cartesian: bool = False,
        interpolate: bool = False,
        engine: str = "jit",
        set: Optional[Mapping[str, Union[float, int, str]]] = None,
        estimate_error: bool = False,
        animation: Optional[bool] = None,
        geometry: Optional[Mapping[int, Union[str, PathLike[str]]]] = None,
    ) -> Run:
        """Simulates the model to `end` as `mbfx run` does. `Run.animate()` runs it again
        to record its frames; `animation=True` records a frame at each output row as it
        runs (no second run), `animation=False` keeps nothing to animate. `geometry`
        ({GRAPHICS id: STL, OBJ or glTF file}) gives EXTERNAL graphics their meshes: a
        CONTACT naming one collides with it, and the animation draws it (recorded as it
        runs unless `animation=False`)."""
    def linearize(
        self,
        statics: bool = True,
        end: Optional[float] = None,
        damping: bool = True,
        *,
        engine: str = "jit",
        set: Optional[Mapping[str, Union[float, int, str]]] = None,
    ) -> "Linearization":
        """The model linearized at its static equilibrium (or after a run to `end`)."""
    def simulation(
        self,
        integrator: Optional[str] = None,
        error: Optional[float] = None,
        set: Optional[Mapping[str, Union[float, int, str]]] = None,
        probes: Optional[Mapping[str, str]] = None,
        *,
        output_step: Optional[float] = None,
        end: Optional[float] = None,
        hmax: Optional[float] = None,
        hinit: Optional[float] = None,
        hmin: Optional[float] = None,
        fixed_step: Optional[float] = None,
        kmax: Optional[int] = None,
        formulation: Optional[str] = None,
        engine: str = "jit",
    ) -> Simulation:
        """The model to step: `advance(t)`, `outputs`, `inputs["u"] = 1.5`, `state()`,
        `restore()`, `reset()`. The arguments are `run`'s; HMAX and HINIT follow
        `output_step` (END/100 with `end` alone; with neither, the first advance's
        interval)."""
    def with_values(self, values: Mapping[str, Union[float, int, str]]) -> Model:
        """A new model with `values` ({"PART/2.MASS": 1.5, ...}) set in the dataset."""
    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...]]: ...

@final
class Simulation:
    """A model stepped from Python (`Model.simulation`)."""

    @property
    def time(self) -> float: ...
    @property
    def outputs(self) -> Dict[str, float]:
        """The POUTPUT VARIABLEs, then the probes, at `time`."""
    @property
    def output_names(self) -> List[str]: ...
    @property
    def inputs(self) -> SimulationInputs:
        """The PINPUT VARIABLEs: `sim.inputs["u"] = 1.5` holds from `time`."""
    def advance(self, t: float) -> None:
        """Integrates to `t`; a failure raises `RunError` with its time."""
    def state(self) -> SimulationState: ...
    def restore(self, state: SimulationState) -> None: ...
    def reset(self) -> None: ...

@final
class SimulationInputs:
    """The inputs of a `Simulation`: the PINPUT VARIABLEs by name; any design variable
    may be read or set by its name or as `VARIABLE/id`."""

    def __getitem__(self, key: str, /) -> float: ...
    def __setitem__(self, key: str, value: float, /) -> None: ...
    def __len__(self) -> int: ...
    def __contains__(self, key: str, /) -> bool: ...
    def __iter__(self) -> Iterator[str]: ...
    def keys(self) -> List[str]: ...
    def items(self) -> List[Tuple[str, float]]: ...

@final
class SimulationState:
    """A `Simulation`'s state at one time, for `Simulation.restore` (it does not pickle)."""

    @property
    def time(self) -> float: ...

@final
class Recording:
    """The animation a run recorded (or none yet), with the request that ran it
    (`mbfx.Animation` wraps it; it does not pickle)."""

    @property
    def frames(self) -> int: ...
    @property
    def notes(self) -> List[str]: ...
    @property
    def fps(self) -> Optional[float]: ...
    @property
    def glyphs(self) -> bool: ...
    @property
    def recorded_frames(self) -> bool:
        """Whether the run recorded its frames as it ran (else `again` runs it)."""
    def glb(self) -> bytes: ...
    def html(self, columns: Sequence[str], rows: np.ndarray) -> str: ...
    def again(self, fps: Optional[float], glyphs: bool) -> Recording:
        """The same run at `fps` with `glyphs`: redrawn from these frames when the rate
        is the same, else recorded by running the request again."""

def compile(
    text: str,
    variables: Optional[Sequence[str]] = None,
    engine: str = "jit",
    units: Optional[Mapping[str, str]] = None,
    threads: Optional[int] = None,
) -> Expression:
    """Checks and compiles `text` over `variables` (values go in that order). With
    engine="jit", a point runs machine code and arrays of 32 points or more the lane
    evaluator; engine="interp" interprets point by point. Both give the same bits.
    `units` gives variables dimensions ({"x": "length", "v": "m/s"}): the text is then
    checked for units of measure, and what does not fit is a W0312 warning. `threads`:
    how many threads a call over arrays of 131 072 points or more splits them over
    (None, the default: every core, as numexpr)."""

def _rebuild_expression(
    text: str,
    variables: Sequence[str],
    engine: str,
    wrt: Sequence[str],
    units: Sequence[Tuple[str, str]],
    threads: Optional[int] = None,
) -> Expression:
    """Unpickles an expression (`Expression.__reduce__`)."""

def _rebuild_diagnostic(
    code: str,
    severity: str,
    message: str,
    span: Tuple[int, int],
    line: int,
    column: int,
    source: str,
    help: Optional[str],
    text: str,
) -> Diagnostic:
    """Unpickles a diagnostic (`Diagnostic.__reduce__`)."""

def _rebuild_report(
    dimension: int,
    dimension_reason: str,
    dof: int,
    gruebler: int,
    equations: int,
    redundant: List[str],
    advice: List[str],
    warnings: List[Diagnostic],
    text: str,
) -> Report:
    """Unpickles a report (`Report.__reduce__`)."""

def _panic_for_tests() -> None:
    """Panics inside Rust, so that the tests see it become `InternalError`."""

def _load_text(text: str, name: str, dim: Optional[int] = None) -> Model:
    """Rebuilds a pickled model (and a study's model on a worker) from its text."""

def load(source: Union[str, PathLike[str]], dim: Optional[int] = None) -> Model:
    """Loads a dataset from a path, or from its text (a str holding a newline)."""
