//! Fuzz targets for the soundness of boundtrace's bounds and tracers.
//!
//! Each target is a function `fn(&[u8]) -> Result<(), String>`: it decodes
//! the bytes into a case (operands, an expression tree, a field and a ray
//! interval, a tiny scene and a ray) and checks the property the library
//! promises; `Err` carries a readable report of the violation. The
//! libFuzzer entry points in `fuzz_targets/` abort with that report; the
//! unit tests below replay the committed seeds (`seeds/<target>/`) and every
//! regression input (`regressions/<target>/`) on stable Rust.
//!
//! The checks are the workspace's own property-test checks (in
//! `tests/common/`, included here as a module), driven by the fuzzer's bytes
//! instead of proptest's random source: the first byte selects the
//! operation or family, the expression-tree and blobtree generators read
//! their random words from the bytes, and proptest strategies (operands,
//! kernels, skeletons) draw from a generator seeded by the bytes. A violation found here is a violation of the same property the
//! test suite checks, with the same reference (`astro-float` enclosures for
//! the arithmetic, 192-bit evaluation for forward bounds, sound point
//! enclosures for fields, the dense reference of `boundtrace_tracer::stats`
//! for tracers).
//!
//! | target | property |
//! | --- | --- |
//! | [`interval_ops`] | every `Interval` operation (f32, f64) encloses the exact result at sampled points |
//! | [`affine_ops`] | every `Affine` operation (1 and 3 noise symbols) encloses the exact result |
//! | [`forward_bounds`] | forward linear/quadratic bounds of random expression trees: exact at `t0`, contain the function, valid end, safe root step; `Interval`/`Affine`/`Jet` agree |
//! | [`field_bounds`] | every bound type of random kernels/blobs/HRBF, SCALIS and homothetic skeletons and blobtrees contains the field |
//! | [`sparse_equivalence`] | the pruned blobtree over a query box has the full field's sign there; the sparse traversal emits the reference program |
//! | [`tracer_first_hit`] | no method steps past the dense reference's first root (or any root, transparent) on tiny random scenes |
//! | [`scene_parse`] | arbitrary bytes as a scene file (`boundtrace_cli::scene_format`): a descriptive error or a valid scene, never a panic; a valid file prints and parses back to itself |
//!
//! ```
//! // A violation is an `Err` with the report; random bytes are a valid case.
//! assert!(boundtrace_fuzz::interval_ops(&[3, 1, 2, 3, 4, 5, 6, 7, 8]).is_ok());
//! ```
#![forbid(unsafe_code)]

#[path = "../../tests/common/mod.rs"]
#[allow(missing_docs, clippy::all)]
mod common;

use boundtrace::fields::blobtree::FlatBlobtree;
use boundtrace::inclusion::{Field, Ray};
use boundtrace::tracer::stats::{ReferenceParams, classify, reference_roots};
use boundtrace::tracer::{Method, Mode, Params, Root, Side, trace};
use proptest::strategy::{Strategy, ValueTree};
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};

use common::Flt;
use common::check::picks;
use common::strategies::{eps, float, form, interval, pow_exponent, powi_exponent, trig_interval};
use common::{affine_props as ap, interval_props as ip};

/// The outcome of a check: a failed assertion is a violation (its message
/// is the report), a rejected case (`prop_assume!`) is fine.
fn outcome(r: Result<(), TestCaseError>) -> Result<(), String> {
    match r {
        Err(TestCaseError::Fail(msg)) => Err(msg.to_string()),
        _ => Ok(()),
    }
}

/// Proptest strategies driven by the fuzzer's bytes: ChaCha seeded with a
/// 256-bit digest of the bytes (four FNV-1a lanes), so every input is one
/// reproducible case. (Proptest's pass-through RNG, which would map bytes
/// to values directly, halves its data at each forked sub-generator and
/// yields zeros once it runs out, on which `rand`'s rejection sampling never
/// ends.) The targets' selector bytes and the tree generators
/// ([`forward_bounds`], the blobtree targets) read the bytes directly.
struct Draw(TestRunner);

impl Draw {
    fn new(data: &[u8]) -> Self {
        let mut seed = [0u8; 32];
        for (lane, chunk) in seed.chunks_mut(8).enumerate() {
            let h = data.iter().fold(
                0xcbf2_9ce4_8422_2325_u64 ^ (lane as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15),
                |h, &b| (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3),
            );
            chunk.copy_from_slice(&h.to_le_bytes());
        }
        let config = Config {
            failure_persistence: None,
            ..Config::default()
        };
        Draw(TestRunner::new_with_rng(
            config,
            TestRng::from_seed(RngAlgorithm::ChaCha, &seed),
        ))
    }

