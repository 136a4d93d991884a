//! The ray-processing methods, selectable by name, and their parameters.

use boundtrace_ia_core::Real;
use core::fmt;
use core::str::FromStr;

/// A ray-processing method. Every method but `scalis-quadratic` is generic
/// over the [`Field`](boundtrace_inclusion::Field) it traces; all run in
/// both [`Mode`]s.
///
/// | name | method | source |
/// | --- | --- | --- |
/// | `sphere` | sphere tracing with the global Lipschitz bound, optional over-relaxation ω | Hart 1996; thesis §2.2.3; Keinert et al. 2014 |
/// | `segment` | segment tracing with local directional Lipschitz bounds | Galin et al. 2020; forward-inclusion paper eq. 11 |
/// | `linear-taylor`, `linear-bottom-up`, `linear-mixed` | forward linear marching | forward-inclusion paper Alg. 1, §5 |
/// | `quadratic-taylor`, `quadratic-bottom-up`, `quadratic-mixed` | forward quadratic marching | forward-inclusion paper §6 |
/// | `interval` | interval-arithmetic bisection with a fixed stack | Mitchell 1990; thesis §2.2.2 |
/// | `affine` | revised-affine-arithmetic bisection with interval pruning | Fryazinov, Pasko and Comninos 2010 |
/// | `scalis-quadratic` | SCALIS skeletons only ([`trace_scalis`](crate::scalis::trace_scalis)): argmin pre-segmentation, quadratic Bézier oracle, per-primitive ranges | thesis Part III ch. 1 Alg. 1 and 2 |
///
/// `scalis-quadratic` needs the skeleton, not a generic field: the generic
/// [`trace`](crate::trace()) answers `Status::Unsupported` for it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum Method {
    /// Sphere tracing (global Lipschitz bound).
    Sphere = 0,
    /// Segment tracing (local directional Lipschitz bounds).
    Segment = 1,
    /// Forward linear marching with Taylor bounds.
    LinearTaylor = 2,
    /// Forward linear marching with bottom-up bounds.
    LinearBottomUp = 3,
    /// Forward linear marching with the tighter of both per side.
    LinearMixed = 4,
    /// Forward quadratic marching with Taylor bounds.
    QuadraticTaylor = 5,
    /// Forward quadratic marching with bottom-up bounds.
    QuadraticBottomUp = 6,
    /// Forward quadratic marching with the tighter of both per side.
    QuadraticMixed = 7,
    /// Interval-arithmetic bisection.
    Interval = 8,
    /// Revised-affine-arithmetic bisection.
    Affine = 9,
    /// SCALIS fast tracing (thesis Part III ch. 1), through
    /// [`trace_scalis`](crate::scalis::trace_scalis) only.
    ScalisQuadratic = 10,
}

impl Method {
    /// Every method, in the order of the table above.
    pub const ALL: [Method; 11] = [
        Method::Sphere,
        Method::Segment,
        Method::LinearTaylor,
        Method::LinearBottomUp,
        Method::LinearMixed,
        Method::QuadraticTaylor,
        Method::QuadraticBottomUp,
        Method::QuadraticMixed,
        Method::Interval,
        Method::Affine,
        Method::ScalisQuadratic,
    ];

    /// The method's name (`"quadratic-taylor"`, …), as parsed by
    /// [`Method::from_name`] and [`FromStr`].
    pub const fn name(self) -> &'static str {
        match self {
            Method::Sphere => "sphere",
            Method::Segment => "segment",
            Method::LinearTaylor => "linear-taylor",
            Method::LinearBottomUp => "linear-bottom-up",
            Method::LinearMixed => "linear-mixed",
            Method::QuadraticTaylor => "quadratic-taylor",
            Method::QuadraticBottomUp => "quadratic-bottom-up",
            Method::QuadraticMixed => "quadratic-mixed",
            Method::Interval => "interval",
            Method::Affine => "affine",
            Method::ScalisQuadratic => "scalis-quadratic",
        }
    }

    /// The method with this name, if any.
    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == name)
    }

    /// The method from its `#[repr(u32)]` code (as stored in GPU constants).
    pub const fn from_code(code: u32) -> Option<Method> {
        Some(match code {
            0 => Method::Sphere,
            1 => Method::Segment,
            2 => Method::LinearTaylor,
            3 => Method::LinearBottomUp,
            4 => Method::LinearMixed,
            5 => Method::QuadraticTaylor,
            6 => Method::QuadraticBottomUp,
            7 => Method::QuadraticMixed,
            8 => Method::Interval,
            9 => Method::Affine,
            10 => Method::ScalisQuadratic,
            _ => return None,
        })
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The error of parsing a [`Method`] from an unknown name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnknownMethod;

impl fmt::Display for UnknownMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("unknown method; expected one of:")?;
        for m in Method::ALL {
            write!(f, " {}", m.name())?;
        }
        Ok(())
    }
}

