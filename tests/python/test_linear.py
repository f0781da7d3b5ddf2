"""`Model.linearize()` (issue 26 §3): the modes of a model at its static equilibrium as
numpy arrays. Expected values come from the mechanics: a double pendulum's frequency
equation in its joint angles, a spring-mass-damper's λ = −c/2m ± i√(k/m − (c/2m)²)."""

from __future__ import annotations

import numpy as np
import pytest

import mbfx

G = 9.81

DOUBLE = """double pendulum
PART/1, GROUND
MARKER/10, PART = 1
PART/2, MASS = 1, CM = 20, IP = 0.1, 0.1, 0.1
MARKER/20, PART = 2, QP = 0, -0.5, 0
MARKER/21, PART = 2
MARKER/22, PART = 2, QP = 0, -1, 0
PART/3, MASS = 1.5, CM = 30, IP = 0.05, 0.05, 0.05
MARKER/30, PART = 3, QP = 0, -1.4, 0
MARKER/31, PART = 3, QP = 0, -1, 0
JOINT/1, REVOLUTE, I = 21, J = 10
JOINT/2, REVOLUTE, I = 31, J = 22
ACCGRAV/JGRAV = -9.81
END
"""

SPRING = """spring-mass-damper
PART/1, GROUND
MARKER/10, PART = 1
MARKER/11, PART = 1, REULER = 0, -90D, 0
PART/2, MASS = 2, CM = 20, IP = 0.1, 0.1, 0.1
MARKER/20, PART = 2, QP = 0, -1, 0
MARKER/21, PART = 2, QP = 0, -1, 0, REULER = 0, -90D, 0
JOINT/1, TRANSLATIONAL, I = 21, J = 11
SPRINGDAMPER/1, TRANSLATION, I = 20, J = 10, K = 500, C = 3, LENGTH = 1
ACCGRAV/JGRAV = -9.81
EQUILIBRIUM/ERROR = 1e-12, IMBALANCE = 1e-10
END
"""


def model(text: str, dim=None) -> mbfx.Model:
    return mbfx.load(text, dim=dim)


@pytest.mark.parametrize("dim", [None, 3])
def test_a_double_pendulum_has_the_roots_of_its_frequency_equation(dim):
    m1, i1, d1, l1, m2, i2, d2 = 1.0, 0.1, 0.5, 1.0, 1.5, 0.05, 0.4
    mass = np.array([[i1 + m1 * d1**2 + m2 * l1**2, m2 * l1 * d2], [m2 * l1 * d2, i2 + m2 * d2**2]])
    stiffness = np.diag([G * (m1 * d1 + m2 * l1), G * m2 * d2])
    want = np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(mass, stiffness)).real))
    lin = model(DOUBLE, dim).linearize()
    assert len(lin.coordinates) == 2 and not lin.moving
    np.testing.assert_allclose(np.abs(lin.eigenvalues), want, rtol=1e-12)
    np.testing.assert_allclose(lin.natural_hz, want / (2 * np.pi), rtol=1e-12)
    # The state matrix has the same spectrum, and the shapes one column per mode.
    spectrum = np.sort(np.abs(np.linalg.eigvals(lin.A)))
    np.testing.assert_allclose(spectrum, np.repeat(want, 2), rtol=1e-10)
    assert lin.shapes.shape == (len(lin.columns), 2)
    assert lin.A.shape == (4, 4) and len(lin.states) == 4


def test_a_spring_mass_damper_has_its_damping_and_loses_it_without():
    m, k, c = 2.0, 500.0, 3.0
    lin = model(SPRING).linearize()
    [lam] = lin.eigenvalues
    assert lam.real == pytest.approx(-c / (2 * m), rel=1e-12)
    assert lam.imag == pytest.approx(np.sqrt(k / m - (c / (2 * m)) ** 2), rel=1e-12)
    assert lin.damping_ratio[0] == pytest.approx(c / (2 * np.sqrt(k * m)), rel=1e-12)
    np.testing.assert_allclose(lin.A, [[0, 1], [-k / m, -c / m]], rtol=1e-12, atol=1e-12)
    undamped = model(SPRING).linearize(damping=False)
    assert undamped.eigenvalues[0].imag == pytest.approx(np.sqrt(k / m), rel=1e-12)
    assert abs(undamped.eigenvalues[0].real) < 1e-9


def test_a_mechanism_without_equilibrium_raises_run_error():
    # The block on its rail with no spring: nothing holds it (E0806).
    free = SPRING.replace("SPRINGDAMPER/1", "!SPRINGDAMPER/1")
    with pytest.raises(mbfx.RunError, match="E0806"):
        model(free).linearize()
