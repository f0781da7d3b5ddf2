//! Tests of the C ABI layer: every wrapper equals its Rust function bit for bit, called
//! directly and through the address and signature in [`symbols`]; null pointers and bad
//! counts give NaN; the table covers every function exactly once.

use std::collections::BTreeSet;
use std::mem::transmute;

use super::*;
use crate::contact::*;
use crate::math::*;
use crate::series::*;
use crate::spline::*;
use crate::steps::*;

/// A Rust gradient on fixed arguments, partials as a vector.
type GradFn = fn() -> (f64, Vec<f64>);

/// One scalar function evaluated on one argument set, four ways.
struct Case {
    name: &'static str,
    args: &'static [f64],
    /// The Rust function.
    rust: fn() -> f64,
    /// The `extern "C"` wrapper, called directly.
    wrapper: fn() -> f64,
    /// The Rust gradient, partials as a vector (empty for functions without one).
    rust_grad: Option<GradFn>,
}

/// `cases!(rust_fn / rust_grad, wrapper; [args]...;)`: one [`Case`] per argument set.
macro_rules! cases {
    ($($f:ident / $g:ident, $w:ident; $([$($a:expr),+]),+;)*) => {{
        vec![$($(
            Case {
                name: stringify!($w),
                args: &[$($a),+],
                rust: || $f($($a),+),
                wrapper: || $w($($a),+),
                rust_grad: Some(|| {
                    let (value, partials) = $g($($a),+);
                    (value, partials.to_vec())
                }),
            },
        )+)*]
    }};
}

/// `plain_cases!(rust_fn, wrapper; [args]...;)` for functions without a gradient.
macro_rules! plain_cases {
    ($($f:ident, $w:ident; $([$($a:expr),+]),+;)*) => {{
        vec![$($(
            Case {
                name: stringify!($w),
                args: &[$($a),+],
                rust: || $f($($a),+),
                wrapper: || $w($($a),+),
                rust_grad: None,
            },
        )+)*]
    }};
}

fn scalar_cases() -> Vec<Case> {
    let mut all = cases! {
        abs / abs_grad, mbfx_abs; [-1.5], [0.0], [f64::NAN];
        acos / acos_grad, mbfx_acos; [0.3], [2.0];
        asin / asin_grad, mbfx_asin; [-0.4];
        atan / atan_grad, mbfx_atan; [7.0];
        atan2 / atan2_grad, mbfx_atan2; [1.0, -1.0], [0.0, -1.0];
        cos / cos_grad, mbfx_cos; [0.7];
        sin / sin_grad, mbfx_sin; [0.7], [f64::INFINITY];
        tan / tan_grad, mbfx_tan; [0.7];
        cosh / cosh_grad, mbfx_cosh; [0.7];
        sinh / sinh_grad, mbfx_sinh; [0.7];
        tanh / tanh_grad, mbfx_tanh; [0.7];
        exp / exp_grad, mbfx_exp; [0.7];
        log / log_grad, mbfx_log; [0.7], [0.0];
        log10 / log10_grad, mbfx_log10; [42.0];
        sqrt / sqrt_grad, mbfx_sqrt; [2.0];
        aint / aint_grad, mbfx_aint; [-6.5];
        anint / anint_grad, mbfx_anint; [-2.5];
        amod / amod_grad, mbfx_mod; [-7.0, 3.0], [0.5, 0.1], [1.0, 0.0];
        sign / sign_grad, mbfx_sign; [-9.6, 0.0], [9.6, -1.0];
        dim / dim_grad, mbfx_dim; [20.0, 5.0], [3.0, 5.0];
        max / max_grad, mbfx_max; [0.0, -3.0], [f64::NAN, 1.0];
        min / min_grad, mbfx_min; [0.0, -3.0], [1.0, f64::NAN];
        pow / pow_grad, mbfx_pow; [-2.0, 3.0], [2.0, 0.5];
        pow_libm / pow_grad, mbfx_pow_libm; [2.0, 0.5], [0.25, 1.5];
        step / step_grad, mbfx_step; [0.25, 0.0, 0.0, 1.0, 1.0], [0.3, 1.0, 0.0, 1.0, 2.0];
        step5 / step5_grad, mbfx_step5; [0.25, 0.0, 0.0, 1.0, 1.0];
        havsin / havsin_grad, mbfx_havsin; [0.25, 0.0, 0.0, 1.0, 1.0];
        impact / impact_grad, mbfx_impact;
            [0.95, -2.0, 1.0, 1e5, 1.5, 100.0, 0.1], [0.95, 30.0, 1.0, 1e5, 1.5, 100.0, 0.1];
        bistop / bistop_grad, mbfx_bistop;
            [2.05, 1.0, -2.0, 2.0, 1000.0, 2.0, 10.0, 0.1],
            [-2.05, -1.0, -2.0, 2.0, 1000.0, 2.0, 10.0, 0.1];
        shf / shf_grad, mbfx_shf; [1.0, 0.0, 2.0, core::f64::consts::FRAC_PI_2, 0.0, 3.0];
        sweep / sweep_grad, mbfx_sweep; [1.25, 2.0, 1.0, 1.0, 3.0, 3.0, 0.5];
    };
    all.extend(plain_cases! {
        step_d2, mbfx_step_d2; [0.25, 0.0, 0.0, 1.0, 1.0];
        step5_d2, mbfx_step5_d2; [0.25, 0.0, 0.0, 1.0, 1.0];
        havsin_d2, mbfx_havsin_d2; [0.25, 0.0, 0.0, 1.0, 1.0];
    });
    all
}

