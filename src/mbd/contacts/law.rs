//! The laws of a contact incident, as functions of its penetration g (≥ 0) and its rate
//! ġ (> 0: deepening) and of the slip speed: the normal force with its partials, the
//! unclamped force the clamp switch watches, and Adams' velocity-dependent friction
//! coefficient.

use crate::model::contact::{Friction, NormalLaw};
use mbfx_runtime::{impact_grad, step, step_grad};

/// Half-width of the POISSON law's blend between its loading and unloading branches, in
/// model velocity units: the factor goes from ε² at ġ = −V to 1 at ġ = +V.
pub const POISSON_BLEND: f64 = 1e-3;

/// A normal force and its partials ∂/∂g and ∂/∂ġ (all zero where the clamp holds it at 0).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Normal {
    /// The force, ≥ 0, pushing I away from J along the incident's normal.
    pub force: f64,
    /// ∂force/∂g.
    pub d_depth: f64,
    /// ∂force/∂ġ.
    pub d_rate: f64,
}

/// The normal force of `law` at penetration `g` > 0 and rate `gd`.
///
/// IMPACT is the runtime's IMPACT function with x = −g, ẋ = −ġ and x1 = 0:
/// k·g^e + STEP(g, 0, 0, DMAX, C)·ġ, clamped at zero. POISSON is a penalty stiffness p
/// on loading and ε²·p on unloading (blended over ±[`POISSON_BLEND`]): a body meeting it
/// leaves with ε times the speed it came with (docs/contact.md).
pub fn normal(law: &NormalLaw, g: f64, gd: f64) -> Normal {
    match *law {
        NormalLaw::Impact {
            stiffness,
            damping,
            dmax,
            exponent,
        } => {
            let (f, d) = impact_grad(-g, -gd, 0.0, stiffness, exponent, damping, dmax);
            if f.is_nan() || f <= 0.0 {
                return Normal::default();
            }
            Normal {
                force: f,
                d_depth: -d[0],
                d_rate: -d[1],
            }
        }
        NormalLaw::Poisson {
            penalty,
            restitution,
        } => {
            let low = restitution * restitution;
            let (s, ds) = step_grad(gd, -POISSON_BLEND, low, POISSON_BLEND, 1.0);
            Normal {
                force: penalty * g * s,
                d_depth: penalty * s,
                d_rate: penalty * g * ds[0],
            }
        }
    }
}

/// The normal force of `law` before its clamp (IMPACT: k·g^e + STEP(…)·ġ, which the
/// clamp switch watches change sign); None where the law has no clamp (POISSON never
/// pulls).
pub fn unclamped(law: &NormalLaw, g: f64, gd: f64) -> Option<f64> {
    match *law {
        NormalLaw::Impact {
            stiffness,
            damping,
            dmax,
            exponent,
        } => Some(stiffness * g.powf(exponent) + step(g, 0.0, 0.0, dmax, damping) * gd),
        NormalLaw::Poisson { .. } => None,
    }
}

/// Adams' friction coefficient at slip speed `s` ≥ 0 and its derivative dμ/ds: from 0 at
/// rest up to MU_STATIC at the stiction transition velocity vs (the STEP Adams writes as
/// STEP(v, −vs, −μs, vs, μs)), down to MU_DYNAMIC at the friction transition velocity
/// vd, MU_DYNAMIC beyond.
pub fn mu(f: &Friction, s: f64) -> (f64, f64) {
    let (vs, vd) = (f.stiction_velocity, f.friction_velocity);
    let (ms, md) = (f.mu_static, f.mu_dynamic);
    let (v, d) = if s >= vd {
        return (md, 0.0);
    } else if s >= vs {
        step_grad(s, vs, ms, vd, md)
    } else {
        step_grad(s, -vs, -ms, vs, ms)
    };
    (v, d[0])
}

