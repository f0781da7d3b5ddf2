"""A01 planar simple pendulum (reference-problems.md §4.1): the exact solution.

A point mass on a massless link of L = 1 m, g = 9.81, released at rest horizontal at
(+1, 0). With phi from the downward vertical, phi0 = pi/2, k = sin(pi/4), m = k**2 = 1/2,
w0 = sqrt(g/L), K = K(m) and u = K - w0*t (Jacobi elliptic functions of parameter m):
    x = 2*k*sn(u)*dn(u)*L,   y = -(1 - 2*k**2*sn(u)**2)*L.
Checked here against an mpmath Taylor integration of phi'' = -(g/L)*sin(phi).
Run: python3 a01_pendulum.py (mpmath at 30 digits); prints the [[at]] rows of
a01_pendulum.toml.
"""
from mpmath import mp, mpf, sqrt, sin, pi, ellipk, ellipfun, odefun

mp.dps = 30
G, L = mpf("9.81"), mpf(1)
TIMES = ["0.5", "1", "2", "10"]


def exact(t):
    m = mpf(1) / 2
    k = sqrt(m)
    u = ellipk(m) - sqrt(G / L) * t
    sn, dn = ellipfun("sn", u, m=m), ellipfun("dn", u, m=m)
    return 2 * k * sn * dn * L, -(1 - 2 * k**2 * sn**2) * L


def main():
    print("# period 4K/w0 =", 4 * ellipk(mpf(1) / 2) / sqrt(G / L))
    phi = odefun(lambda t, y: [y[1], -(G / L) * sin(y[0])], 0, [pi / 2, mpf(0)])
    for ts in TIMES:
        t = mpf(ts)
        x, y = exact(t)
        p = phi(t)[0]
        check = max(abs(x - L * sin(p)), abs(y + L * mp.cos(p)))
        assert check < mpf("1e-20"), (ts, check)
        print(f"\n[[at]]\ntime = {float(t)!r}\nx = {mp.nstr(x, 17)}\ny = {mp.nstr(y, 17)}")


if __name__ == "__main__":
    main()
