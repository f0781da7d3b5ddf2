"""Light cart-pole (reference-problems.md §4.7): the exact solution by quadrature.

Cart M = 1e-6 kg on a frictionless horizontal track, massless pole L = 1 m pinned to it,
point mass m = 1 kg at the pole's end, released at rest with the pole horizontal
(theta = pi/2, the mass at +x of the cart), g = 9.81 (assumed: the source does not state
it). theta is measured from the downward vertical, counterclockwise: the mass sits at
cart + L*(sin(theta), -cos(theta)). Horizontal momentum (0) and energy are conserved:
    theta'**2 = 2*g*cos(theta) / (L*(mu*cos(theta)**2 + sin(theta)**2)),  mu = M/(M+m),
    x_cart = (m*L/(M+m))*(1 - sin(theta)),   y_mass = -L*cos(theta).
With F(phi) = integral_0^phi dtheta/theta', the quarter swing is Q = F(pi/2); the motion
goes pi/2 -> 0 -> -pi/2 -> 0 -> pi/2 in 4Q, each leg one inversion of F.
Run: python3 cart_pole.py (mpmath at 30 digits); prints Q, the peak rate and the
[[at]] rows of cart_pole.toml, and checks them against the table of §4.7.
"""
from mpmath import mp, mpf, sqrt, sin, cos, pi, quad, findroot

mp.dps = 30
G, L, M, m = mpf("9.81"), mpf(1), mpf("1e-6"), mpf(1)
MU = M / (M + m)


def rate(th):
    return sqrt(2 * G * cos(th) / (L * (MU * cos(th) ** 2 + sin(th) ** 2)))


# Split points resolve the width-sqrt(mu) dip of 1/theta' at the vertical.
SPLITS = [mpf(0), mpf("1e-4"), mpf("1e-3"), mpf("1e-2"), mpf("0.1"), mpf(1)]


def F(phi):
    pts = [p for p in SPLITS if p < phi] + [phi]
    return quad(lambda th: 1 / rate(th), pts)


def F_inverse(tau):
    """theta in [0, pi/2] with F(theta) = tau."""
    return findroot(lambda th: F(th) - tau, (mpf(0), pi / 2), solver="anderson")


Q = F(pi / 2)


def theta(t):
    s = t % (4 * Q)
    if s <= Q:
        return F_inverse(Q - s)
    if s <= 2 * Q:
        return -F_inverse(s - Q)
    if s <= 3 * Q:
        return -F_inverse(3 * Q - s)
    return F_inverse(s - 3 * Q)


# §4.7's table: t -> (theta, x_cart).
TABLE = {1: ("-1.524675515758677", "1.998934624974967"),
         5: ("0.5389876497103628", "0.486732086555402"),
         10: ("-1.549129441894826", "1.999763282468728")}


def main():
    print("# Q =", Q, " period =", 4 * Q, " peak rate =", rate(0))
    for t in (1, 5, 10):
        th = theta(mpf(t))
        x_cart = m * L / (M + m) * (1 - sin(th))
        y_mass = -L * cos(th)
        dev = max(abs(th - mpf(TABLE[t][0])), abs(x_cart - mpf(TABLE[t][1])))
        assert dev < mpf("1e-14"), (t, dev)
        print(f"\n[[at]]\ntime = {float(t)!r}\ntheta = {mp.nstr(th, 17)}\n"
              f"x_cart = {mp.nstr(x_cart, 17)}\ny_mass = {mp.nstr(y_mass, 17)}\n"
              f"# theta' = {mp.nstr(rate(th), 17)} (sign from the leg), "
              f"|table - here| = {mp.nstr(dev, 2)}")


if __name__ == "__main__":
    main()
