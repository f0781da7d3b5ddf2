"""Model.simulation: stepping a model from Python. Advancing to `run`'s output times with
the inputs held gives `run`'s rows bit for bit (the IMPACT block and a pendulum, GSTIFF and
dopri853); a PI controller closing a loop on a plant through its PINPUT settles where the
closed loop's steady state, derived below, says; the inputs mapping, snapshots, reset, and
the errors (RunError naming the time, ValueError for a time behind)."""

from __future__ import annotations

import pytest

import mbfx
from conftest import ROOT, same_bits

IMPACT = ROOT / "examples" / "scenes" / "impact_block_k1e5.adm"
CART_POLE = ROOT / "examples" / "scenes" / "cart_pole.adm"

# A pendulum with a PINPUT torque TORQUE (VARIABLE/3) and a POUTPUT angle ANGLE (the file
# says more).
PENDULUM = (ROOT / "examples" / "pendulum_pinput.adm").read_text()

# The plant of the PI loop: a block of M = 1 kg on a slider along global x, a spring of
# K = 50 N/m and a damper of C = 20 N*s/m to ground, pushed by the PINPUT force u; its
# POUTPUT is the position x. No gravity.
M, K, C = 1.0, 50.0, 20.0
PLANT = f"""PI plant (tests/python/test_simulation.py)
UNITS/FORCE = NEWTON, MASS = KILOGRAM, LENGTH = METER, TIME = SECOND
PART/1, GROUND
MARKER/10, PART = 1
MARKER/11, PART = 1, QP = 0, 0, 0, REULER = 90D, 90D, 0D
PART/2, MASS = {M}, CM = 20, IP = 1, 1, 1
MARKER/20, PART = 2, QP = 0, 0, 0, REULER = 90D, 90D, 0D
JOINT/1, TRANSLATIONAL, I = 20, J = 11
SFORCE/1, TRANSLATION, ACTIONONLY, I = 20, J = 11
, FUNCTION = -{K}*DZ(20, 11, 11) - {C}*VZ(20, 11, 11, 11) + VARVAL(1)
! adams_view_name='u'
VARIABLE/1, FUNCTION = 0
! adams_view_name='x'
VARIABLE/2, FUNCTION = DZ(20, 11, 11)
PINPUT/1, VARIABLES = 1
POUTPUT/1, VARIABLES = 2
END
"""


def check_matches_run(model: mbfx.Model, probes: dict, **kwargs) -> None:
    """Advances a simulation to each of run's output times: every probe equals the run's
    column bit for bit."""
    run = model.run(probes=probes, **kwargs)
    sim = model.simulation(
        integrator=kwargs.get("integrator"),
        probes=probes,
        output_step=kwargs["output_step"],
        end=kwargs["end"],
        hmin=kwargs.get("hmin"),
    )
    assert len(run.time) > 10
    for k, t in enumerate(run.time):
        sim.advance(t)
        assert same_bits(sim.time, t)
        outputs = sim.outputs
        for name in probes:
            assert same_bits(outputs[name], run[name][k]), (name, t, outputs[name], run[name][k])


@pytest.mark.parametrize("integrator", ["gstiff", "dopri853"])
def test_stepping_the_impact_block_gives_runs_rows_bit_for_bit(integrator: str) -> None:
    check_matches_run(
        mbfx.load(IMPACT),
        {"y": "DY(201, 101)", "vy": "VY(201, 101)"},
        end=2.0,
        output_step=0.01,
        hmin=1e-10,
        integrator=integrator,
    )


@pytest.mark.parametrize("integrator", ["gstiff", "dopri853"])
def test_stepping_a_pendulum_gives_runs_rows_bit_for_bit(integrator: str) -> None:
    # The POUTPUT's expression is a probe too, so that the run reads what the simulation
    # reads (a velocity column makes every row reconcile, in both).
    probes = {"angle": "AZ(21, 10)", "x": "DX(20, 10)", "wz": "WZ(21, 10)"}
    check_matches_run(
        mbfx.load(PENDULUM), probes, end=2.0, output_step=0.02, integrator=integrator
    )