/// μ(s)/s and its derivative: the friction force is −Fn·(μ(s)/s)·v_t, smooth through
/// s = 0 (μ is odd in the slip velocity, so μ/s is even there with slope 0).
pub fn mu_over_speed(f: &Friction, s: f64) -> (f64, f64) {
    let vs = f.stiction_velocity;
    if s < 1e-9 * vs {
        // μ'(0) of the cubic STEP across ±vs: 3/2 · μs / vs.
        return (1.5 * f.mu_static / vs, 0.0);
    }
    let (m, dm) = mu(f, s);
    (m / s, (dm * s - m) / (s * s))
}

#[cfg(test)]
mod tests {
    //! The laws against their closed forms, written out here.
    use super::*;
    use crate::model::contact::FrictionMode;

    const IMPACT: NormalLaw = NormalLaw::Impact {
        stiffness: 1e5,
        damping: 100.0,
        dmax: 0.1,
        exponent: 1.5,
    };

    fn friction() -> Friction {
        Friction {
            mode: FrictionMode::On,
            mu_static: 0.5,
            mu_dynamic: 0.3,
            stiction_velocity: 0.1,
            friction_velocity: 1.0,
        }
    }

    #[test]
    fn impact_is_the_runtime_law() {
        // Spec §5.4: IMPACT(0.95, −2, 1, 1E5, 1.5, 100, 0.1) = 1218.034 is a penetration
        // of 0.05 deepening at 2: k·g^1.5 + STEP(0.05; 0, 0, 0.1, 100)·2 = 1118.034 + 100.
        let n = normal(&IMPACT, 0.05, 2.0);
        assert!((n.force - 1218.0339887498967).abs() < 1e-9, "{n:?}");
        // ∂/∂g: 1.5·k·g^0.5 + ġ·∂STEP/∂g (the cubic's slope 1.5·C/DMAX at its middle).
        let want = 1.5 * 1e5 * 0.05f64.sqrt() + 2.0 * 1.5 * 100.0 / 0.1;
        assert!((n.d_depth - want).abs() < 1e-6, "{} {want}", n.d_depth);
        assert!((n.d_rate - 50.0).abs() < 1e-12);
        // Leaving fast: the unclamped force is negative and the clamp holds 0.
        let n = normal(&IMPACT, 0.05, -30.0);
        assert_eq!(n, Normal::default());
        let u = unclamped(&IMPACT, 0.05, -30.0).unwrap();
        assert!((u + 381.96601125010625).abs() < 1e-9, "{u}");
    }

    #[test]
    fn poisson_loads_with_p_and_unloads_with_e2_p() {
        let law = NormalLaw::Poisson {
            penalty: 1e4,
            restitution: 0.5,
        };
        assert!((normal(&law, 0.01, 1.0).force - 100.0).abs() < 1e-12);
        assert!((normal(&law, 0.01, -1.0).force - 25.0).abs() < 1e-12);
        assert!(unclamped(&law, 0.01, -1.0).is_none());
    }

    #[test]
    fn friction_coefficient_follows_adams_steps() {
        let f = friction();
        assert_eq!(mu(&f, 0.0).0, 0.0);
        assert!((mu(&f, 0.1).0 - 0.5).abs() < 1e-15);
        assert!((mu(&f, 1.0).0 - 0.3).abs() < 1e-15);
        assert!((mu(&f, 5.0).0 - 0.3).abs() < 1e-15);
        // Halfway from vs to vd: the middle of the STEP.
        assert!((mu(&f, 0.55).0 - 0.4).abs() < 1e-15);
        // μ/s at rest: the slope 3/2·μs/vs, and its derivative against a difference.
        assert!((mu_over_speed(&f, 0.0).0 - 7.5).abs() < 1e-12);
        let (s, h) = (0.3, 1e-6);
        let fd = (mu_over_speed(&f, s + h).0 - mu_over_speed(&f, s - h).0) / (2.0 * h);
        assert!((mu_over_speed(&f, s).1 - fd).abs() < 1e-6);
    }
}