/// Calls an all-`f64` symbol through its address, by the arity its table entry gives.
///
/// # Safety
/// `s.addr` must be an `extern "C"` function taking `args.len()` `f64` and returning `f64`.
unsafe fn call_scalar(s: &Symbol, args: &[f64]) -> f64 {
    type F1 = extern "C" fn(f64) -> f64;
    type F2 = extern "C" fn(f64, f64) -> f64;
    type F5 = extern "C" fn(f64, f64, f64, f64, f64) -> f64;
    type F6 = extern "C" fn(f64, f64, f64, f64, f64, f64) -> f64;
    type F7 = extern "C" fn(f64, f64, f64, f64, f64, f64, f64) -> f64;
    type F8 = extern "C" fn(f64, f64, f64, f64, f64, f64, f64, f64) -> f64;
    let a = args;
    // SAFETY: the caller guarantees the signature; function pointers and `*const u8` have
    // the same size.
    unsafe {
        match a.len() {
            1 => transmute::<*const u8, F1>(s.addr)(a[0]),
            2 => transmute::<*const u8, F2>(s.addr)(a[0], a[1]),
            5 => transmute::<*const u8, F5>(s.addr)(a[0], a[1], a[2], a[3], a[4]),
            6 => transmute::<*const u8, F6>(s.addr)(a[0], a[1], a[2], a[3], a[4], a[5]),
            7 => transmute::<*const u8, F7>(s.addr)(a[0], a[1], a[2], a[3], a[4], a[5], a[6]),
            8 => transmute::<*const u8, F8>(s.addr)(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]),
            n => panic!("no test caller for arity {n}"),
        }
    }
}

/// Calls a gradient symbol (`f64` arguments then `out`) through its address.
///
/// # Safety
/// `s.addr` must be an `extern "C"` function taking `args.len()` `f64` and a `*mut f64`,
/// writing `args.len()` values; `out` must have room for them.
unsafe fn call_grad(s: &Symbol, args: &[f64], out: *mut f64) -> f64 {
    type G1 = unsafe extern "C" fn(f64, *mut f64) -> f64;
    type G2 = unsafe extern "C" fn(f64, f64, *mut f64) -> f64;
    type G5 = unsafe extern "C" fn(f64, f64, f64, f64, f64, *mut f64) -> f64;
    type G6 = unsafe extern "C" fn(f64, f64, f64, f64, f64, f64, *mut f64) -> f64;
    type G7 = unsafe extern "C" fn(f64, f64, f64, f64, f64, f64, f64, *mut f64) -> f64;
    type G8 = unsafe extern "C" fn(f64, f64, f64, f64, f64, f64, f64, f64, *mut f64) -> f64;
    let a = args;
    let p = s.addr;
    // SAFETY: the caller guarantees the signature and the room behind `out`.
    unsafe {
        match a.len() {
            1 => transmute::<*const u8, G1>(p)(a[0], out),
            2 => transmute::<*const u8, G2>(p)(a[0], a[1], out),
            5 => transmute::<*const u8, G5>(p)(a[0], a[1], a[2], a[3], a[4], out),
            6 => transmute::<*const u8, G6>(p)(a[0], a[1], a[2], a[3], a[4], a[5], out),
            7 => transmute::<*const u8, G7>(p)(a[0], a[1], a[2], a[3], a[4], a[5], a[6], out),
            8 => transmute::<*const u8, G8>(p)(a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7], out),
            n => panic!("no test caller for arity {n}"),
        }
    }
}

