//! The trigonometric functions against the platform's libm (both under 1 ulp, so they may
//! differ by 1 ulp and no more), at the values the spec fixes, and block against scalar.

use super::*;
use crate::test_util::ulps;

/// A reproducible stream of doubles: `scale` times a uniform number in (−1, 1).
fn samples(seed: u64, count: usize, scale: f64) -> impl Iterator<Item = f64> {
    let mut s = seed;
    (0..count).map(move |_| {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        scale * ((s >> 11) as f64 / (1u64 << 52) as f64 - 1.0)
    })
}

/// Arguments over every scale the fast path takes, and the multiples of π/2 nearest
/// doubles fall on (where x − n·π/2 cancels most).
fn trig_arguments() -> Vec<f64> {
    let mut xs = Vec::new();
    for (k, scale) in [1e-300, 1e-8, 0.5, 1.0, 4.0, 10.0, 100.0, 1e4, 1e6]
        .iter()
        .enumerate()
    {
        xs.extend(samples(0x9e37_79b9 + k as u64, 20_000, *scale));
    }
    for n in 1..200_000u32 {
        let x = f64::from(n) * core::f64::consts::FRAC_PI_2;
        xs.extend([x, x.next_up(), x.next_down(), -x]);
    }
    xs.retain(|x| x.abs() < TRIG_LIMIT);
    xs
}

#[test]
fn sin_and_cos_are_within_one_ulp_of_libm() {
    for x in trig_arguments() {
        assert!(
            ulps(sin(x), x.sin()) <= 1,
            "sin({x:e}) = {:e}, libm {:e}",
            sin(x),
            x.sin()
        );
        assert!(
            ulps(cos(x), x.cos()) <= 1,
            "cos({x:e}) = {:e}, libm {:e}",
            cos(x),
            x.cos()
        );
    }
}

#[test]
fn atan2_is_within_one_ulp_of_libm() {
    let mut args: Vec<(f64, f64)> = Vec::new();
    for (k, (sy, sx)) in [
        (1.0, 1.0),
        (1e-3, 1.0),
        (1.0, 1e-3),
        (1e10, 1e-10),
        (1e-200, 1e200),
    ]
    .iter()
    .enumerate()
    {
        let ys = samples(0x51ed + k as u64, 50_000, *sy);
        let xs = samples(0x2545_f491 + k as u64, 50_000, *sx);
        args.extend(ys.zip(xs));
    }
    // The breakpoints of the reduction (|y/x| = 7/16, 11/16, 1) and their neighbours.
    for r in [0.4375f64, 0.6875, 1.0] {
        for v in [r.next_down(), r, r.next_up()] {
            args.extend([(v, 1.0), (1.0, v), (-v, 1.0), (v, -1.0), (-1.0, -v)]);
        }
    }
    for (y, x) in args {
        let (got, want) = (atan2(y, x), y.atan2(x));
        assert!(
            ulps(got, want) <= 1,
            "atan2({y:e}, {x:e}) = {got:e}, libm {want:e}"
        );
    }
}

#[test]
fn symmetric_and_exact_where_the_value_is_known() {
    for x in trig_arguments() {
        assert_eq!(
            sin(-x).to_bits(),
            (-sin(x)).to_bits(),
            "sin is odd at {x:e}"
        );
        assert_eq!(cos(-x).to_bits(), cos(x).to_bits(), "cos is even at {x:e}");
    }
    assert_eq!(sin(0.0).to_bits(), 0.0f64.to_bits());
    assert_eq!(sin(-0.0).to_bits(), (-0.0f64).to_bits());
    assert_eq!(cos(0.0), 1.0);
    assert_eq!(cos(-0.0), 1.0);
    // Below 2⁻²⁷, sin x = x and cos x = 1 after rounding (x³/6 and x²/2 are below half
    // an ulp); the smallest subnormal too.
    for x in [2f64.powi(-30), 1e-300, f64::from_bits(1)] {
        assert_eq!(sin(x), x);
        assert_eq!(cos(x), 1.0);
    }
    // atan2 at the diagonals and axes: the doubles nearest π/4, 3π/4 and π/2.
    let pi = core::f64::consts::PI;
    assert_eq!(atan2(1.0, 1.0), pi / 4.0);
    assert_eq!(atan2(-2.5, -2.5), -0.75 * pi);
    assert_eq!(atan2(3.0, 1e-320), pi / 2.0);
    assert_eq!(atan2(0.0, -1.0), pi);
    assert_eq!(atan2(-0.0, 1.0).to_bits(), (-0.0f64).to_bits());
}

#[test]
fn non_finite_and_huge_arguments_are_libms() {
    for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert!(sin(x).is_nan() && cos(x).is_nan());
    }
    for x in [TRIG_LIMIT, 1e9, -3e15, 1e300] {
        assert_eq!(sin(x).to_bits(), x.sin().to_bits());
        assert_eq!(cos(x).to_bits(), x.cos().to_bits());
    }
    for (y, x) in [
        (0.0, 0.0),
        (1.0, f64::INFINITY),
        (f64::NAN, 1.0),
        (1e300, 1e-300),
    ] {
        assert_eq!(atan2(y, x).to_bits(), y.atan2(x).to_bits());
    }
}

#[test]
fn blocks_give_the_scalar_bits() {
    let special = [
        0.0,
        -0.0,
        f64::NAN,
        f64::INFINITY,
        -1e300,
        TRIG_LIMIT,
        TRIG_LIMIT.next_down(),
        1e-310,
    ];
    let mut xs: Vec<f64> = samples(7, 1000, 20.0).collect();
    xs.extend(special);
    let ys: Vec<f64> = samples(11, xs.len(), 3.0).chain(special).collect();
    for (xb, yb) in xs.chunks_exact(8).zip(ys.chunks_exact(8)) {
        let x: [f64; 8] = xb.try_into().unwrap();
        let y: [f64; 8] = yb.try_into().unwrap();
        let (mut s, mut c, mut a) = ([0.0; 8], [0.0; 8], [0.0; 8]);
        sin_lanes(&mut s, &x);
        cos_lanes(&mut c, &x);
        atan2_lanes(&mut a, &y, &x);
        for i in 0..8 {
            assert_eq!(s[i].to_bits(), sin(x[i]).to_bits(), "sin({:e})", x[i]);
            assert_eq!(c[i].to_bits(), cos(x[i]).to_bits(), "cos({:e})", x[i]);
            assert_eq!(a[i].to_bits(), atan2(y[i], x[i]).to_bits(), "atan2 at {i}");
        }
    }
}

/// The scalar path skips the reduction below 0.785 (n = 0 there), which is only sound if
/// the reduction would give back the argument exactly.
#[test]
fn below_pi_over_4_the_reduction_is_the_identity() {
    let mut xs: Vec<f64> = samples(3, 100_000, 0.785).map(f64::abs).collect();
    xs.extend([0.0, f64::from_bits(1), 1e-300, 0.785f64.next_down()]);
    for ax in xs {
        let (y0, y1, n) = reduce(ax);
        assert_eq!(
            (y0.to_bits(), y1.to_bits(), n),
            (ax.to_bits(), 0, 0),
            "{ax:e}"
        );
    }
}