impl core::error::Error for UnknownMethod {}

impl FromStr for Method {
    type Err = UnknownMethod;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Method::from_name(s).ok_or(UnknownMethod)
    }
}

/// Opaque (first root) or transparent (every root along the ray).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum Mode {
    /// Stop at the first root.
    #[default]
    Opaque = 0,
    /// Register every root along the ray once, with its side.
    Transparent = 1,
}

/// Tracing parameters (all lengths in units of the ray parameter `t`).
///
/// Build with [`Params::new`] (the defaults) and the `with_*` setters,
/// which validate; the fields are public for plain-data use (GPU constants),
/// and [`Params::validate`] checks a hand-built value.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Params<T> {
    /// ε at the root: a reported root lies within `eps` of a true root
    /// (a sign change is bracketed in an interval of length ≤ `eps`), and
    /// roots closer than `eps` to each other are reported once.
    pub eps: T,
    /// Minimal step size: a safe step shorter than this is replaced by a
    /// step of `min_step` when an interval enclosure of the field over it
    /// excludes zero (so it stays safe); `0` disables it.
    pub min_step: T,
    /// Over-relaxation factor ω ∈ [1, 2) of sphere tracing (1 = none); a
    /// failed over-relaxed step falls back to the safe step.
    pub omega: T,
    /// Growth factor `k > 1` of the next interval length (paper Alg. 1:
    /// `t_end = t + k·step`); also segment tracing's.
    pub k: T,
    /// Maximal number of steps per ray.
    pub max_steps: u32,
}

/// An invalid [`Params`] value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct InvalidParams {
    /// The parameter's name.
    pub name: &'static str,
    /// What is required of it.
    pub reason: &'static str,
}

impl fmt::Display for InvalidParams {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "invalid tracing parameter `{}`: {}",
            self.name, self.reason
        )
    }
}

impl core::error::Error for InvalidParams {}

impl<T: Real> Default for Params<T> {
    fn default() -> Self {
        Self::new()
    }
}

/// The checks of [`Params::validate`], in order: (field, reason).
const PARAM_CHECKS: [(&str, &str); 5] = [
    ("eps", "must be finite and > 0"),
    ("min_step", "must be finite and >= 0"),
    ("omega", "must be in [1, 2)"),
    ("k", "must be finite and > 1"),
    ("max_steps", "must be >= 1"),
];

impl<T: Real> Params<T> {
    /// The defaults: `eps = 1e-4`, `min_step = 0` (off), `omega = 1`,
    /// `k = 2` (the paper's), `max_steps = 10_000` (sphere tracing of
    /// density fields can need thousands of steps on grazing rays; the
    /// other methods rarely need more than 100).
    pub fn new() -> Self {
        Self {
            eps: T::from_f64(1e-4),
            min_step: T::ZERO,
            omega: T::ONE,
            k: T::TWO,
            max_steps: 10_000,
        }
    }

    /// Checks every field: `eps` finite and `> 0`, `min_step` finite and
    /// `≥ 0`, `omega ∈ [1, 2)`, `k` finite and `> 1`, `max_steps ≥ 1`.
    ///
    /// # Errors
    /// The first invalid field.
    pub fn validate(&self) -> Result<(), InvalidParams> {
        match self.first_invalid() {
            0 => Ok(()),
            i => {
                let (name, reason) = PARAM_CHECKS[i - 1];
                Err(InvalidParams { name, reason })
            }
        }
    }

