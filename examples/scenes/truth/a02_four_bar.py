"""A02 N four-bar mechanism (reference-problems.md §4.2): the exact solution.

On the parallelogram branch every crank turns by the same theta from upright and the
couplers translate, so the mechanism is one pendulum (links of L = 1 m, m = 1 kg):
    J*theta'' = C*sin(theta),  J = m*L**2*((N+1)/3 + N),  C = m*g*L*((N+1)/2 + N),
    theta(0) = 0, theta'(0) = 1 rad/s;  B0 = (L*sin(theta), L*cos(theta)).
B0 is the top of the first crank, MARKER/203 of src/bench/generate.rs (four_bar).
Run: python3 a02_four_bar.py (mpmath Taylor ODE solver, 30 digits); prints B0 at
t = 1, 5, 10 for N = 1, 2, 40 and its difference from the table of §4.2.
"""
from mpmath import mp, mpf, sin, cos, odefun

mp.dps = 30
G, L, M = mpf("9.81"), mpf(1), mpf(1)

# §4.2's table: (N, t) -> (B0x, B0y).
TABLE = {
    (40, 1): ("-0.1153568806321099", "-0.99332411130045019"),
    (40, 5): ("-0.54019005067552627", "-0.84154305246444305"),
    (40, 10): ("0.18051222668672839", "0.98357274058231157"),
    (2, 1): ("-0.19502030194943509", "-0.98079920566217383"),
    (2, 5): ("-0.81131046100510741", "-0.58461554534897555"),
    (2, 10): ("0.32845811154081538", "0.94451853817860096"),
    (1, 1): ("-0.26071267518365036", "-0.96541643915907317"),
    (1, 5): ("-0.94490818604295389", "-0.32733548531898346"),
    (1, 10): ("0.47838505776097056", "0.8781501787912093"),
}


def main():
    for n in (1, 2, 40):
        j = M * L**2 * (mpf(n + 1) / 3 + n)
        c = M * G * L * (mpf(n + 1) / 2 + n)
        theta = odefun(lambda t, y: [y[1], c / j * sin(y[0])], 0, [mpf(0), mpf(1)])
        print(f"# N = {n}: J = {j}, C = {c}")
        for t in (1, 5, 10):
            th = theta(mpf(t))[0]
            bx, by = L * sin(th), L * cos(th)
            tx, ty = (mpf(v) for v in TABLE[(n, t)])
            dev = max(abs(bx - tx), abs(by - ty))
            assert dev < mpf("1e-16"), (n, t, dev)
            print(f"[[at]]\ntime = {float(t)!r}\nb0x = {mp.nstr(bx, 17)}\n"
                  f"b0y = {mp.nstr(by, 17)}\n# theta = {mp.nstr(th, 20)}, "
                  f"|B0 - table| = {mp.nstr(dev, 2)}")


if __name__ == "__main__":
    main()
