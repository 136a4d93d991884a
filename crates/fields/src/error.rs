//! [`FieldError`]: why a field or a scene could not be built.

use core::fmt;

/// Why a field, primitive, operator or blobtree could not be constructed.
///
/// Construction validates its input (radii, lengths, degrees, sizes) and
/// reports the first problem; evaluation never fails.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum FieldError {
    /// A parameter is outside its domain (NaN, negative or zero radius,
    /// zero-length segment, kernel degree below 2, …).
    InvalidParameter {
        /// The parameter's name, as in the constructor's docs.
        name: &'static str,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// A linear system is singular or numerically degenerate (e.g. HRBF
    /// fitting with duplicate points).
    Singular {
        /// What made it degenerate.
        reason: &'static str,
    },
    /// A structure exceeds what the flat encoding can address.
    TooLarge {
        /// What overflowed (e.g. "nodes").
        what: &'static str,
        /// How many were requested.
        count: usize,
        /// The maximum the encoding supports.
        max: usize,
    },
    /// Flat scene data is malformed (bad node type, offset out of range, …).
    Malformed {
        /// What is wrong.
        reason: &'static str,
    },
}

impl fmt::Display for FieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FieldError::InvalidParameter { name, reason } => {
                write!(f, "invalid parameter `{name}`: {reason}")
            }
            FieldError::Singular { reason } => write!(f, "singular system: {reason}"),
            FieldError::TooLarge { what, count, max } => {
                write!(f, "too many {what}: {count} (at most {max})")
            }
            FieldError::Malformed { reason } => write!(f, "malformed scene data: {reason}"),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for FieldError {}

/// Checks that `x` is finite and `> 0`.
pub(crate) fn positive<T: boundtrace_ia_core::Real>(
    name: &'static str,
    x: T,
) -> Result<T, FieldError> {
    if x.is_nan() {
        return Err(FieldError::InvalidParameter {
            name,
            reason: "is NaN",
        });
    }
    if !x.is_finite() {
        return Err(FieldError::InvalidParameter {
            name,
            reason: "is infinite",
        });
    }
    if x <= T::ZERO {
        return Err(FieldError::InvalidParameter {
            name,
            reason: "must be > 0",
        });
    }
    Ok(x)
}

/// Checks that every coordinate of `p` is finite.
pub(crate) fn finite3<T: boundtrace_ia_core::Real>(
    name: &'static str,
    p: [T; 3],
) -> Result<[T; 3], FieldError> {
    if p.iter().all(|x| x.is_finite()) {
        Ok(p)
    } else {
        Err(FieldError::InvalidParameter {
            name,
            reason: "has a NaN or infinite coordinate",
        })
    }
}
