//! mbfx's own `SIN`, `COS` and `ATAN2`: under 1 ulp, the same bits on every platform and
//! in every back end, and written so that a loop over an array of them vectorises.
//!
//! The C library's routines branch on the argument's range and differ between platforms
//! (glibc, musl and macOS round differently), so an evaluator over arrays could only call
//! them one point at a time. These use only IEEE additions, multiplications and
//! divisions (no FMA: Rust never contracts, and none is written), so the scalar call of
//! the interpreter and the JIT and the block loop of the lane evaluator give the same
//! bits, on any x86-64 level and on any other target.
//!
//! - **SIN, COS** for |x| < 2²⁰: x − n·π/2 by Cody–Waite in four pieces of π/2 (three of
//!   33 bits, so n·piece is exact for n < 2²⁰, then the rest), carried as a double-double
//!   (y0, y1); then the sine or cosine polynomial of the quadrant on [−π/4, π/4] with the
//!   tail's first-order correction. The polynomials' coefficients are fdlibm's (Sun, 1993;
//!   |error| ≤ 2⁻⁵⁸ on [0, π/4]). Larger, infinite and NaN arguments go to `f64::sin` /
//!   `f64::cos` (the platform's libm), which is then the answer in every back end too.
//! - **ATAN2(y, x)** for finite, non-zero x and y between 2⁻⁵⁰⁰ and 2⁵⁰⁰ in magnitude: with
//!   num/den = min/max ≤ 1, atan(num/den) = atan(c) + atan(t), c ∈ {0, ½, 1} and
//!   t = (num − c·den)/(den + c·num), its rounding error recovered (Dekker's product);
//!   fdlibm's atan polynomial on |t| ≤ 7/16; then the quadrant's k·π/2 ± atan(num/den)
//!   summed with π and atan(c) as double-doubles, so only the last addition rounds at the
//!   result's scale.
//!   Zeros, infinities, NaN and extreme magnitudes go to `f64::atan2`.
//!
//! The accuracy is measured, not only argued: `tests/python/test_trig_accuracy.py`
//! compares with mpmath at 200 bits, and the unit tests below with the platform's libm.

/// Arguments of SIN and COS below this take the Cody–Waite path (n = round(x·2/π) stays
/// below 2²⁰, so n times a 33-bit piece of π/2 is exact).
pub const TRIG_LIMIT: f64 = 1_048_576.0;

/// 2/π, rounded.
const TWO_OVER_PI: f64 = f64::from_bits(0x3fe4_5f30_6dc9_c883);
/// π/2 in pieces: the first three 33 significant bits each, then the rest, rounded.
const PIO2_1: f64 = f64::from_bits(0x3ff9_21fb_5440_0000);
const PIO2_2: f64 = f64::from_bits(0x3dd0_b461_1a60_0000);
const PIO2_3: f64 = f64::from_bits(0x3ba3_198a_2e00_0000);
const PIO2_3T: f64 = f64::from_bits(0x397b_839a_2520_49c1);
/// 1.5·2⁵²: adding it rounds to an integer, which then sits in the low mantissa bits.
const ROUNDER: f64 = 6_755_399_441_055_744.0;

/// Sine polynomial (fdlibm `__kernel_sin`): sin x ≈ x + S1·x³ + … + S6·x¹³.
const S1: f64 = f64::from_bits(0xbfc5_5555_5555_5549);
const S2: f64 = f64::from_bits(0x3f81_1111_1110_f8a6);
const S3: f64 = f64::from_bits(0xbf2a_01a0_19c1_61d5);
const S4: f64 = f64::from_bits(0x3ec7_1de3_57b1_fe7d);
const S5: f64 = f64::from_bits(0xbe5a_e5e6_8a2b_9ceb);
const S6: f64 = f64::from_bits(0x3de5_d93a_5acf_d57c);

/// Cosine polynomial (fdlibm `__kernel_cos`): cos x ≈ 1 − x²/2 + C1·x⁴ + … + C6·x¹⁴.
const C1: f64 = f64::from_bits(0x3fa5_5555_5555_554c);
const C2: f64 = f64::from_bits(0xbf56_c16c_16c1_5177);
const C3: f64 = f64::from_bits(0x3efa_01a0_19cb_1590);
const C4: f64 = f64::from_bits(0xbe92_7e4f_809c_52ad);
const C5: f64 = f64::from_bits(0x3e21_ee9e_bdb4_b1c4);
const C6: f64 = f64::from_bits(0xbda8_fae9_be88_38d4);