fn symbol(name: &str) -> Symbol {
    *symbols()
        .iter()
        .find(|s| s.name == name)
        .unwrap_or_else(|| panic!("no symbol {name}"))
}

/// Bit patterns, with every NaN mapped to one pattern: NaN payloads and signs are not
/// reproducible (LLVM folds `1.0 % 0.0` to +NaN at compile time, x86 `fmod` gives −NaN
/// at run time), so "bit for bit" means equal bits or both NaN.
fn bits(v: &[f64]) -> Vec<u64> {
    v.iter()
        .map(|x| {
            if x.is_nan() {
                f64::NAN.to_bits()
            } else {
                x.to_bits()
            }
        })
        .collect()
}

fn same(a: f64, b: f64) -> bool {
    bits(&[a]) == bits(&[b])
}

#[test]
fn scalar_wrappers_equal_the_rust_functions_bit_for_bit() {
    for case in scalar_cases() {
        let want = (case.rust)();
        assert!(
            same((case.wrapper)(), want),
            "{} {:?}",
            case.name,
            case.args
        );
        let s = symbol(case.name);
        assert_eq!(s.params, vec![Param::F64; case.args.len()], "{}", case.name);
        assert_eq!(s.ret, Ret::F64);
        // SAFETY: the table says this symbol takes `args.len()` f64 (checked above).
        let via_table = unsafe { call_scalar(&s, case.args) };
        assert!(same(via_table, want), "{} via table", case.name);
    }
}

#[test]
fn grad_wrappers_equal_the_rust_gradients_bit_for_bit() {
    for case in scalar_cases() {
        let Some(rust_grad) = case.rust_grad else {
            continue;
        };
        let (value, partials) = rust_grad();
        let n = case.args.len();
        let name = format!("{}_grad", case.name);
        let s = symbol(&name);
        let mut params = vec![Param::F64; n];
        params.push(Param::Ptr);
        assert_eq!(s.params, params, "{name}");
        // One extra slot checks that nothing is written past the partials.
        let mut out = vec![-123.0; n + 1];
        // SAFETY: signature checked above; `out` has room for n partials.
        let got = unsafe { call_grad(&s, case.args, out.as_mut_ptr()) };
        assert!(same(got, value), "{name} {:?}", case.args);
        assert_eq!(bits(&out[..n]), bits(&partials), "{name} {:?}", case.args);
        assert_eq!(out[n], -123.0, "{name} wrote past its partials");
        // SAFETY: signature checked above; every gradient wrapper accepts a null `out`
        // (it writes nothing and returns NaN, `write_partials`).
        let without_out = unsafe { call_grad(&s, case.args, ptr::null_mut()) };
        assert!(without_out.is_nan(), "{name}");
    }
}

#[test]
fn series_wrappers_equal_the_rust_functions() {
    let a = [1.0, 2.0, 3.0, -0.5];
    // SAFETY: `a` is valid for 3 and 4 reads.
    unsafe {
        assert_eq!(mbfx_poly(3.0, 1.0, a.as_ptr(), 3), 17.0);
        assert_eq!(mbfx_poly(0.3, 0.1, a.as_ptr(), 4), poly(0.3, 0.1, &a));
        assert_eq!(mbfx_cheby(0.5, 0.0, a.as_ptr(), 3), 0.5);
        assert_eq!(mbfx_cheby(0.3, 0.1, a.as_ptr(), 4), cheby(0.3, 0.1, &a));
        assert_eq!(
            mbfx_forcos(0.3, 0.1, 2.0, a.as_ptr(), 4),
            forcos(0.3, 0.1, 2.0, &a)
        );
        assert_eq!(
            mbfx_forsin(0.3, 0.1, 2.0, a.as_ptr(), 4),
            forsin(0.3, 0.1, 2.0, &a)
        );
    }
}

