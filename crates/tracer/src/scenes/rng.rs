//! A tiny deterministic PRNG (splitmix64), so scenes are identical on every
//! platform and need no dependency.

/// splitmix64 (Steele, Lea and Flood 2014).
#[derive(Clone, Debug)]
pub(crate) struct Rng(u64);

impl Rng {
    /// A generator for `seed`, decorrelated per scene by `stream`.
    pub(crate) fn new(seed: u64, stream: u64) -> Self {
        let mut r = Rng(seed ^ stream.wrapping_mul(0xD1B5_4A32_D192_ED03));
        r.next_u64();
        r
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)` (53 bits).
    pub(crate) fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in `[a, b)`.
    pub(crate) fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }

    /// Uniform on the unit sphere.
    pub(crate) fn direction(&mut self) -> [f64; 3] {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f64::consts::TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        [r * phi.cos(), r * phi.sin(), z]
    }

    /// Uniform in the ball of radius `r`.
    pub(crate) fn in_ball(&mut self, r: f64) -> [f64; 3] {
        let d = self.direction();
        let s = r * self.unit().cbrt();
        d.map(|x| x * s)
    }

    /// A uniformly random unit quaternion `[x, y, z, w]` (Shoemake 1992).
    pub(crate) fn quaternion(&mut self) -> [f64; 4] {
        let (u1, u2, u3) = (self.unit(), self.unit(), self.unit());
        let tau = std::f64::consts::TAU;
        let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
        [
            a * (tau * u2).sin(),
            a * (tau * u2).cos(),
            b * (tau * u3).sin(),
            b * (tau * u3).cos(),
        ]
    }
}

/// `a + s·b`.
pub(crate) fn add_scaled(a: [f64; 3], s: f64, b: [f64; 3]) -> [f64; 3] {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}

/// `|a − b|`.
pub(crate) fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// `a/|a|` (`a` itself when zero).
pub(crate) fn normalize(a: [f64; 3]) -> [f64; 3] {
    let n = dist(a, [0.0; 3]);
    if n > 0.0 { a.map(|x| x / n) } else { a }
}

/// Rotates `v` by the unit quaternion `q = [x, y, z, w]` (used by the
/// scene generators and by scene files' transforms).
pub fn rotate(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    let u = [q[0], q[1], q[2]];
    let w = q[3];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    // v + 2w(u × v) + 2u × (u × v)
    let uv = cross(u, v);
    let uuv = cross(u, uv);
    [0, 1, 2].map(|k| v[k] + 2.0 * (w * uv[k] + uuv[k]))
}

/// `n` points of a Fibonacci spiral on the unit sphere.
pub(crate) fn fibonacci_sphere(n: usize) -> Vec<[f64; 3]> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * i as f64;
            [r * phi.cos(), r * phi.sin(), z]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deterministic_and_in_range() {
        let (mut a, mut b) = (Rng::new(7, 1), Rng::new(7, 1));
        let mut c = Rng::new(7, 2);
        let xs: Vec<f64> = (0..100).map(|_| a.unit()).collect();
        let ys: Vec<f64> = (0..100).map(|_| b.unit()).collect();
        assert_eq!(xs, ys);
        assert_ne!(xs[0], c.unit());
        assert!(xs.iter().all(|x| (0.0..1.0).contains(x)));
        let d = a.direction();
        assert!((dist(d, [0.0; 3]) - 1.0).abs() < 1e-12);
        let q = a.quaternion();
        let n: f64 = q.iter().map(|x| x * x).sum();
        assert!((n - 1.0).abs() < 1e-12);
        let v = rotate(q, [0.3, -0.2, 0.5]);
        assert!((dist(v, [0.0; 3]) - dist([0.3, -0.2, 0.5], [0.0; 3])).abs() < 1e-12);
        assert!(dist(a.in_ball(0.5), [0.0; 3]) <= 0.5);
        assert_eq!(fibonacci_sphere(8).len(), 8);
    }
}