@pytest.mark.parametrize("integrator", ["gstiff", "dopri853", "hht"])
def test_a_pi_controller_settles_the_plant_where_the_closed_loop_says(integrator: str) -> None:
    # u = KP*(r - x) + KI*z with z' = r - x, held over each 1 ms step (the controller's
    # sample and hold). Closed loop: M x''' + C x'' + (K + KP) x' + KI x = KI r, whose
    # poles (s^3 + 20 s^2 + 200 s + 400: -2.58 and -8.71 +- 8.90i) are stable, so at
    # rest x' = x'' = 0 and z' = r - x = 0: x = r, and the spring alone balances u,
    # u = K*r (the integral holds z = K*r/KI). The slowest pole decays as e^(-2.58 t):
    # after 8 s, e^-20.6 ~ 1e-9 of the step is left. (A changed input restarts a BDF's
    # history and starts the one-step methods afresh: both paths.)
    KP, KI, r, dt = 150.0, 400.0, 0.1, 1e-3
    sim = mbfx.load(PLANT).simulation(integrator=integrator, error=1e-6)
    assert list(sim.inputs) == ["u"]
    assert list(sim.outputs) == ["x"]
    z = 0.0
    u = 0.0
    for k in range(1, 8001):
        e = r - sim.outputs["x"]
        z += e * dt
        u = KP * e + KI * z
        sim.inputs["u"] = u
        sim.advance(k * dt)
    assert sim.time == pytest.approx(8.0, abs=1e-12)
    assert abs(sim.outputs["x"] - r) < 1e-7, sim.outputs
    assert abs(u - K * r) < 1e-4, u
    assert abs(z - K * r / KI) < 1e-6, z
    assert sim.inputs["u"] == u


def test_a_held_torque_turns_the_pendulum_as_its_closed_form_says() -> None:
    # Without gravity, a torque T about the pin turns the arm of inertia I = m*L^2 + Izz
    # at alpha = T/I: theta = alpha*t^2/2.
    model = mbfx.load(PENDULUM.replace("ACCGRAV/JGRAV = -9.81\n", ""))
    sim = model.simulation(error=1e-8, output_step=0.01)
    sim.inputs["TORQUE"] = 0.5
    alpha = 0.5 / (1.0 + 1e-3)
    for k in range(1, 101):
        t = k * 0.01
        sim.advance(t)
        assert sim.outputs["ANGLE"] == pytest.approx(0.5 * alpha * t * t, abs=1e-6)


def test_the_inputs_mapping_reads_sets_and_refuses() -> None:
    sim = mbfx.load(PENDULUM).simulation(output_step=0.01)
    inputs = sim.inputs
    assert len(inputs) == 1 and "TORQUE" in inputs and "torque" in inputs
    assert inputs.keys() == ["TORQUE"] and inputs.items() == [("TORQUE", 0.0)]
    inputs["VARIABLE/3"] = 0.25
    assert inputs["TORQUE"] == 0.25
    with pytest.raises(KeyError, match="TORQUE"):
        inputs["thrust"] = 1.0
    with pytest.raises(ValueError, match="not an input"):
        inputs["ANGLE"] = 1.0
    with pytest.raises(ValueError, match="finite"):
        inputs["TORQUE"] = float("nan")
    with pytest.raises(TypeError, match="TORQUE"):
        inputs["TORQUE"] = "1.0"  # type: ignore[assignment]


def test_snapshots_restore_and_reset_repeat_their_bits() -> None:
    model = mbfx.load(PENDULUM)
    sim = model.simulation(output_step=0.01)
    sim.inputs["TORQUE"] = 0.3
    sim.advance(0.5)
    state = sim.state()
    assert state.time == 0.5
    ends = []
    for _ in range(2):
        sim.restore(state)
        assert sim.time == 0.5 and sim.inputs["TORQUE"] == 0.3
        sim.advance(1.0)
        ends.append(sim.outputs)
    assert ends[0] == ends[1]
    sim.reset()
    assert sim.time == 0.0 and sim.inputs["TORQUE"] == 0.0
    fresh = model.simulation(output_step=0.01)
    for t in (0.3, 0.6, 1.0):
        sim.advance(t)
        fresh.advance(t)
        assert sim.outputs == fresh.outputs


def test_errors_name_the_time_and_the_argument() -> None:
    # The light cart-pole stops at its first vertical crossing, t = 0.4515 s, at the
    # default HMIN of an output step of 0.1 s (examples/scenes/cart_pole.toml says why).
    sim = mbfx.load(CART_POLE).simulation(output_step=0.1, probes={"x": "DX(201)"})
    with pytest.raises(mbfx.RunError) as failed:
        for k in range(1, 11):
            sim.advance(k * 0.1)
    assert failed.value.time == pytest.approx(0.4515, abs=1e-3)
    assert failed.value.code == "E0802"
    # Stopped: every later advance raises the same, until a reset.
    with pytest.raises(mbfx.RunError):
        sim.advance(1.0)
    sim.reset()
    sim.advance(0.1)
    with pytest.raises(ValueError, match="t=0.05"):
        sim.advance(0.05)
    with pytest.raises(TypeError, match="t must be a number"):
        sim.advance("1")  # type: ignore[arg-type]
    with pytest.raises(mbfx.RunError, match="time"):
        mbfx.load(PENDULUM).simulation(probes={"time": "DX(20)"})