/// Arctangent polynomial (fdlibm `atan`): atan t ≈ t − t·(A0·t² + A1·t⁴ + … + A10·t²²).
const AT: [f64; 11] = [
    f64::from_bits(0x3fd5_5555_5555_550d),
    f64::from_bits(0xbfc9_9999_9998_ebc4),
    f64::from_bits(0x3fc2_4924_9200_83ff),
    f64::from_bits(0xbfbc_71c6_fe23_1671),
    f64::from_bits(0x3fb7_45cd_c54c_206e),
    f64::from_bits(0xbfb3_b0f2_af74_9a6d),
    f64::from_bits(0x3fb1_0d66_a0d0_3d51),
    f64::from_bits(0xbfad_de2d_52de_fd9a),
    f64::from_bits(0x3fa9_7b4b_2476_0deb),
    f64::from_bits(0xbfa2_b444_2c6a_6c2f),
    f64::from_bits(0x3f90_ad3a_e322_da11),
];
/// atan(½) and atan(1) as double-doubles (high, low).
const ATAN_HALF: (f64, f64) = (
    f64::from_bits(0x3fdd_ac67_0561_bb4f),
    f64::from_bits(0x3c7a_2b7f_222f_65e2),
);
const ATAN_ONE: (f64, f64) = (
    f64::from_bits(0x3fe9_21fb_5444_2d18),
    f64::from_bits(0x3c81_a626_3314_5c07),
);
/// π/2 as a double-double.
const PIO2: (f64, f64) = (
    f64::from_bits(0x3ff9_21fb_5444_2d18),
    f64::from_bits(0x3c91_a626_3314_5c07),
);
/// ATAN2's fast path takes magnitudes in (2⁻⁵⁰⁰, 2⁵⁰⁰): Dekker's split of them cannot
/// overflow and their ratio stays a normal number.
const ATAN2_LOW: f64 = f64::from_bits(0x20b0_0000_0000_0000);
const ATAN2_HIGH: f64 = f64::from_bits(0x5f30_0000_0000_0000);

/// True where SIN and COS take the Cody–Waite path (false for NaN and ±∞).
#[inline(always)]
fn in_range(x: f64) -> bool {
    x.abs() < TRIG_LIMIT
}

/// `a` where `pick`, `b` elsewhere (both computed: a select, which block loops vectorise).
#[inline(always)]
fn blend(pick: bool, a: f64, b: f64) -> f64 {
    if pick {
        a
    } else {
        b
    }
}

/// `x` with its sign bit flipped where `flip`.
#[inline(always)]
fn flip_sign(x: f64, flip: bool) -> f64 {
    f64::from_bits(x.to_bits() ^ (u64::from(flip) << 63))
}

/// a + b = s + e exactly (Knuth's two-sum, any magnitudes).
#[inline(always)]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// a·b = p + e exactly (Dekker's product through Veltkamp's split: no FMA).
#[inline(always)]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    const SPLIT: f64 = 134_217_729.0; // 2²⁷ + 1
    let split = |v: f64| {
        let t = SPLIT * v;
        let hi = t - (t - v);
        (hi, v - hi)
    };
    let p = a * b;
    let ((ah, al), (bh, bl)) = (split(a), split(b));
    (p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
}

/// For 0 ≤ ax < [`TRIG_LIMIT`]: ax − n·π/2 as y0 + y1 (|y0| ≲ π/4, |y1| ≤ ulp(y0)/2),
/// and n mod 4.
#[inline(always)]
fn reduce(ax: f64) -> (f64, f64, u64) {
    let shifted = ax * TWO_OVER_PI + ROUNDER;
    let n = shifted - ROUNDER;
    let quadrant = shifted.to_bits() & 3;
    // Exact: n·PIO2_1 has at most 53 bits and lies within a factor 2 of ax (Sterbenz).
    let a = ax - n * PIO2_1;
    let (s, e) = two_sum(a, -(n * PIO2_2));
    let (s, e2) = two_sum(s, -(n * PIO2_3));
    let tail = (e + e2) - n * PIO2_3T;
    let y0 = s + tail;
    (y0, (s - y0) + tail, quadrant)
}

