//! Bisection methods (in progress).
use crate::method::{Mode, Params};
use crate::trace::{Root, Trace};
use boundtrace_ia_core::Real;
use boundtrace_inclusion::{Field, Ray};

pub(crate) fn interval<T: Real, F: Field<T>>(
    _field: &F,
    _ray: &Ray<T>,
    _span: [T; 2],
    _mode: Mode,
    _params: &Params<T>,
    _roots: &mut [Root<T>],
) -> Trace<T> {
    Trace { roots: 0, status: crate::Status::Unsupported, t_reached: _span[0], stats: Default::default() }
}

pub(crate) fn affine<T: Real, F: Field<T>>(
    _field: &F,
    _ray: &Ray<T>,
    _span: [T; 2],
    _mode: Mode,
    _params: &Params<T>,
    _roots: &mut [Root<T>],
) -> Trace<T> {
    Trace { roots: 0, status: crate::Status::Unsupported, t_reached: _span[0], stats: Default::default() }
}