#[test]
fn series_grad_wrappers_lay_out_scalars_then_coefficients() {
    let a = [1.0, 2.0, 3.0, -0.5];
    let mut da = [0.0; 4];
    let mut out = [-123.0; 8];
    let (v, dx, dx0) = poly_grad(0.3, 0.1, &a, &mut da);
    // SAFETY: `a` holds 4 values and `out` room for 2 + 4.
    let got = unsafe { mbfx_poly_grad(0.3, 0.1, a.as_ptr(), 4, out.as_mut_ptr()) };
    assert_eq!(
        (got, &out[..6]),
        (v, &[dx, dx0, da[0], da[1], da[2], da[3]][..])
    );
    assert_eq!(out[6], -123.0);
    let (v, dx, dx0) = cheby_grad(0.3, 0.1, &a, &mut da);
    // SAFETY: as above.
    let got = unsafe { mbfx_cheby_grad(0.3, 0.1, a.as_ptr(), 4, out.as_mut_ptr()) };
    assert_eq!(
        (got, &out[..6]),
        (v, &[dx, dx0, da[0], da[1], da[2], da[3]][..])
    );
    let (v, dx, dx0, dw) = forcos_grad(0.3, 0.1, 2.0, &a, &mut da);
    out = [-123.0; 8];
    // SAFETY: `a` holds 4 values and `out` room for 3 + 4.
    let got = unsafe { mbfx_forcos_grad(0.3, 0.1, 2.0, a.as_ptr(), 4, out.as_mut_ptr()) };
    assert_eq!(
        (got, &out[..7]),
        (v, &[dx, dx0, dw, da[0], da[1], da[2], da[3]][..])
    );
    assert_eq!(out[7], -123.0);
    let (v, dx, dx0, dw) = forsin_grad(0.3, 0.1, 2.0, &a, &mut da);
    // SAFETY: as above.
    let got = unsafe { mbfx_forsin_grad(0.3, 0.1, 2.0, a.as_ptr(), 4, out.as_mut_ptr()) };
    assert_eq!(
        (got, &out[..7]),
        (v, &[dx, dx0, dw, da[0], da[1], da[2], da[3]][..])
    );
}

#[test]
fn null_pointers_and_bad_counts_give_nan() {
    let a = [1.0; 32];
    let mut out = [-123.0; 40];
    let null = ptr::null::<f64>();
    // SAFETY: every pointer is null or valid for the counts used (a holds 32 values,
    // out has room for 3 + 32).
    unsafe {
        assert!(mbfx_poly(1.0, 0.0, null, 3).is_nan());
        assert!(mbfx_poly(1.0, 0.0, a.as_ptr(), 0).is_nan());
        assert!(mbfx_poly(1.0, 0.0, a.as_ptr(), 32).is_nan());
        assert_eq!(mbfx_poly(1.0, 0.0, a.as_ptr(), 31), 31.0);
        assert!(mbfx_cheby(1.0, 0.0, null, 3).is_nan());
        assert!(mbfx_forcos(1.0, 0.0, 1.0, null, 3).is_nan());
        assert!(mbfx_forsin(1.0, 0.0, 1.0, a.as_ptr(), 32).is_nan());
        assert!(mbfx_poly_grad(1.0, 0.0, null, 3, out.as_mut_ptr()).is_nan());
        assert!(mbfx_cheby_grad(1.0, 0.0, a.as_ptr(), 3, ptr::null_mut()).is_nan());
        assert!(mbfx_forcos_grad(1.0, 0.0, 1.0, a.as_ptr(), 32, out.as_mut_ptr()).is_nan());
        assert!(mbfx_forsin_grad(1.0, 0.0, 1.0, a.as_ptr(), 0, out.as_mut_ptr()).is_nan());
        assert!(
            out.iter().all(|&v| v == -123.0),
            "nothing is written on failure"
        );
        assert!(mbfx_akispl(1.0, 0.0, ptr::null(), 0).is_nan());
        assert!(mbfx_cubspl(1.0, 0.0, ptr::null(), 0).is_nan());
        assert!(mbfx_akispl_grad(1.0, 0.0, ptr::null(), out.as_mut_ptr()).is_nan());
        assert!(mbfx_step_grad(0.5, 0.0, 0.0, 1.0, 1.0, ptr::null_mut()).is_nan());
    }
}