/// sin(y0 + y1) on |y0| ≲ π/4 (fdlibm's kernel with the tail's correction).
#[inline(always)]
fn sin_kernel(x: f64, y: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
    let v = z * x;
    x - ((z * (0.5 * y - v * r) - y) - v * S1)
}

/// cos(y0 + y1) on |y0| ≲ π/4 (fdlibm's kernel: 1 − z/2 split so its rounding is kept).
#[inline(always)]
fn cos_kernel(x: f64, y: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + (z * r - x * y))
}

/// sin(|x|) for quadrant offset 0, cos(|x|) for 1: the kernel the quadrant picks,
/// branch-free (both kernels run), for |x| < [`TRIG_LIMIT`].
#[inline(always)]
fn sin_cos_lane(ax: f64, offset: u64) -> f64 {
    let (y0, y1, n) = reduce(ax);
    let q = n.wrapping_add(offset);
    let r = blend(q & 1 != 0, cos_kernel(y0, y1), sin_kernel(y0, y1));
    flip_sign(r, q & 2 != 0)
}

/// The same value as [`sin_cos_lane`], running only the kernel the quadrant picks, and
/// no reduction below π/4 (where [`reduce`] gives (ax, 0, 0) exactly: n = 0).
#[inline(always)]
fn sin_cos_point(ax: f64, offset: u64) -> f64 {
    let (y0, y1, n) = if ax < 0.785 { (ax, 0.0, 0) } else { reduce(ax) };
    let q = n.wrapping_add(offset);
    let r = if q & 1 != 0 {
        cos_kernel(y0, y1)
    } else {
        sin_kernel(y0, y1)
    };
    flip_sign(r, q & 2 != 0)
}

/// `SIN(x)`, x in radians: under 1 ulp for |x| < 2²⁰, libm beyond (see the module).
/// Odd by construction: sin(−x) = −sin(x), bit for bit, and sin(−0) = −0.
pub fn sin(x: f64) -> f64 {
    if in_range(x) {
        flip_sign(sin_cos_point(x.abs(), 0), x.is_sign_negative())
    } else {
        x.sin()
    }
}

/// `COS(x)`, x in radians: under 1 ulp for |x| < 2²⁰, libm beyond. Even: cos(−x) = cos(x).
pub fn cos(x: f64) -> f64 {
    if in_range(x) {
        sin_cos_point(x.abs(), 1)
    } else {
        x.cos()
    }
}

/// The angle of (x, y), `y.atan2(x)`'s meaning, for the fast path's arguments (see
/// [`atan2_in_range`]); the same operations at every call, no branch.
#[inline(always)]
fn atan2_lane(y: f64, x: f64) -> f64 {
    // The choices below are a minimum, a maximum and products with a 0-or-1 made from a
    // comparison, rather than selects between computed values: x86-64 has no scalar
    // select of doubles, so in the scalar call most selects become branches.
    let one_if = |b: bool| f64::from(u8::from(b));
    let (ax, ay) = (x.abs(), y.abs());
    let (num, den) = (ax.min(ay), ax.max(ay));
    // atan(num/den) = atan(c) + atan(t), t = (num − c·den)/(den + c·num), |t| ≤ 7/16,
    // c by fdlibm's breakpoints on num/den (compared without dividing). The numerator is
    // exact (c·den is, and Sterbenz), the denominator a double-double.
    let (above_half, above_one) = (one_if(num >= 0.4375 * den), one_if(num >= 0.6875 * den));
    let c = 0.5 * (above_half + above_one);
    let n = num - c * den;
    let (d_hi, d_lo) = two_sum(den, c * num);
    let t = n / d_hi;
    // t's rounding error: n − t·(d_hi + d_lo), Dekker's product exact, to first order.
    let (ph, pl) = two_prod(t, d_hi);
    let residual = ((n - ph) - pl) - t * d_lo;
    let z = t * t;
    let w = z * z;
    let s1 = z * (AT[0] + w * (AT[2] + w * (AT[4] + w * (AT[6] + w * (AT[8] + w * AT[10])))));
    let s2 = w * (AT[1] + w * (AT[3] + w * (AT[5] + w * (AT[7] + w * AT[9]))));
    // atan(t_exact) = t − m, with t's error over 1 + t² in m (one division: the term is
    // below t's last bit, so its own rounding is moot).
    let m = t * (s1 + s2) - residual / (d_hi * (1.0 + z));
    // θ = K + σ·atan(num/den): K = π/2 when swapped (|y| > |x|), π for x < 0 unswapped;
    // σ = −1 when exactly one of the two holds. S = K + σ·atan(c) as a double-double
    // (π = 2·π/2 exactly, high and low parts alike).
    let swap = ay > ax;
    let negative_x = x.is_sign_negative();
    let sigma = 1.0 - 2.0 * one_if(swap ^ negative_x);
    let k = one_if(swap) + 2.0 * one_if(!swap & negative_x);
    let half_only = above_half - above_one;
    let a_hi = ATAN_HALF.0 * half_only + ATAN_ONE.0 * above_one;
    let a_lo = ATAN_HALF.1 * half_only + ATAN_ONE.1 * above_one;
    let (s_hi, e) = two_sum(PIO2.0 * k, sigma * a_hi);
    let s_lo = e + (PIO2.1 * k + sigma * a_lo);
    let theta = s_hi - ((sigma * m - s_lo) - sigma * t);
    flip_sign(theta, y.is_sign_negative())
}