    /// Whether [`validate`](Self::validate) succeeds (without building the
    /// error, whose strings a SPIR-V shader cannot hold).
    #[inline]
    pub fn is_valid(&self) -> bool {
        self.first_invalid() == 0
    }

    /// `0` when valid, else `1 +` the index of the first failed check in
    /// [`PARAM_CHECKS`].
    fn first_invalid(&self) -> usize {
        if !(self.eps.is_finite() && self.eps > T::ZERO) {
            return 1;
        }
        if !(self.min_step.is_finite() && self.min_step >= T::ZERO) {
            return 2;
        }
        if !(self.omega >= T::ONE && self.omega < T::TWO) {
            return 3;
        }
        if !(self.k.is_finite() && self.k > T::ONE) {
            return 4;
        }
        if self.max_steps == 0 {
            return 5;
        }
        0
    }

    /// With ε at the root.
    ///
    /// # Errors
    /// When `eps` is not finite and `> 0`.
    pub fn with_eps(self, eps: T) -> Result<Self, InvalidParams> {
        let p = Self { eps, ..self };
        p.validate().map(|()| p)
    }

    /// With a minimal step size (`0` = off).
    ///
    /// # Errors
    /// When `min_step` is not finite and `≥ 0`.
    pub fn with_min_step(self, min_step: T) -> Result<Self, InvalidParams> {
        let p = Self { min_step, ..self };
        p.validate().map(|()| p)
    }

    /// With the over-relaxation factor of sphere tracing.
    ///
    /// # Errors
    /// When `omega ∉ [1, 2)`.
    pub fn with_omega(self, omega: T) -> Result<Self, InvalidParams> {
        let p = Self { omega, ..self };
        p.validate().map(|()| p)
    }

    /// With the interval growth factor `k`.
    ///
    /// # Errors
    /// When `k` is not finite and `> 1`.
    pub fn with_k(self, k: T) -> Result<Self, InvalidParams> {
        let p = Self { k, ..self };
        p.validate().map(|()| p)
    }

    /// With the maximal number of steps per ray.
    ///
    /// # Errors
    /// When `max_steps == 0`.
    pub fn with_max_steps(self, max_steps: u32) -> Result<Self, InvalidParams> {
        let p = Self { max_steps, ..self };
        p.validate().map(|()| p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for m in Method::ALL {
            assert_eq!(Method::from_name(m.name()), Some(m));
            assert_eq!(m.name().parse::<Method>(), Ok(m));
            assert_eq!(Method::from_code(m as u32), Some(m));
        }
        assert_eq!("nope".parse::<Method>(), Err(UnknownMethod));
        assert_eq!(Method::from_code(11), None);
        assert_eq!(Method::from_code(10), Some(Method::ScalisQuadratic));
    }

    #[test]
    fn params_validation() {
        let p = Params::<f64>::new();
        assert!(p.validate().is_ok());
        assert!(p.with_eps(0.0).is_err());
        assert!(p.with_eps(f64::NAN).is_err());
        assert!(p.with_min_step(-1.0).is_err());
        assert!(p.with_omega(2.0).is_err());
        assert!(p.with_omega(0.5).is_err());
        assert!(p.with_k(1.0).is_err());
        assert!(p.with_max_steps(0).is_err());
        assert_eq!(p.with_omega(1.6).unwrap().omega, 1.6);
    }

    #[test]
    fn is_valid_agrees_with_validate_and_names_the_field() {
        let p = Params::<f64>::new();
        assert!(p.is_valid());
        let bad = [
            (Params { eps: 0.0, ..p }, "eps"),
            (
                Params {
                    min_step: -1.0,
                    ..p
                },
                "min_step",
            ),
            (Params { omega: 2.0, ..p }, "omega"),
            (Params { k: 1.0, ..p }, "k"),
            (Params { max_steps: 0, ..p }, "max_steps"),
            // The first failed check is reported.
            (
                Params {
                    eps: f64::NAN,
                    k: 0.0,
                    ..p
                },
                "eps",
            ),
        ];
        for (q, name) in bad {
            assert!(!q.is_valid());
            assert_eq!(q.validate().unwrap_err().name, name);
        }
    }
}