#[test]
fn spline_wrappers_equal_the_rust_functions() {
    let xs: Vec<f64> = (-4..=4).map(f64::from).collect();
    let ys = vec![-3.6, -2.5, -1.2, -0.4, 0.0, 0.4, 1.2, 2.5, 3.6];
    let s = Spline::new(xs, vec![0.0], ys).expect("valid spline");
    let mut out = [0.0; 2];
    for x in [-5.0, -0.5, 1.5, 3.9] {
        for iord in [0, 1, 2, 3] {
            // SAFETY: `s` is a live Spline.
            let (a, c) = unsafe { (mbfx_akispl(x, 0.0, &s, iord), mbfx_cubspl(x, 0.0, &s, iord)) };
            assert!(same(a, akispl(x, 0.0, &s, iord)));
            assert!(same(c, cubspl(x, 0.0, &s, iord)));
        }
        for (wrapper, rust) in [
            (
                mbfx_akispl_grad as unsafe extern "C" fn(f64, f64, *const Spline, *mut f64) -> f64,
                akispl_grad as fn(f64, f64, &Spline) -> (f64, f64, f64),
            ),
            (mbfx_cubspl_grad, cubspl_grad),
        ] {
            // SAFETY: `s` is a live Spline and `out` has room for 2.
            let v = unsafe { wrapper(x, 0.0, &s, out.as_mut_ptr()) };
            assert_eq!((v, out[0], out[1]), rust(x, 0.0, &s));
        }
    }
}

#[test]
fn table_lists_every_function_once_with_its_companions() {
    let table = symbols();
    let names: BTreeSet<&str> = table.iter().map(|s| s.name).collect();
    assert_eq!(names.len(), table.len(), "duplicate names");
    assert!(table
        .iter()
        .all(|s| !s.addr.is_null() && s.name.starts_with("mbfx_")));
    // Spec §4 and §5: every Adams function has a value symbol and a gradient symbol.
    let adams = [
        "abs", "acos", "asin", "atan", "atan2", "cos", "sin", "tan", "cosh", "sinh", "tanh", "exp",
        "log", "log10", "sqrt", "aint", "anint", "mod", "sign", "dim", "max", "min", "pow",
        "pow_libm", "step", "step5", "havsin", "impact", "bistop", "poly", "cheby", "forcos",
        "forsin", "shf", "sweep", "akispl", "cubspl",
    ];
    let mut expected = BTreeSet::new();
    for f in adams {
        expected.insert(format!("mbfx_{f}"));
        expected.insert(format!("mbfx_{f}_grad"));
    }
    for f in ["step", "step5", "havsin"] {
        expected.insert(format!("mbfx_{f}_d2"));
    }
    let got: BTreeSet<String> = names.iter().map(|s| s.to_string()).collect();
    assert_eq!(got, expected);
    // Every all-f64 symbol is exercised by `scalar_cases` (or its `_grad` by the case).
    let cased: BTreeSet<&str> = scalar_cases().iter().map(|c| c.name).collect();
    for s in &table {
        let base = s.name.strip_suffix("_grad").unwrap_or(s.name);
        let pointer_free = s
            .params
            .iter()
            .all(|p| *p == Param::F64 || *p == Param::Ptr)
            && !s.params[..s.params.len() - 1].contains(&Param::Ptr);
        if pointer_free {
            assert!(cased.contains(base), "{} has no wrapper test", s.name);
        }
    }
}