    /// A value of `s`, or `None` when the strategy rejects the bytes.
    fn get<S: Strategy>(&mut self, s: S) -> Option<S::Value> {
        s.new_tree(&mut self.0).ok().map(|t| t.current())
    }
}

/// Draws a value or ends the case as uninteresting.
macro_rules! draw {
    ($d:expr, $s:expr) => {
        match $d.get($s) {
            Some(v) => v,
            None => return Ok(()),
        }
    };
}

/// Splits off the first byte (the case's selector).
fn head(data: &[u8]) -> (u8, &[u8]) {
    match data.split_first() {
        Some((&h, rest)) => (h, rest),
        None => (0, data),
    }
}

// ---------------------------------------------------------------------------
// interval_ops

/// Operations of [`interval_ops`], in selector order.
pub const INTERVAL_OPS: [&str; 31] = [
    "new",
    "point",
    "hull",
    "intersection",
    "contains",
    "subset",
    "width",
    "mid",
    "rad",
    "mag",
    "mig",
    "neg",
    "add",
    "sub",
    "mul",
    "div",
    "scalar_rhs",
    "scalar_lhs",
    "recip",
    "sqr",
    "powi",
    "pow",
    "sqrt",
    "exp",
    "ln",
    "sin",
    "cos",
    "abs",
    "min",
    "max",
    "ops_chain",
];

/// `Interval` operations: the first byte picks the operation (low 7 bits,
/// modulo [`INTERVAL_OPS`]) and the float type (top bit: `f64`); the rest
/// draws the operands (the containment tests' strategies: infinities,
/// signed zeros, subnormals, anchors) and the sample points. The exact
/// result at every sample is enclosed with `astro-float` and must lie in the
/// computed interval.
pub fn interval_ops(data: &[u8]) -> Result<(), String> {
    let (h, rest) = head(data);
    let op = usize::from(h & 0x7f) % INTERVAL_OPS.len();
    if h & 0x80 == 0 {
        interval_op::<f32>(op, rest)
    } else {
        interval_op::<f64>(op, rest)
    }
}

fn interval_op<T>(op: usize, data: &[u8]) -> Result<(), String>
where
    T: Flt
        + std::ops::Add<boundtrace::ia_core::Interval<T>, Output = boundtrace::ia_core::Interval<T>>
        + std::ops::Sub<boundtrace::ia_core::Interval<T>, Output = boundtrace::ia_core::Interval<T>>
        + std::ops::Mul<boundtrace::ia_core::Interval<T>, Output = boundtrace::ia_core::Interval<T>>
        + std::ops::Div<boundtrace::ia_core::Interval<T>, Output = boundtrace::ia_core::Interval<T>>,
{
    let mut d = Draw::new(data);
    let r = match op {
        0 => ip::prop_new(draw!(d, float::<T>()), draw!(d, float::<T>())),
        1 => ip::prop_point(draw!(d, float::<T>())),
        4 => ip::prop_contains(draw!(d, interval::<T>())),
        5 => ip::prop_subset(draw!(d, interval::<T>()), draw!(d, interval::<T>())),
        6 => ip::prop_width(draw!(d, interval::<T>())),
        7 => ip::prop_mid(draw!(d, interval::<T>())),
        8 => ip::prop_rad(draw!(d, interval::<T>())),
        25 | 26 => {
            let x = draw!(d, trig_interval::<T>());
            let pk = draw!(d, picks());
            if op == 25 {
                ip::prop_sin(x, &pk)
            } else {
                ip::prop_cos(x, &pk)
            }
        }
        30 => return interval_chain::<T>(&mut d),
        _ => {
            let x = draw!(d, interval::<T>());
            let pk = draw!(d, picks());
            match op {
                9 => ip::prop_mag(x, &pk),
                10 => ip::prop_mig(x, &pk),
                11 => ip::prop_neg(x, &pk),
                16 => ip::prop_scalar_rhs(x, draw!(d, float::<T>()), &pk),
                17 => ip::prop_scalar_lhs(x, draw!(d, float::<T>()), &pk),
                18 => ip::prop_recip(x, &pk),
                19 => ip::prop_sqr(x, &pk),
                20 => ip::prop_powi(x, draw!(d, powi_exponent()), &pk),
                21 => ip::prop_pow(x, draw!(d, pow_exponent::<T>()), &pk),
                22 => ip::prop_sqrt(x, &pk),
                23 => ip::prop_exp(x, &pk),
                24 => ip::prop_ln(x, &pk),
                27 => ip::prop_abs(x, &pk),
                _ => {
                    let y = draw!(d, interval::<T>());
                    match op {
                        2 => ip::prop_hull(x, y, &pk),
                        3 => ip::prop_intersection(x, y, &pk),
                        12 => ip::prop_add(x, y, &pk),
                        13 => ip::prop_sub(x, y, &pk),
                        14 => ip::prop_mul(x, y, &pk),
                        15 => ip::prop_div(x, y, &pk),
                        28 => ip::prop_min(x, y, &pk),
                        _ => ip::prop_max(x, y, &pk),
                    }
                }
            }
        }
    };
    outcome(r)
}

