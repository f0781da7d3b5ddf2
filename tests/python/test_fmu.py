"""`mbfx fmu` (issue 43 §2): the FMU of tests/data/fmu_plant.adm (a 2 kg block on a
spring, K = 500 N/m, C = 40 N*s/m, pushed by the PINPUT force u; POUTPUT y and v) passes
FMPy's validation with no problem, and a PI loop closed around it through FMPy's
FMI 2.0 co-simulation calls gives what the same loop through the stepping API
(`Model.simulation`) gives, to 1e-12. A bad call comes back as fmi2Error with its reason
sent to the importer's logger. The command line writes the FMU with the slave library
`cargo build --release -p mbfx-fmi` put beside the `mbfx` binary (tests/run-all.sh)."""

from __future__ import annotations

import ctypes
from pathlib import Path

import fmpy
import fmpy.validation
import pytest
from fmpy.fmi2 import FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE

import mbfx
from conftest import ROOT, run_cli

PLANT = ROOT / "tests" / "data" / "fmu_plant.adm"
# The PI controller: u = KP*(r - y) + KI*z, z' = r - y, held over each step (sample and
# hold), driving the block from its rest height -1 m to r. With x = y + 1 the closed loop
# is M x''' + C x'' + (K + KP) x' + KI x = KI (r + 1): poles of 2 s^3 + 40 s^2 + 800 s +
# 4000 at -6.39 and -6.81 +- 16.3i, so after 1.5 s e^-9.6 ~ 7e-5 of the step is left, and
# at rest the spring alone balances u: u = K (r + 1) = 50 N.
KP, KI, R, DT, STEPS = 300.0, 4000.0, -0.9, 1e-3, 1500
ERROR = 1e-6


@pytest.fixture(scope="module")
def plant_fmu(tmp_path_factory: pytest.TempPathFactory, cli: Path) -> Path:
    path = tmp_path_factory.mktemp("fmu") / "plant.fmu"
    done = run_cli("fmu", str(PLANT), "-o", str(path), "--end", "1.5", "--output-step", "0.001")
    assert done.returncode == 0, done.stderr
    return path


def test_fmpy_finds_no_problem_in_the_fmu(plant_fmu: Path) -> None:
    assert fmpy.validation.validate_fmu(str(plant_fmu)) == []
    md = fmpy.read_model_description(str(plant_fmu), validate=True)
    assert md.fmiVersion == "2.0"
    assert md.coSimulation.modelIdentifier == "plant"
    assert md.coSimulation.canHandleVariableCommunicationStepSize
    got = [(v.name, v.causality, v.variability, v.unit) for v in md.modelVariables]
    assert got == [
        ("u", "input", "continuous", "newton"),
        ("y", "output", "continuous", "meter"),
        ("v", "output", "continuous", "meter/second"),
    ]
    assert md.modelVariables[0].start == "0.0"
    units = {u.name: u.baseUnit for u in md.unitDefinitions}
    assert (units["newton"].kg, units["newton"].m, units["newton"].s) == (1, 1, -2)
    assert md.defaultExperiment.stopTime == "1.5"


class Slave:
    """The FMU instantiated through FMPy's FMI 2.0 calls, with a logger that keeps the
    messages."""

    def __init__(self, path: Path) -> None:
        self.md = fmpy.read_model_description(str(path))
        self.folder = fmpy.extract(str(path))
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.messages: list[str] = []

        def log(_env, _name, status, category, message) -> None:  # type: ignore[no-untyped-def]
            self.messages.append(f"{status} {category.decode()} {message.decode()}")

        # (FMPy declares the variadic logger with the format as its last argument: the
        # library passes the message as the format, with no conversion in it.)
        self._logger = fmi2CallbackLoggerTYPE(log)
        self.callbacks = fmi2CallbackFunctions()
        self.callbacks.logger = self._logger
        self.fmu = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=self.folder,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName="plant",
        )
        self.fmu.instantiate(callbacks=self.callbacks)

    def get(self, *names: str) -> list[float]:
        return list(self.fmu.getReal([self.vr[n] for n in names]))

    def set(self, name: str, value: float) -> None:
        self.fmu.setReal([self.vr[name]], [value])

    def close(self) -> None:
        self.fmu.terminate()
        self.fmu.freeInstance()


def pi_loop(read, write, advance) -> list[tuple[float, float, float]]:  # type: ignore[no-untyped-def]
    """The PI loop over a plant given by three calls; (u, y, v) after each step."""
    z = 0.0
    rows = []
    for k in range(STEPS):
        y, _ = read()
        e = R - y
        z += e * DT
        u = KP * e + KI * z
        write(u)
        advance(k * DT, (k + 1) * DT)
        y, v = read()
        rows.append((u, y, v))
    return rows


def test_a_pi_loop_through_the_fmu_equals_the_same_loop_through_the_stepping_api(
    plant_fmu: Path,
) -> None:
    slave = Slave(plant_fmu)
    slave.fmu.setupExperiment(tolerance=ERROR, startTime=0.0)
    slave.fmu.enterInitializationMode()
    slave.fmu.exitInitializationMode()
    through_fmu = pi_loop(
        lambda: slave.get("y", "v"),
        lambda u: slave.set("u", u),
        lambda t, _t_next: slave.fmu.doStep(currentCommunicationPoint=t, communicationStepSize=DT),
    )
    slave.close()

    sim = mbfx.load(str(PLANT)).simulation(error=ERROR)
    assert list(sim.inputs) == ["u"] and list(sim.outputs) == ["y", "v"]

    def advance(t: float, _t_next: float) -> None:
        sim.advance(t + DT)  # the end of the step as the FMU takes it: t + h

    def write(u: float) -> None:
        sim.inputs["u"] = u

    through_api = pi_loop(lambda: (sim.outputs["y"], sim.outputs["v"]), write, advance)

    worst = max(abs(a - b) for f, s in zip(through_fmu, through_api) for a, b in zip(f, s))
    assert worst <= 1e-12, worst
    # The loop did its work: the block settled at r from -1 m, the spring alone
    # balancing u.
    u, y, v = through_fmu[-1]
    assert abs(y - R) < 1e-4 and abs(v) < 1e-2 and abs(u - 500.0 * (R + 1.0)) < 1.0, (u, y, v)


def test_a_bad_call_is_an_error_with_its_reason_logged(plant_fmu: Path) -> None:
    slave = Slave(plant_fmu)
    with pytest.raises(Exception):
        slave.fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=0.1)
    with pytest.raises(Exception):
        slave.fmu.setupExperiment(startTime=1.0)
    slave.fmu.setupExperiment(startTime=0.0)
    slave.fmu.enterInitializationMode()
    slave.fmu.exitInitializationMode()
    with pytest.raises(Exception):
        slave.set("y", 1.0)
    with pytest.raises(Exception):
        slave.fmu.getInteger([0])
    slave.close()
    text = "\n".join(slave.messages)
    for want in [
        "fmi2DoStep is not allowed now (the instance is instantiated, not initialized)",
        "an Adams dataset's time starts at 0",
        "y is an output: only inputs can be set",
        "this FMU has no Integer variables",
    ]:
        assert want in text, text
    assert all(m.startswith("3 logStatusError") for m in slave.messages), slave.messages
