//! Independent reference solutions: a Dormand–Prince 5(4) integrator for small ODEs
//! (std only, adaptive, landing exactly on every output time) and the Jacobi elliptic
//! functions that give the A01 pendulum in closed form. Nothing here calls mbfx: these are
//! the outside truths the dynamics is measured against, so they are themselves checked
//! against closed forms in this file's tests.

/// Dormand–Prince 5(4) (Hairer, Nørsett & Wanner, *Solving ODEs I*, table 5.2), local
/// extrapolation, step control on the mixed error norm `atol + rtol·|y|`.
/// Integrates `y' = f(t, y)` from `(times[0], y0)` and returns `y` at every entry of `times`
/// (increasing). Steps are cut to land on each output time, so no interpolation error enters.
pub fn dopri5<const N: usize>(
    f: impl Fn(f64, &[f64; N]) -> [f64; N],
    y0: [f64; N],
    times: &[f64],
    rtol: f64,
    atol: f64,
) -> Vec<[f64; N]> {
    const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
    const A: [[f64; 6]; 7] = [
        [0.0; 6],
        [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
        [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
        [
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
            0.0,
            0.0,
        ],
        [
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
            0.0,
        ],
        [
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ];
    // Fifth-order weights minus the embedded fourth-order ones.
    const E: [f64; 7] = [
        71.0 / 57600.0,
        0.0,
        -71.0 / 16695.0,
        71.0 / 1920.0,
        -17253.0 / 339200.0,
        22.0 / 525.0,
        -1.0 / 40.0,
    ];
    let mut out = vec![y0];
    let mut t = times[0];
    let mut y = y0;
    let mut h = 1e-4;
    let mut k = [[0.0; N]; 7];
    for &t_out in &times[1..] {
        while t < t_out {
            let last = t + h >= t_out;
            let step = if last { t_out - t } else { h };
            k[0] = f(t, &y);
            for s in 1..7 {
                let mut ys = y;
                for (i, yi) in ys.iter_mut().enumerate() {
                    *yi += step * (0..s).map(|j| A[s][j] * k[j][i]).sum::<f64>();
                }
                k[s] = f(t + C[s] * step, &ys);
            }
            // Stage 7 is evaluated at the fifth-order solution (FSAL), so that is y_new.
            let mut y_new = y;
            for (i, yi) in y_new.iter_mut().enumerate() {
                *yi += step * (0..6).map(|j| A[6][j] * k[j][i]).sum::<f64>();
            }
            k[6] = f(t + step, &y_new);
            let err = (0..N)
                .map(|i| {
                    let e = step * (0..7).map(|j| E[j] * k[j][i]).sum::<f64>();
                    let sc = atol + rtol * y[i].abs().max(y_new[i].abs());
                    (e / sc).powi(2)
                })
                .sum::<f64>()
                / N as f64;
            let err = err.sqrt();
            let factor = (0.9 * err.powf(-0.2)).clamp(0.2, 5.0);
            if err <= 1.0 {
                t = if last { t_out } else { t + step };
                y = y_new;
                if !last {
                    h = step * factor;
                }
            } else {
                h = step * factor;
            }
            assert!(h > 1e-14, "reference integrator: step underflow at t = {t}");
        }
        out.push(y);
    }
    out
}

/// Jacobi elliptic functions (sn, cn, dn) of argument `u` and parameter `m` (0 ≤ m < 1) by
/// the arithmetic–geometric mean (Abramowitz & Stegun 16.4), and K(m) = π / (2·AGM).
pub fn jacobi_sn_cn_dn(u: f64, m: f64) -> (f64, f64, f64) {
    let (mut a, mut b) = (1.0_f64, (1.0 - m).sqrt());
    let mut c = vec![m.sqrt()];
    let mut an = vec![a];
    while c.last().unwrap().abs() > 1e-17 && c.len() < 40 {
        let (a1, b1) = ((a + b) / 2.0, (a * b).sqrt());
        c.push((a - b) / 2.0);
        a = a1;
        b = b1;
        an.push(a);
    }
    let n = c.len() - 1;
    let mut phi = 2f64.powi(n as i32) * a * u;
    for i in (1..=n).rev() {
        phi = (phi + (c[i] / an[i] * phi.sin()).asin()) / 2.0;
    }
    let (sn, cn) = (phi.sin(), phi.cos());
    // dn > 0 for m < 1; A&S's cn/cos(φ₁ − φ₀) is 0/0 at u = K.
    (sn, cn, (1.0 - m * sn * sn).sqrt())
}

/// Complete elliptic integral of the first kind K(m) = π / (2·AGM(1, √(1−m))).
pub fn elliptic_k(m: f64) -> f64 {
    let (mut a, mut b) = (1.0_f64, (1.0 - m).sqrt());
    // Quadratic convergence: 8 rounds reach the last bit (a loop on |a − b| may alternate
    // in the last ulp forever).
    for _ in 0..8 {
        (a, b) = ((a + b) / 2.0, (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

/// IFToMM A01 (reference-problems §4.1): a 1 kg point mass on a massless 1 m link, g = 9.81
/// in −y, released at rest from P1 = (1, 0). Exact position at time `t`:
/// x = 2k·sn(u)·dn(u)·L, y = −(1 − 2k²·sn²(u))·L, k = sin(π/4), u = K(k²) − ω₀t.
pub fn a01_exact(t: f64) -> (f64, f64) {
    let (l, g) = (A01_LENGTH, A01_GRAVITY);
    let k = std::f64::consts::FRAC_PI_4.sin();
    let m = k * k;
    let u = elliptic_k(m) - (g / l).sqrt() * t;
    let (sn, _, dn) = jacobi_sn_cn_dn(u, m);
    (2.0 * k * sn * dn * l, -(1.0 - 2.0 * m * sn * sn) * l)
}

pub const A01_LENGTH: f64 = 1.0;
pub const A01_GRAVITY: f64 = 9.81;
pub const A01_MASS: f64 = 1.0;

/// Reference-problems §4.1's table: (t, x, y), computed there with mpmath to 17 digits.
// The published digits as printed, some beyond f64's: they round to the nearest double.
#[allow(clippy::excessive_precision)]
pub const A01_TABLE: [(f64, f64, f64); 7] = [
    (0.5, 0.39104879155054639, -0.9203699487851922),
    (1.0, -0.98629175113187532, -0.16501085312554117),
    (2.0, 0.79356619534332175, -0.60848393044379151),
    (10.0, 0.27508746257611686, -0.96141920509912506),
    (100.0, 0.18151335142703138, -0.9833884803340575),
    (1000.0, -0.68323018855231486, -0.73020306042276233),
    (2000.0, -0.81460306858903215, -0.58001882783693546),
];

/// §4.1's period 4K/ω₀ (2.36784194757623744930329503724 s).
pub const A01_PERIOD: f64 = 2.367_841_947_576_237_4;

/// Andrews' squeezing mechanism, the Test Set version (reference-problems §2.1: Mazzia,
/// Magherini & Iavernaro's `andrews.f`; Hairer & Wanner II, §VII.7): its parameters, the
/// constraints g(q) in the Test Set's coordinates q = (β, Θ, γ, Φ, δ, Ω, ε), the spring, the
/// consistent initial values and the PSIDE reference at t = 0.03, copied from §2.1.
pub mod squeezer {
    /// m1..m7 (kg) and I1..I7 (kg·m², about each CM's z axis).
    pub const MASS: [f64; 7] = [
        0.04325, 0.00365, 0.02373, 0.00706, 0.07050, 0.00706, 0.05498,
    ];
    pub const INERTIA: [f64; 7] = [
        2.194e-6, 4.410e-7, 5.255e-6, 5.667e-7, 1.169e-5, 5.667e-7, 1.912e-5,
    ];
    /// The spring (c0 N/m, free length l0 m) from D on body 3 to the fixed point C, and the
    /// motor torque mom (N·m) on body 1.
    pub const C0: f64 = 4530.0;
    pub const L0: f64 = 7785e-5;
    pub const MOM: f64 = 33e-3;
    // Fixed points and lengths (m), the Test Set's names.
    const XA: f64 = -0.06934;
    const YA: f64 = -0.00227;
    const XB: f64 = -0.03635;
    const YB: f64 = 0.03273;
    const XC: f64 = 0.014;
    const YC: f64 = 0.072;
    const D: f64 = 28e-3;
    const E: f64 = 2e-2;
    const RR: f64 = 7e-3;
    const SS: f64 = 35e-3;
    const SC: f64 = 18e-3;
    const SD: f64 = 2e-2;
    const U: f64 = 4e-2;
    const ZF: f64 = 2e-2;
    const ZT: f64 = 4e-2;

    /// g1..g6: the point E reached from O through bodies 1 and 2 equals E reached from B
    /// through body 3 (g1, g2), from A through bodies 5 and 4 (g3, g4), and from A through
    /// bodies 7 and 6 (g5, g6).
    pub fn constraints(q: &[f64; 7]) -> [f64; 6] {
        let [b, th, ga, ph, de, om, ep] = *q;
        let ex = RR * b.cos() - D * (b + th).cos();
        let ey = RR * b.sin() - D * (b + th).sin();
        [
            ex - SS * ga.sin() - XB,
            ey + SS * ga.cos() - YB,
            ex - E * (ph + de).sin() - ZT * de.cos() - XA,
            ey + E * (ph + de).cos() - ZT * de.sin() - YA,
            ex - ZF * (om + ep).cos() - U * ep.sin() - XA,
            ey - ZF * (om + ep).sin() + U * ep.cos() - YA,
        ]
    }

    /// The spring's energy ½·c0·(L − l0)² at body 3's angle γ, L = |D − C| with
    /// D = (sd·cos γ + sc·sin γ + xb, sd·sin γ − sc·cos γ + yb).
    pub fn spring_energy(gamma: f64) -> f64 {
        let (s, c) = gamma.sin_cos();
        let l = (SD * c + SC * s + XB - XC).hypot(SD * s - SC * c + YB - YC);
        0.5 * C0 * (l - L0).powi(2)
    }

    // §2.1's digits as printed, some beyond f64's: they round to the nearest double.
    /// Consistent initial positions q0 (rad); v0 = 0.
    #[allow(clippy::excessive_precision)]
    pub const Q0: [f64; 7] = [
        -0.0617138900142764496358948458001,
        0.0,
        0.455279819163070380255912382449,
        0.222668390165885884674473185609,
        0.487364979543842550225598953530,
        -0.222668390165885884674473185609,
        1.23054744454982119249735015568,
    ];
    /// Consistent initial accelerations w0 = q̈(0) and multipliers λ0.
    #[allow(clippy::excessive_precision)]
    pub const W0: [f64; 7] = [
        14222.4439199541138705911625887,
        -10666.8329399655854029433719415,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
    ];
    #[allow(clippy::excessive_precision)]
    pub const LAMBDA0: [f64; 6] = [
        98.5668703962410896057654982170,
        -6.12268834425566265503114393122,
        0.0,
        0.0,
        0.0,
        0.0,
    ];
    /// The reference at t = 0.03 (PSIDE, rtol = atol = 1e-14): y1..y7 = q, y8..y14 = q̇,
    /// y15..y21 = q̈, y22..y27 = λ. Positions good to 15–16 digits, velocities to about 10,
    /// accelerations and multipliers to about 1e-8 relative (§2.1).
    pub const END: f64 = 0.03;
    #[allow(clippy::excessive_precision)]
    pub const Y_REF: [f64; 27] = [
        0.1581077119629904e+2,
        -0.1575637105984298e+2,
        0.4082224013073101e-1,
        -0.5347301163226948e+0,
        0.5244099658805304e+0,
        0.5347301163226948e+0,
        0.1048080741042263e+1,
        0.1139920302151208e+4,
        -0.1424379294994111e+4,
        0.1103291221937134e+2,
        0.1929337464421385e+2,
        0.5735699284790808e+0,
        -0.1929337464421385e+2,
        0.3231791658026955e+0,
        -0.2463176316945196e+5,
        0.5185037701610329e+5,
        0.3241025686413781e+6,
        0.5667493645176213e+6,
        0.1674362929479361e+5,
        -0.5667493645176222e+6,
        0.9826520791458422e+4,
        0.1991753333731910e+3,
        -0.2975531228015052e+2,
        0.2306654119098399e+2,
        0.3145271365475927e+2,
        0.2264249232082739e+2,
        0.1161740700019673e+2,
    ];
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dopri5_reproduces_a_damped_oscillator_in_closed_form() {
        // x'' + 2ζω x' + ω² x = 0, x(0) = 1, x'(0) = 0, ζ = 0.1, ω = 3.
        let (z, w) = (0.1, 3.0);
        let times: Vec<f64> = (0..=500).map(|i| i as f64 * 0.01).collect();
        let ys = dopri5(
            |_, y| [y[1], -2.0 * z * w * y[1] - w * w * y[0]],
            [1.0, 0.0],
            &times,
            1e-12,
            1e-14,
        );
        let wd = w * (1.0 - z * z).sqrt();
        for (t, y) in times.iter().zip(&ys) {
            let exact = (-z * w * t).exp() * ((wd * t).cos() + z * w / wd * (wd * t).sin());
            assert!((y[0] - exact).abs() < 1e-11, "t = {t}: {} vs {exact}", y[0]);
        }
    }

    #[test]
    fn elliptic_functions_give_the_a01_table_and_period() {
        let k = std::f64::consts::FRAC_PI_4.sin();
        let period = 4.0 * elliptic_k(k * k) / (A01_GRAVITY / A01_LENGTH).sqrt();
        assert!((period - A01_PERIOD).abs() < 1e-14, "{period}");
        for (t, x, y) in A01_TABLE {
            let (xe, ye) = a01_exact(t);
            // u = K − ω₀t loses about |u|·ε in the subtraction: 1e-12 at t = 2000.
            let tol = 1e-14 * (1.0 + 20.0 * t);
            assert!(
                (xe - x).abs() < tol && (ye - y).abs() < tol,
                "t = {t}: ({xe}, {ye})"
            );
        }
        // sn² + cn² = 1 and dn² + m·sn² = 1 at an arbitrary point.
        let (sn, cn, _) = jacobi_sn_cn_dn(0.7, 0.3);
        assert!((sn * sn + cn * cn - 1.0).abs() < 1e-15);
        // At u = K: sn = 1, dn = √(1 − m), so A01 starts at (2k·√(1 − k²), 0) = (1, 0).
        let (sn, _, dn) = jacobi_sn_cn_dn(elliptic_k(0.5), 0.5);
        assert!((sn - 1.0).abs() < 1e-15 && (dn - 0.5f64.sqrt()).abs() < 1e-15);
        let (x0, y0) = a01_exact(0.0);
        assert!((x0 - 1.0).abs() < 1e-15 && y0.abs() < 1e-15);
    }

    #[test]
    fn dopri5_reproduces_the_a01_table() {
        // φ from the downward vertical, φ'' = −(g/L)·sin φ, φ(0) = π/2.
        let w2 = A01_GRAVITY / A01_LENGTH;
        let times = [0.0, 0.5, 1.0, 2.0, 10.0];
        let ys = dopri5(
            |_, y| [y[1], -w2 * y[0].sin()],
            [std::f64::consts::FRAC_PI_2, 0.0],
            &times,
            1e-13,
            1e-15,
        );
        for ((t, x, y), s) in A01_TABLE.iter().zip(&ys[1..]) {
            let (xe, ye) = (s[0].sin(), -s[0].cos());
            assert!((xe - x).abs() < 1e-10 && (ye - y).abs() < 1e-10, "t = {t}");
        }
    }
}