#[test]
fn pointer_symbols_work_through_their_table_signatures() {
    type Series = unsafe extern "C" fn(f64, f64, *const f64, usize) -> f64;
    type Fourier = unsafe extern "C" fn(f64, f64, f64, *const f64, usize) -> f64;
    type Interp = unsafe extern "C" fn(f64, f64, *const Spline, i32) -> f64;
    use Param::{Ptr, Usize, F64, I32};
    let a = [1.0, 2.0, 3.0];
    let xs: Vec<f64> = (0..=5).map(f64::from).collect();
    let ys: Vec<f64> = xs.iter().map(|x| x * x).collect();
    let spline = Spline::new(xs, vec![0.0], ys).expect("valid spline");
    for name in ["mbfx_poly", "mbfx_cheby"] {
        let s = symbol(name);
        assert_eq!(s.params, [F64, F64, Ptr, Usize]);
        // SAFETY: the table gives this signature; `a` holds 3 values.
        let got = unsafe { transmute::<*const u8, Series>(s.addr)(0.3, 0.1, a.as_ptr(), 3) };
        let want = if name == "mbfx_poly" {
            poly(0.3, 0.1, &a)
        } else {
            cheby(0.3, 0.1, &a)
        };
        assert_eq!(got, want, "{name}");
    }
    for name in ["mbfx_forcos", "mbfx_forsin"] {
        let s = symbol(name);
        assert_eq!(s.params, [F64, F64, F64, Ptr, Usize]);
        // SAFETY: the table gives this signature; `a` holds 3 values.
        let got = unsafe { transmute::<*const u8, Fourier>(s.addr)(0.3, 0.1, 2.0, a.as_ptr(), 3) };
        let want = if name == "mbfx_forcos" {
            forcos(0.3, 0.1, 2.0, &a)
        } else {
            forsin(0.3, 0.1, 2.0, &a)
        };
        assert_eq!(got, want, "{name}");
    }
    for name in ["mbfx_akispl", "mbfx_cubspl"] {
        let s = symbol(name);
        assert_eq!(s.params, [F64, F64, Ptr, I32]);
        // SAFETY: the table gives this signature; `spline` is live.
        let got = unsafe { transmute::<*const u8, Interp>(s.addr)(2.5, 0.0, &spline, 1) };
        let want = if name == "mbfx_akispl" {
            akispl(2.5, 0.0, &spline, 1)
        } else {
            cubspl(2.5, 0.0, &spline, 1)
        };
        assert_eq!(got, want, "{name}");
    }
}

/// The symbols that point at libm directly give the bits of the Rust functions they
/// stand for, on edge values and a spread of ordinary ones.
#[test]
fn table_addresses_give_the_rust_functions_bits() {
    type F1 = extern "C" fn(f64) -> f64;
    type F2 = extern "C" fn(f64, f64) -> f64;
    let table = symbols();
    let addr = |name: &str| table.iter().find(|s| s.name == name).expect("listed").addr;
    let mut xs = vec![0.0, -0.0, 5e-324, -1e-310, 1e300, -1e300, f64::INFINITY];
    xs.extend([
        f64::NEG_INFINITY,
        f64::NAN,
        0.5,
        -0.5,
        1.0,
        -1.0,
        0.9999,
        710.0,
    ]);
    xs.extend((0..200).map(|i| (f64::from(i) - 100.0) * 0.173));
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
    type Named1 = (&'static str, fn(f64) -> f64);
    type Named2 = (&'static str, fn(f64, f64) -> f64);
    let unary: [Named1; 13] = [
        ("mbfx_acos", acos),
        ("mbfx_asin", asin),
        ("mbfx_atan", atan),
        ("mbfx_cos", cos),
        ("mbfx_sin", sin),
        ("mbfx_tan", tan),
        ("mbfx_cosh", cosh),
        ("mbfx_sinh", sinh),
        ("mbfx_tanh", tanh),
        ("mbfx_exp", exp),
        ("mbfx_log", log),
        ("mbfx_log10", log10),
        ("mbfx_sqrt", sqrt),
    ];
    for (name, rust) in unary {
        // SAFETY: the table lists these symbols with one f64 parameter and an f64 result.
        let f = unsafe { core::mem::transmute::<*const u8, F1>(addr(name)) };
        for &x in &xs {
            assert!(same(f(x), rust(x)), "{name}({x:e})");
        }
    }
    let binary: [Named2; 3] = [
        ("mbfx_atan2", atan2),
        ("mbfx_pow", pow),
        ("mbfx_pow_libm", pow_libm),
    ];
    for (name, rust) in binary {
        // SAFETY: the table lists these symbols with two f64 parameters and an f64 result.
        let f = unsafe { core::mem::transmute::<*const u8, F2>(addr(name)) };
        for &a in &xs {
            for &b in xs.iter().step_by(7) {
                assert!(same(f(a, b), rust(a, b)), "{name}({a:e}, {b:e})");
            }
        }
    }
}
