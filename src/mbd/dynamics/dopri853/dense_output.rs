//! DOP853's continuous extension of order 7 (Hairer, Nørsett & Wanner, *Solving ODEs I*,
//! §II.6 and §II.10, the dense output of their code `dop853`): over an accepted step
//! from y₀ to y₁ = y₀ + Δy of size h, with the twelve stages' slopes k₀…k₁₁, the slope
//! at the end k₁₂ = f(t₀ + h, y₁) and three more stages k₁₃…k₁₅ (at c = 0.1, 0.2, 7/9),
//!
//! ```text
//! y(t₀ + s·h) = y₀ + s·(F₀ + s'·(F₁ + s·(F₂ + s'·(F₃ + s·(F₄ + s'·(F₅ + s·F₆)))))),  s' = 1 − s,
//! F₀ = Δy,  F₁ = h·k₀ − Δy,  F₂ = 2·Δy − h·(k₀ + k₁₂),  F₃₊ᵢ = h·Σⱼ Dᵢⱼ·kⱼ.
//! ```
//!
//! F₀…F₂ alone are the cubic Hermite interpolant of (y₀, k₀, y₁, k₁₂); the D rows lift it to
//! order 7. The extra stages cost three evaluations, so [`super::Dopri853`] makes them
//! only for a step with an output time inside it. The coefficients are the published
//! decimals; the tests check them against the row sums and against a step of an ODE
//! whose solution is known.

// The published digits are kept as printed (see the tableau).
#![allow(clippy::excessive_precision)]

/// Stages of a step with its extension: the twelve, the end's slope, three more.
pub const EXTENDED: usize = 16;

/// The stage that holds the slope at the step's end, f(t₀ + h, y₁).
pub const END: usize = 12;

/// The nodes of the three extra stages (13, 14, 15).
pub const C_EXTRA: [f64; 3] = [0.1, 0.2, 0.777777777777777777777777777778];

/// The extra stages' coupling coefficients over the earlier stages (the end's slope, 12,
/// among them), as (j, aᵢⱼ).
pub const A_EXTRA: [&[(usize, f64)]; 3] = [
    &[
        (0, 5.61675022830479523392909219681e-2),
        (6, 2.53500210216624811088794765333e-1),
        (7, -2.46239037470802489917441475441e-1),
        (8, -1.24191423263816360469010140626e-1),
        (9, 1.5329179827876569731206322685e-1),
        (10, 8.20105229563468988491666602057e-3),
        (11, 7.56789766054569976138603589584e-3),
        (12, -8.298e-3),
    ],
    &[
        (0, 3.18346481635021405060768473261e-2),
        (5, 2.83009096723667755288322961402e-2),
        (6, 5.35419883074385676223797384372e-2),
        (7, -5.49237485713909884646569340306e-2),
        (10, -1.08347328697249322858509316994e-4),
        (11, 3.82571090835658412954920192323e-4),
        (12, -3.40465008687404560802977114492e-4),
        (13, 1.41312443674632500278074618366e-1),
    ],
    &[
        (0, -4.28896301583791923408573538692e-1),
        (5, -4.69762141536116384314449447206),
        (6, 7.68342119606259904184240953878),
        (7, 4.06898981839711007970213554331),
        (8, 3.56727187455281109270669543021e-1),
        (12, -1.39902416515901462129418009734e-3),
        (13, 2.9475147891527723389556272149),
        (14, -9.15095847217987001081870187138),
    ],
];