/// True where [`atan2_lane`] gives ATAN2: both arguments finite, non-zero and of
/// magnitude in (2⁻⁵⁰⁰, 2⁵⁰⁰) (false for NaN).
#[inline(always)]
fn atan2_in_range(y: f64, x: f64) -> bool {
    let inside = |v: f64| v.abs() > ATAN2_LOW && v.abs() < ATAN2_HIGH;
    inside(x) & inside(y)
}

/// `ATAN2(y, x)`: the angle of the point (x, y) in (−π, π], under 1 ulp on the fast
/// path's arguments, libm's `atan2` elsewhere (zeros, infinities, NaN, extremes).
pub fn atan2(y: f64, x: f64) -> f64 {
    if atan2_in_range(y, x) {
        atan2_lane(y, x)
    } else {
        y.atan2(x)
    }
}

/// `out[i] = sin(x[i])` over a block: the fast path at every lane (a loop the compiler
/// vectorises), then libm at the rare lanes outside it. The bits are [`sin`]'s.
#[inline(always)]
pub fn sin_lanes<const N: usize>(out: &mut [f64; N], x: &[f64; N]) {
    sin_cos_lanes(out, x, 0, sin)
}

/// `out[i] = cos(x[i])` over a block; the bits are [`cos`]'s.
#[inline(always)]
pub fn cos_lanes<const N: usize>(out: &mut [f64; N], x: &[f64; N]) {
    sin_cos_lanes(out, x, 1, cos)
}

/// The block loop of sine (`offset` 0: odd, so the sign of x is put back) or cosine
/// (`offset` 1), `scalar` being the same function point by point.
#[inline(always)]
fn sin_cos_lanes<const N: usize>(
    out: &mut [f64; N],
    x: &[f64; N],
    offset: u64,
    scalar: fn(f64) -> f64,
) {
    let odd = offset == 0;
    let mut outside = false;
    for (o, &v) in out.iter_mut().zip(x) {
        outside |= !in_range(v);
        *o = flip_sign(sin_cos_lane(v.abs(), offset), odd & v.is_sign_negative());
    }
    if outside {
        patch(out, x, scalar);
    }
}

/// `out[i] = atan2(y[i], x[i])` over a block; the bits are [`atan2`]'s.
#[inline(always)]
pub fn atan2_lanes<const N: usize>(out: &mut [f64; N], y: &[f64; N], x: &[f64; N]) {
    let mut outside = false;
    for ((o, &y), &x) in out.iter_mut().zip(y).zip(x) {
        outside |= !atan2_in_range(y, x);
        *o = atan2_lane(y, x);
    }
    if outside {
        for ((o, &y), &x) in out.iter_mut().zip(y).zip(x) {
            if !atan2_in_range(y, x) {
                *o = atan2(y, x);
            }
        }
    }
}

/// Recomputes the lanes outside the Cody–Waite range with the scalar function (libm).
#[cold]
fn patch(out: &mut [f64], x: &[f64], f: fn(f64) -> f64) {
    for (o, &v) in out.iter_mut().zip(x) {
        if !in_range(v) {
            *o = f(v);
        }
    }
}

#[cfg(test)]
mod tests;
