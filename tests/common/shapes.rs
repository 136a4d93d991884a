//! Analytic fields with known roots, for the tracer tests.

use boundtrace::inclusion::{Field, FieldNum};

/// A ball as a signed distance (Lipschitz 1, no Taylor bound): the roots of
/// a ray are the two ray–sphere intersections.
pub struct Ball {
    /// Centre.
    pub c: [f64; 3],
    /// Radius.
    pub r: f64,
}

impl Field<f64> for Ball {
    fn eval<N: FieldNum<f64>>(&self, p: [N; 3]) -> N {
        ((p[0] - self.c[0]).sqr() + (p[1] - self.c[1]).sqr() + (p[2] - self.c[2]).sqr()).sqrt()
            - self.r
    }
    fn lipschitz(&self) -> Option<f64> {
        Some(1.0)
    }
}