/// The rows D₀…D₃ (of F₃…F₆) over the sixteen stages, as (j, Dᵢⱼ).
const D: [[(usize, f64); 12]; 4] = [
    [
        (0, -0.84289382761090128651353491142e1),
        (5, 0.56671495351937776962531783590),
        (6, -0.30689499459498916912797304727e1),
        (7, 0.23846676565120698287728149680e1),
        (8, 0.21170345824450282767155149946e1),
        (9, -0.87139158377797299206789907490),
        (10, 0.22404374302607882758541771650e1),
        (11, 0.63157877876946881815570249290),
        (12, -0.88990336451333310820698117400e-1),
        (13, 0.18148505520854727256656404962e2),
        (14, -0.91946323924783554000451984436e1),
        (15, -0.44360363875948939664310572000e1),
    ],
    [
        (0, 0.10427508642579134603413151009e2),
        (5, 0.24228349177525818288430175319e3),
        (6, 0.16520045171727028198505394887e3),
        (7, -0.37454675472269020279518312152e3),
        (8, -0.22113666853125306036270938578e2),
        (9, 0.77334326684722638389603898808e1),
        (10, -0.30674084731089398182061213626e2),
        (11, -0.93321305264302278729567221706e1),
        (12, 0.15697238121770843886131091075e2),
        (13, -0.31139403219565177677282850411e2),
        (14, -0.93529243588444783865713862664e1),
        (15, 0.35816841486394083752465898540e2),
    ],
    [
        (0, 0.19985053242002433820987653617e2),
        (5, -0.38703730874935176555105901742e3),
        (6, -0.18917813819516756882830838328e3),
        (7, 0.52780815920542364900561016686e3),
        (8, -0.11573902539959630126141871134e2),
        (9, 0.68812326946963000169666922661e1),
        (10, -0.10006050966910838403183860980e1),
        (11, 0.77771377980534432092869265740),
        (12, -0.27782057523535084065932004339e1),
        (13, -0.60196695231264120758267380846e2),
        (14, 0.84320405506677161018159903784e2),
        (15, 0.11992291136182789328035130030e2),
    ],
    [
        (0, -0.25693933462703749003312586129e2),
        (5, -0.15418974869023643374053993627e3),
        (6, -0.23152937917604549567536039109e3),
        (7, 0.35763911791061412378285349910e3),
        (8, 0.93405324183624310003907691704e2),
        (9, -0.37458323136451633156875139351e2),
        (10, 0.10409964950896230045147246184e3),
        (11, 0.29840293426660503123344363579e2),
        (12, -0.43533456590011143754432175058e2),
        (13, 0.96324553959188282948394950600e2),
        (14, -0.39177261675615439165231486172e2),
        (15, -0.14972683625798562581422125276e3),
    ],
];

/// Rows of the extension's coefficients.
pub const ROWS: usize = 7;

/// The extension of one step over `len` components: F₀…F₆ row by row (`ROWS·len`).
#[derive(Clone, Debug, Default)]
pub struct Extension {
    f: Vec<f64>,
    len: usize,
}

impl Extension {
    /// Fills the coefficients of a step of `h` from Δy (`dy(i)`) and stage j's slope of
    /// component i (`slope(j, i)`, all [`EXTENDED`] stages). With `full` false the D rows
    /// are left out (F₃…F₆ = 0): the cubic Hermite interpolant, for a step whose extra
    /// stages could not be evaluated.
    pub fn fill(
        &mut self,
        len: usize,
        h: f64,
        full: bool,
        dy: impl Fn(usize) -> f64,
        slope: impl Fn(usize, usize) -> f64,
    ) {
        self.len = len;
        self.f.clear();
        self.f.resize(ROWS * len, 0.0);
        for i in 0..len {
            let (d, k0, k1) = (dy(i), slope(0, i), slope(END, i));
            self.f[i] = d;
            self.f[len + i] = h * k0 - d;
            self.f[2 * len + i] = 2.0 * d - h * (k0 + k1);
            if full {
                for (r, row) in D.iter().enumerate() {
                    let sum: f64 = row.iter().map(|&(j, x)| x * slope(j, i)).sum();
                    self.f[(3 + r) * len + i] = h * sum;
                }
            }
        }
    }