/// A chain of up to 8 unary/binary operations, each result feeding the next
/// as its left operand: every step's containment is checked on its actual
/// (often unusual) operands.
fn interval_chain<T>(d: &mut Draw) -> Result<(), String>
where
    T: Flt
        + std::ops::Add<boundtrace::ia_core::Interval<T>, Output = boundtrace::ia_core::Interval<T>>
        + std::ops::Sub<boundtrace::ia_core::Interval<T>, Output = boundtrace::ia_core::Interval<T>>
        + std::ops::Mul<boundtrace::ia_core::Interval<T>, Output = boundtrace::ia_core::Interval<T>>
        + std::ops::Div<boundtrace::ia_core::Interval<T>, Output = boundtrace::ia_core::Interval<T>>,
{
    let mut x = draw!(d, interval::<T>());
    let steps = draw!(d, 1usize..=8);
    for _ in 0..steps {
        let op = draw!(d, 0usize..12);
        let pk = draw!(d, picks());
        let (r, next) = match op {
            0 => (ip::prop_neg(x, &pk), -x),
            1 => (ip::prop_sqr(x, &pk), x.sqr()),
            2 => (ip::prop_sqrt(x, &pk), x.sqrt()),
            3 => (ip::prop_exp(x, &pk), x.exp()),
            4 => (ip::prop_ln(x, &pk), x.ln()),
            5 => (ip::prop_recip(x, &pk), x.recip()),
            6 => (ip::prop_sin(x, &pk), x.sin()),
            7 => (ip::prop_abs(x, &pk), x.abs()),
            _ => {
                let y = draw!(d, interval::<T>());
                match op {
                    8 => (ip::prop_add(x, y, &pk), x + y),
                    9 => (ip::prop_sub(x, y, &pk), x - y),
                    10 => (ip::prop_mul(x, y, &pk), x * y),
                    _ => (ip::prop_div(x, y, &pk), x / y),
                }
            }
        };
        outcome(r)?;
        x = next;
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// affine_ops

/// Operations of [`affine_ops`], in selector order.
pub const AFFINE_OPS: [&str; 19] = [
    "constant",
    "from_interval",
    "variable",
    "to_interval",
    "eval",
    "neg",
    "add",
    "sub",
    "mul",
    "div",
    "min",
    "max",
    "scalar_rhs",
    "scalar_lhs",
    "sqr",
    "exp",
    "sqrt",
    "ln",
    "recip",
];

/// `Affine` operations: the first byte picks the operation (low 5 bits,
/// modulo [`AFFINE_OPS`]), the float type (bit 7: `f64`) and the number of
/// noise symbols (bit 6: 3, else 1); the rest draws the forms, three noise
/// assignments and the sample points. The exact result at every assignment
/// and sample must lie in the result form's range there.
pub fn affine_ops(data: &[u8]) -> Result<(), String> {
    let (h, rest) = head(data);
    let op = usize::from(h & 0x1f) % AFFINE_OPS.len();
    match (h & 0x80 != 0, h & 0x40 != 0) {
        (false, false) => affine_op::<f32, 1>(op, rest),
        (false, true) => affine_op::<f32, 3>(op, rest),
        (true, false) => affine_op::<f64, 1>(op, rest),
        (true, true) => affine_op::<f64, 3>(op, rest),
    }
}

fn affine_op<T, const N: usize>(op: usize, data: &[u8]) -> Result<(), String>
where
    T: Flt
        + std::ops::Add<boundtrace::ia_core::Affine<T, N>, Output = boundtrace::ia_core::Affine<T, N>>
        + std::ops::Sub<boundtrace::ia_core::Affine<T, N>, Output = boundtrace::ia_core::Affine<T, N>>
        + std::ops::Mul<boundtrace::ia_core::Affine<T, N>, Output = boundtrace::ia_core::Affine<T, N>>
        + std::ops::Div<boundtrace::ia_core::Affine<T, N>, Output = boundtrace::ia_core::Affine<T, N>>,
{
    let mut d = Draw::new(data);
    let r = match op {
        0 => {
            let c = draw!(d, float::<T>());
            ap::prop_constant::<T, N>(c, &draw!(d, eps::<T, N>()))
        }
        1 | 2 => {
            let iv = draw!(d, interval::<T>());
            let e = draw!(d, eps::<T, N>());
            let pk = draw!(d, picks());
            if op == 1 {
                ap::prop_from_interval::<T, N>(iv, &e, &pk)
            } else {
                let k = draw!(d, 0..=N);
                ap::prop_variable::<T, N>(iv, k, &e, &pk)
            }
        }
        3 => ap::prop_to_interval(draw!(d, form::<T, N>())),
        4 => {
            let x = draw!(d, form::<T, N>());
            ap::prop_eval(x, &draw!(d, eps::<T, N>()))
        }
        _ => {
            let x = draw!(d, form::<T, N>());
            let e = draw!(d, eps::<T, N>());
            let pk = draw!(d, picks());
            match op {
                5 => ap::prop_neg(x, &e, &pk),
                12 => ap::prop_scalar_rhs(x, draw!(d, float::<T>()), &e, &pk),
                13 => ap::prop_scalar_lhs(x, draw!(d, float::<T>()), &e, &pk),
                14 => ap::prop_sqr(x, &e, &pk),
                15 => ap::prop_exp(x, &e, &pk),
                16 => ap::prop_sqrt(x, &e, &pk),
                17 => ap::prop_ln(x, &e, &pk),
                18 => ap::prop_recip(x, &e, &pk),
                _ => {
                    let y = draw!(d, form::<T, N>());
                    match op {
                        6 => ap::prop_add(x, y, &e, &pk),
                        7 => ap::prop_sub(x, y, &e, &pk),
                        8 => ap::prop_mul(x, y, &e, &pk),
                        9 => ap::prop_div(x, y, &e, &pk),
                        10 => ap::prop_min(x, y, &e, &pk),
                        _ => ap::prop_max(x, y, &e, &pk),
                    }
                }
            }
        }
    };
    outcome(r)
}

// ---------------------------------------------------------------------------
// forward_bounds

/// Forward bounds of a random expression tree over the ray parameter
/// (every `FieldNum` operation, guarded and unguarded singular arguments),
/// on a random ray interval and composition variant: the first byte's low
/// bit picks `f64`, the rest drives the tree generator. Checked against a
/// 192-bit reference: exactness at `t0`, containment on a grid, the
/// validity end, the safe root step, and that `Interval`, `Affine` and
/// `Jet` evaluations of the same tree agree with the reference.
pub fn forward_bounds(data: &[u8]) -> Result<(), String> {
    let (h, rest) = head(data);
    if h & 1 == 0 {
        outcome(common::forward::check_bytes::<f32>(rest))
    } else {
        outcome(common::forward::check_bytes::<f64>(rest))
    }
}

// ---------------------------------------------------------------------------
// field_bounds

/// Bounds of random fields over random ray intervals: the first byte picks
/// the family (modulo 5): kernels, blob sums and HRBF fits under every
/// density operator (`f32` and `f64`); 1- and 2-segment SCALIS skeletons;
/// homothetic-distance primitives; random blobtrees (CSG, smooth and
/// compact operators over transformed primitives); the tracer's
/// per-primitive SCALIS cell bounds. Every bound type
/// (`Interval`, `Affine`, forward linear and quadratic, bottom-up, Taylor
/// and mixed, per-primitive ranges, directional Lipschitz) must contain a
/// sound enclosure of the field at sampled points of its interval.
pub fn field_bounds(data: &[u8]) -> Result<(), String> {
    let (h, rest) = head(data);
    match h % 5 {
        0 => {
            let mut d = Draw::new(rest);
            let c = draw!(d, common::kernel_cases::case());
            outcome(common::kernel_cases::check_case::<f64>(&c))?;
            outcome(common::kernel_cases::check_case::<f32>(&c))
        }
        1 => {
            let mut d = Draw::new(rest);
            let c = draw!(d, common::scalis_cases::case());
            outcome(common::scalis_cases::check_case(&c))
        }
        2 => {
            let mut d = Draw::new(rest);
            let c = draw!(d, common::scalis_cases::hcase());
            outcome(common::scalis_cases::check_homothetic(&c))
        }
        3 => {
            let mut rng = common::blobtree::Rng::from_bytes(rest);
            outcome(common::blobtree::check_bound_containment(&mut rng))
        }
        _ => {
            let mut d = Draw::new(rest);
            let c = draw!(d, common::scalis_cases::case());
            let cells = draw!(d, 1u32..=64);
            scalis_cell_bounds(&c, cells)
        }
    }
}

/// The tracer's per-primitive SCALIS density bounds by skeleton cells
/// (`boundtrace::tracer::scalis::bounds::density_bounds`, float distances
/// widened outward) contain a sound enclosure of each segment's density at
/// the ends and three sampled points of the ray interval.
fn scalis_cell_bounds(c: &common::scalis_cases::Case, cells: u32) -> Result<(), String> {
    use boundtrace::fields::homothetic::Segment;
    use boundtrace::fields::scalis::ScalisSegment;
    use boundtrace::ia_core::Interval;
    use boundtrace::tracer::scalis::bounds::density_bounds;
    let speed = c.ray.speed();
    if !(speed > 1e-3 && speed.is_finite()) {
        return Ok(());
    }
    let (t0, t1) = (c.t0, c.t0 + c.h);
    for &((a, ra), (b, rb)) in &c.segs {
        let Ok(seg) = Segment::new(a, ra, b, rb) else {
            continue;
        };
        let Ok(seg) = ScalisSegment::new(seg, c.kernel, 1.0) else {
            continue;
        };
        let bound = density_bounds(&seg, &c.ray, t0, t1, cells);
        for t in [
            t0,
            t1,
            t0 + c.h * c.taus[0],
            t0 + c.h * c.taus[1],
            t0 + c.h * c.taus[2],
        ] {
            let exact: Interval<f64> = seg.density(c.ray.at::<Interval<f64>>(t, t));
            if bound.intersection(exact).is_empty() {
                return Err(format!(
                    "density_bounds({cells} cells) = {bound:?} misses the density {exact:?} \
                     at t = {t:e} on [{t0:e}, {t1:e}]\n  segment {a:?} r={ra} -> {b:?} r={rb}\n  \
                     kernel {:?}\n  ray {:?}",
                    c.kernel, c.ray
                ));
            }
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// sparse_equivalence

/// Sparse blobtree evaluation: the first byte's low bit picks the check.
/// (0) For a random query box in one of four large random trees (≥ 200
/// nodes, sharp, smooth and compact operators), the pruned view built from
/// the primitives whose ABV meets the box has the sign of the full field at
/// random points of the box, and equals the direct sparse evaluation
/// (synchronized-tracing paper eq. 4). (1) For a random tree and random
/// active set, the fast-ancestor sparse traversal visits exactly the active
/// nodes and emits the program of a recursive reference.
pub fn sparse_equivalence(data: &[u8]) -> Result<(), String> {
    let (h, rest) = head(data);
    let mut rng = common::blobtree::Rng::from_bytes(rest);
    if h & 1 == 0 {
        outcome(common::blobtree::check_local_equivalence(&mut rng))
    } else {
        outcome(common::blobtree::check_sparse_traversal_matches_reference(
            &mut rng,
        ))
    }
}

// ---------------------------------------------------------------------------
// tracer_first_hit

/// Ray span of [`tracer_first_hit`]: the rays start within `[−3, 3]³` and
/// the scenes lie within about `[−2, 2]³`.
const SPAN: [f64; 2] = [0.0, 8.0];

/// Tracers on tiny random scenes: the first byte picks the scene family
/// (low bit: a random blobtree of 1–4 primitives, or a sum of 1–4 compact
/// or smooth point blobs); the rest draws the scene and a ray. Every method
/// ([`Method::ALL`]) is run in opaque and transparent mode and classified
/// against the dense reference (`boundtrace_tracer::stats`, interval
/// enclosures, ε = 1e-4): **no method may step past a certain reference
/// root** (opaque: the first; transparent: any) without reporting it. Giving
/// up (`max_steps`) and unsupported methods are not violations.
pub fn tracer_first_hit(data: &[u8]) -> Result<(), String> {
    let (h, rest) = head(data);
    if h & 1 == 0 {
        let mut rng = common::blobtree::Rng::from_bytes(rest);
        let n = 1 + rng.below(4);
        let tree = common::blobtree::random_tree::<f64>(&mut rng, n, 1.0, 0.05, 0.3);
        let Ok(flat) = FlatBlobtree::from_node(&tree) else {
            return Ok(());
        };
        let ray = Ray::new(rng.point(3.0), rng.point(1.0));
        check_tracers(&flat.as_ref(), &ray, &|| format!("blobtree {tree:?}"))
    } else {
        let mut d = Draw::new(rest);
        let blobs = draw!(
            d,
            proptest::collection::vec(common::kernel_cases::bdesc(), 1..=4)
        );
        let iso = draw!(d, 0.05f64..0.6);
        let o = draw!(d, proptest::array::uniform3(-3.0f64..3.0));
        let dir = draw!(d, proptest::array::uniform3(-1.0f64..1.0));
        let field = common::kernel_cases::make_blobs::<f64>(iso, &blobs);
        let ray = Ray::new(o, dir);
        check_tracers(&field, &ray, &|| format!("blobs iso={iso} {blobs:?}"))
    }
}

fn check_tracers<F: Field<f64>>(
    field: &F,
    ray: &Ray<f64>,
    scene: &dyn Fn() -> String,
) -> Result<(), String> {
    let speed = ray.speed();
    if !(speed > 1e-3 && speed.is_finite()) {
        return Ok(());
    }
    let params = Params::<f64>::new();
    let Ok(rp) = ReferenceParams::new(params.eps) else {
        return Ok(());
    };
    let Ok(reference) = reference_roots(field, ray, SPAN, &rp) else {
        return Ok(());
    };
    let mut buf = [Root {
        t: 0.0,
        side: Side::Touch,
    }; 64];
    for method in Method::ALL {
        for mode in [Mode::Opaque, Mode::Transparent] {
            let tr = trace(field, ray, SPAN, method, mode, &params, &mut buf);
            let roots = &buf[..(tr.roots as usize).min(buf.len())];
            let v = classify(mode, &rp, &reference, roots, tr.status, tr.t_reached);
            if v.stepped_past {
                return Err(format!(
                    "{method} ({mode:?}) stepped past a root: verdict {v}, status {:?}, \
                     t_reached {}\n  roots     {roots:?}\n  reference {reference:?}\n  \
                     ray {ray:?} span {SPAN:?}\n  scene {}",
                    tr.status,
                    tr.t_reached,
                    scene()
                ));
            }
        }
    }
    Ok(())
}

/// `scene_parse`: the bytes as a scene file. Parsing and building must
/// return a descriptive error (non-empty message) or a scene with a finite
/// box (`min < max`); a parsed file must print and parse back to itself
/// (exact numbers), and build in `f32` as well without panicking. A panic
/// anywhere is the fuzzer's finding.
pub fn scene_parse(data: &[u8]) -> Result<(), String> {
    use boundtrace_cli::scene_format::SceneFile;
    let file = match SceneFile::parse_bytes(data) {
        Ok(f) => f,
        Err(e) if e.message.is_empty() => return Err(format!("empty error message: {e:?}")),
        Err(_) => return Ok(()),
    };
    let again = SceneFile::parse(&file.to_json())
        .map_err(|e| format!("a parsed file does not parse back: {e}\n{}", file.to_json()))?;
    if again != file {
        return Err(format!(
            "print/parse round trip differs:\n{file:?}\n{again:?}"
        ));
    }
    match file.build::<f64>() {
        Err(e) if e.message.is_empty() => Err(format!("empty error message: {e:?}")),
        Err(_) => Ok(()),
        Ok(scene) => {
            let [lo, hi] = scene.bounds();
            if !(0..3).all(|k| lo[k].is_finite() && hi[k].is_finite() && lo[k] < hi[k]) {
                return Err(format!("a built scene has a bad box {:?}", scene.bounds()));
            }
            let _ = file.build::<f32>();
            Ok(())
        }
    }
}

// ---------------------------------------------------------------------------
// Replays (stable `cargo test`)

/// A target: bytes in, `Err(report)` on a violation.
pub type Target = fn(&[u8]) -> Result<(), String>;

/// Every target by name (the replays iterate over them).
pub const TARGETS: [(&str, Target); 7] = [
    ("interval_ops", interval_ops),
    ("affine_ops", affine_ops),
    ("forward_bounds", forward_bounds),
    ("field_bounds", field_bounds),
    ("sparse_equivalence", sparse_equivalence),
    ("tracer_first_hit", tracer_first_hit),
    ("scene_parse", scene_parse),
];

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// The files of `dir` (sorted), or none when it does not exist.
    fn inputs(dir: &Path) -> Vec<std::path::PathBuf> {
        let Ok(rd) = std::fs::read_dir(dir) else {
            return Vec::new();
        };
        let mut v: Vec<_> = rd
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.is_file())
            .collect();
        v.sort();
        v
    }

    fn replay(name: &str, target: Target) {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let seeds = inputs(&root.join("seeds").join(name));
        assert!(
            seeds.len() >= 8,
            "{name}: the committed seed corpus fuzz/seeds/{name}/ has {} inputs",
            seeds.len()
        );
        let regressions = inputs(&root.join("regressions").join(name));
        for path in seeds.iter().chain(&regressions) {
            let data = std::fs::read(path).expect("read an input");
            if let Err(report) = target(&data) {
                panic!(
                    "{name}: {} violates the property:\n{report}",
                    path.display()
                );
            }
        }
        println!(
            "{name}: {} seeds and {} regression inputs replayed",
            seeds.len(),
            regressions.len()
        );
    }

    #[test]
    fn replay_interval_ops() {
        replay("interval_ops", interval_ops);
    }

    #[test]
    fn replay_affine_ops() {
        replay("affine_ops", affine_ops);
    }

    #[test]
    fn replay_forward_bounds() {
        replay("forward_bounds", forward_bounds);
    }

    #[test]
    fn replay_field_bounds() {
        replay("field_bounds", field_bounds);
    }

    #[test]
    fn replay_sparse_equivalence() {
        replay("sparse_equivalence", sparse_equivalence);
    }

    #[test]
    fn replay_tracer_first_hit() {
        replay("tracer_first_hit", tracer_first_hit);
    }

    #[test]
    fn replay_scene_parse() {
        replay("scene_parse", scene_parse);
    }

    /// The scene check can fail: a valid file whose printed form differs
    /// would be reported (here: a wrong version is an error, not a scene).
    #[test]
    fn scene_parse_accepts_the_examples_and_rejects_garbage() {
        let ok = br#"{"version": 1, "field": {"blobs": {"iso": 0.5, "blobs": [
            {"center": [0, 0, 0], "kernel": {"compact": {"degree": 6, "sigma": 1}}}]}}}"#;
        assert_eq!(scene_parse(ok), Ok(()));
        let file = boundtrace_cli::scene_format::SceneFile::parse_bytes(ok).unwrap();
        assert!(file.build::<f64>().is_ok());
        assert!(boundtrace_cli::scene_format::SceneFile::parse_bytes(b"{\"version\": 2").is_err());
    }

    /// The checks can fail: a wrong interval (the exact sum shifted by one
    /// step) is reported by the same reference the targets use.
    #[test]
    fn a_wrong_enclosure_is_reported() {
        use boundtrace::ia_core::Interval;
        let x = Interval::new(1.0f64, 2.0);
        let wrong = Interval::new(2.0f64.next_up(), 4.0);
        let pk = common::check::Picks::FIXED[0];
        let r = common::check::binary("add", x, x, wrong, &pk, |a, b, p| {
            Some(common::reference::add(a, b, p))
        });
        assert!(outcome(r).is_err());
    }

    /// Every selector of every target runs on a few byte strings (empty,
    /// zeros, a ramp) without a violation or a panic.
    #[test]
    fn every_selector_runs() {
        let ramp: Vec<u8> = (0..=255u8).collect();
        // Distinct selectors: operation and type bits, or the family bits.
        let selectors = [256u16, 256, 2, 5, 2, 2, 256];
        for ((name, target), count) in TARGETS.into_iter().zip(selectors) {
            for sel in 0..count {
                for body in [&[][..], &[0u8; 64][..], &ramp[..]] {
                    let mut data = vec![sel as u8];
                    data.extend_from_slice(body);
                    if let Err(report) = target(&data) {
                        panic!("{name}: selector {sel}: {report}");
                    }
                }
            }
        }
    }
}