    /// y(t₀ + s·h) − y₀ of component `i`, s ∈ [0, 1].
    pub fn at(&self, i: usize, s: f64) -> f64 {
        let f = |r: usize| self.f[r * self.len + i];
        let s1 = 1.0 - s;
        s * (f(0) + s1 * (f(1) + s * (f(2) + s1 * (f(3) + s * (f(4) + s1 * (f(5) + s * f(6)))))))
    }
}

#[cfg(test)]
mod tests {
    use super::super::tableau::{A, B, C, STAGES};
    use super::*;

    #[test]
    fn each_extra_row_sums_to_its_node() {
        for (row, c) in A_EXTRA.iter().zip(C_EXTRA) {
            let sum: f64 = row.iter().map(|&(_, a)| a).sum();
            let size: f64 = row.iter().map(|&(_, a)| a.abs()).sum();
            assert!((sum - c).abs() <= 8.0 * f64::EPSILON * size, "{sum} vs {c}");
        }
    }

    /// One extended step of y' = f(t, y) (scalar) from (t0, y0): the extension.
    fn step(f: impl Fn(f64, f64) -> f64, t0: f64, y0: f64, h: f64) -> Extension {
        let mut k = [0.0; EXTENDED];
        let node = |s: usize| match s {
            s if s < STAGES => C[s],
            END => 1.0,
            s => C_EXTRA[s - END - 1],
        };
        let rows = |s: usize| match s {
            s if s < STAGES => A[s],
            END => &B[..],
            s => A_EXTRA[s - END - 1],
        };
        for s in 0..EXTENDED {
            let y = y0 + h * rows(s).iter().map(|&(j, a)| a * k[j]).sum::<f64>();
            k[s] = f(t0 + node(s) * h, y);
        }
        let y1 = y0 + h * B.iter().map(|&(j, b)| b * k[j]).sum::<f64>();
        let mut e = Extension::default();
        e.fill(1, h, true, |_| y1 - y0, |j, _| k[j]);
        e
    }

    #[test]
    fn the_extension_is_of_order_seven_inside_the_step() {
        // y' = −t·y³ + cos t from y(0) = 1 has no closed form; y' = y·cos t does:
        // y = exp(sin t). The error inside the step falls as h⁸ (order 7), so halving h
        // divides it by about 256 (at least 128 allowed).
        let f = |t: f64, y: f64| y * t.cos();
        let exact = |t: f64| t.sin().exp();
        let worst = |h: f64| {
            let e = step(f, 0.3, exact(0.3), h);
            (1..10)
                .map(|k| {
                    let s = k as f64 / 10.0;
                    (exact(0.3) + e.at(0, s) - exact(0.3 + s * h)).abs()
                })
                .fold(0.0, f64::max)
        };
        let (e1, e2) = (worst(0.4), worst(0.2));
        assert!(e1 < 1e-7, "{e1}");
        assert!(e1 / e2 > 128.0, "order: {e1} / {e2} = {}", e1 / e2);
    }

    #[test]
    fn the_hermite_part_alone_meets_the_ends_and_their_slopes() {
        let mut e = Extension::default();
        // y₀ = 0, y₁ = 2, slopes 1 and 3 over h = 0.5.
        e.fill(
            1,
            0.5,
            false,
            |_| 2.0,
            |j, _| if j == 0 { 1.0 } else { 3.0 },
        );
        assert_eq!(e.at(0, 0.0), 0.0);
        assert!((e.at(0, 1.0) - 2.0).abs() < 1e-15);
        // Central differences a hair inside the ends (the curvature moves the slope by
        // about 7·s there).
        let ds = 1e-7;
        let slope = |s: f64| (e.at(0, s + ds) - e.at(0, s - ds)) / (2.0 * ds) / 0.5;
        let (a, b) = (slope(1e-5), slope(1.0 - 1e-5));
        assert!((a - 1.0).abs() < 1e-3 && (b - 3.0).abs() < 1e-3, "{a}, {b}");
    }
}
