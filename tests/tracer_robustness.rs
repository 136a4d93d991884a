//! Robustness of the tracing methods on every standard scene (issue 6),
//! against the dense reference of `boundtrace::tracer::stats`.
//!
//! For every scene of `scenes::NAMES` (one test each), every method and
//! both modes, on rays launched from the faces of the scene's box (thesis
//! §1.8 methodology, reduced counts):
//! - no method ever steps past a root (`stepped_past == 0`, both modes);
//! - every method agrees with the reference on ≥ 99.99% of the traced
//!   rays (with fewer than 10,000 rays: on every ray);
//! - `sphere` is traced exactly where the field has a global Lipschitz
//!   bound, `*-taylor` exactly where it has Taylor bounds and
//!   `scalis-quadratic` exactly on the SCALIS scenes; elsewhere every ray is
//!   `Unsupported`. On SCALIS scenes, `scalis-quadratic`, `sphere` (per-ray
//!   Lipschitz) and `interval` (per-primitive ranges) run through
//!   `boundtrace::tracer::scalis` (issue 7).
//!
//! Failures list the scene, method, mode and the first disagreeing rays
//! (index, origin, direction, roots of the method and of the reference,
//! status and `t_reached`). `BOUNDTRACE_RAYS_SCALE=k` multiplies the ray
//! counts (e.g. `k = 20`, with `--release`, so that the cheap scenes trace
//! ≥ 10,000 rays and the 99.99% criterion is not just "every ray").

use boundtrace::inclusion::Field;
use boundtrace::tracer::scenes::{DEFAULT_SEED, NAMES, Scene, SceneField};
use boundtrace::tracer::stats::{
    MethodStats, RaySet, ReferenceParams, enlarged, run_scene_method, scene_reference,
};
use boundtrace::tracer::{Method, Mode, Params};
use std::time::Instant;

/// The ray seed.
const SEED: u64 = 6;

/// The agreement the issue requires.
const MIN_AGREE: f64 = 0.9999;

/// Known limitations: method × scene-name prefix pairs whose rays may
/// *give up* (`Status::MaxSteps` at the default 10,000 steps) — and do
/// nothing else wrong: no spurious or far root, never a step past a root.
/// Each is reported in BENCHMARKS.md with its cause.
///
/// Empty since issue 7: `sphere` on SCALIS skeletons now uses the per-ray
/// Lipschitz bounds of thesis §1.7 and `interval` the per-primitive ranges
/// of ch. 2 (`boundtrace::tracer::scalis`), and both finish.
const MAY_GIVE_UP: &[(Method, &str, &str)] = &[];

/// The reason `method` may give up on `scene`, if it may.
fn may_give_up(method: Method, scene: &str) -> Option<&'static str> {
    MAY_GIVE_UP
        .iter()
        .find(|(m, prefix, _)| *m == method && scene.starts_with(prefix))
        .map(|(_, _, why)| *why)
}

fn scale() -> usize {
    std::env::var("BOUNDTRACE_RAYS_SCALE")
        .ok()
        .and_then(|s| s.parse().ok())
        .filter(|&k: &usize| k > 0)
        .unwrap_or(1)
}

/// What is wrong with one method × mode run, if anything.
fn problems(scene: &Scene<f64>, s: &MethodStats, rays: &RaySet<f64>) -> Option<String> {
    let field = scene.field();
    let head = format!(
        "{} × {} × {:?} ({} rays, {} traced)",
        scene.name(),
        s.method,
        s.mode,
        s.rays,
        s.traced()
    );
    if s.traced() == 0 {
        // Unsupported everywhere: only where the field lacks what the
        // method needs.
        let lacks = match s.method {
            Method::Sphere => field.lipschitz().is_none(),
            Method::LinearTaylor => rays
                .rays()
                .iter()
                .take(64)
                .all(|r| field.taylor_linear(&r.ray, r.span[0], r.span[1]).is_none()),
            Method::QuadraticTaylor => rays.rays().iter().take(64).all(|r| {
                field
                    .taylor_quadratic(&r.ray, r.span[0], r.span[1])
                    .is_none()
            }),
            // needs a SCALIS skeleton (`scalis::trace_scalis`)
            Method::ScalisQuadratic => !matches!(field, SceneField::Scalis(_)),
            _ => false,
        };
        return (!lacks).then(|| format!("{head}: Unsupported although the field supports it"));
    }
    let mut out = Vec::new();
    if s.method == Method::Sphere && field.lipschitz().is_none() {
        out.push("traced without a Lipschitz bound".to_string());
    }
    if s.unsupported > 0 {
        out.push(format!("{} rays Unsupported", s.unsupported));
    }
    if s.stepped_past > 0 {
        out.push(format!("stepped past a root on {} rays", s.stepped_past));
    }
    let allowed = (s.traced() as f64 * (1.0 - MIN_AGREE)).floor() as usize;
    let disagree = s.traced() - s.agree;
    let known = may_give_up(s.method, scene.name());
    let only_gave_up = s.spurious == 0 && s.far == 0 && disagree <= allowed + s.max_steps;
    if disagree > allowed && known.is_some() && only_gave_up {
        eprintln!(
            "{head}: {disagree} rays gave up (max-steps {}), a known limitation: {}",
            s.max_steps,
            known.unwrap_or_default()
        );
    } else if disagree > allowed {
        out.push(format!(
            "{disagree} rays disagree (allowed {allowed}: agree {:.4}% < {}%): missed {}, \
             gave up {}, spurious {}, far {}, stepped past {}, max-steps {}",
            100.0 * s.agree_ratio().unwrap_or(0.0),
            100.0 * MIN_AGREE,
            s.missed,
            s.gave_up,
            s.spurious,
            s.far,
            s.stepped_past,
            s.max_steps,
        ));
    }
    if out.is_empty() {
        return None;
    }
    let mut msg = format!("{head}: {}", out.join("; "));
    for f in &s.failures {
        msg.push_str(&format!("\n    {f}"));
    }
    Some(msg)
}

/// Every method × mode on `rays` rays of scene `name` (`sphere` on the
/// first `sphere_rays` of them: thousands of steps per ray on the big
/// scenes).
fn check_scene(name: &str, rays: usize, sphere_rays: usize) {
    let scene = Scene::<f64>::build(name, DEFAULT_SEED).unwrap_or_else(|e| panic!("{name}: {e}"));
    let rays = RaySet::new(enlarged(scene.bounds(), 1e-3), rays * scale(), SEED)
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    let clock = Instant::now();
    // The default parameters (max_steps 10,000: thousands of steps are
    // common for sphere tracing on grazing rays, papers' Table 1.2).
    let params = Params::new();
    let rp = ReferenceParams::new(params.eps).unwrap();
    let reference = scene_reference(&scene, &rays, &rp).unwrap();
    assert!(
        reference.hits() * 10 >= rays.len(),
        "{name}: only {} of {} rays hit the surface; the test would prove little",
        reference.hits(),
        rays.len()
    );
    let mut report = Vec::new();
    let n_sphere = sphere_rays * scale();
    let (sphere_set, sphere_ref) = (rays.prefix(n_sphere), reference.prefix(n_sphere));
    for method in Method::ALL {
        let (set, re) = match method {
            Method::Sphere => (&sphere_set, &sphere_ref),
            _ => (&rays, &reference),
        };
        for mode in [Mode::Opaque, Mode::Transparent] {
            let s = run_scene_method(&scene, set, re, method, mode, &params)
                .unwrap_or_else(|e| panic!("{name} {method} {mode:?}: {e}"));
            assert_eq!(s.rays, set.len());
            report.extend(problems(&scene, &s, set));
        }
    }
    eprintln!(
        "{name}: {} rays, {:.1} s",
        rays.len(),
        clock.elapsed().as_secs_f64()
    );
    assert!(
        report.is_empty(),
        "{} problem(s) on scene {name}:\n{}",
        report.len(),
        report.join("\n")
    );
}

/// One test per scene, with its ray counts (all methods, sphere tracing):
/// sized so that the file runs in about 1.5 minutes on 2 idle cores in the
/// dev profile (the harness runs inside the tracer crate, at opt-level 2);
/// the big scenes get fewer rays. Ignored by default (run them with
/// `cargo test --release --test tracer_robustness -- --ignored`):
/// `aggregate-3*` (1,110 primitives evaluated in full by the dense
/// reference and every method: 1.5–3 minutes in release, passing since
/// 2026-11-24) and `aggregate-4*` (11,110 primitives, about a second per
/// ray and method).
macro_rules! scenes {
    ($($(#[$attr:meta])* $test:ident => $name:literal, $rays:expr, $sphere:expr;)*) => {
        $(
            #[test]
            $(#[$attr])*
            fn $test() {
                check_scene($name, $rays, $sphere);
            }
        )*

        #[test]
        fn every_scene_is_checked() {
            let checked = [$($name),*];
            assert_eq!(NAMES, checked, "add the new scenes to tests/tracer_robustness.rs");
        }
    };
}

scenes! {
    blobs => "blobs", 600, 600;
    blobs_sum => "blobs-sum", 600, 600;
    molecule => "molecule", 12, 4;
    hrbf_8 => "hrbf-8", 600, 600;
    hrbf_17 => "hrbf-17", 600, 600;
    scalis_tree => "scalis-tree", 150, 30;
    scalis_foam => "scalis-foam", 60, 12;
    scalis_random => "scalis-random", 200, 60;
    aggregate_1 => "aggregate-1", 600, 600;
    aggregate_1_smooth => "aggregate-1-smooth", 300, 300;
    aggregate_2 => "aggregate-2", 60, 60;
    aggregate_2_smooth => "aggregate-2-smooth", 36, 36;
    #[ignore = "1,110 primitives evaluated in full (dense reference and every method): ~1.5 min in release; run with --release --ignored"]
    aggregate_3 => "aggregate-3", 24, 24;
    #[ignore = "1,110 primitives evaluated in full (dense reference and every method): ~3 min in release; run with --release --ignored"]
    aggregate_3_smooth => "aggregate-3-smooth", 24, 24;
    #[ignore = "11,110 primitives: ~1 s per ray and method; run with --release --ignored"]
    aggregate_4 => "aggregate-4", 12, 12;
    #[ignore = "11,110 primitives: ~1 s per ray and method; run with --release --ignored"]
    aggregate_4_smooth => "aggregate-4-smooth", 12, 12;
}

/// Regression: a ray of `aggregate-1-smooth` (ray 1357 of 5,000, seed 1)
/// on which `quadratic-bottom-up` used to give up. Within 10⁻⁸ of the
/// surface the bottom-up bound's validity interval collapsed to ~10⁻¹¹ and
/// the marcher stepped by it 10,000 times; a validity shorter than `eps`
/// now hands the step to interval certification (`march.rs`).
#[test]
fn collapsed_validity_does_not_crawl() {
    use boundtrace::inclusion::Ray;
    use boundtrace::tracer::{Root, Side, Status, trace};
    let scene = Scene::<f64>::build("aggregate-1-smooth", DEFAULT_SEED).unwrap();
    let ray = Ray::new(
        [0.9721150607617056, 0.002258114262562394, 0.7185601299801379],
        [-1.0, 0.0, 0.0],
    );
    let span = [0.0, 1.9442301215234112];
    // The dense reference's first root on this ray.
    let reference = 0.9900369303230108;
    let params = Params::new();
    for method in [Method::QuadraticBottomUp, Method::QuadraticMixed] {
        let mut roots = [Root {
            t: 0.0,
            side: Side::Touch,
        }; 4];
        let tr = trace(
            scene.field(),
            &ray,
            span,
            method,
            Mode::Opaque,
            &params,
            &mut roots,
        );
        assert_eq!(tr.status, Status::Finished, "{method}: {tr:?}");
        assert_eq!(tr.roots, 1, "{method}: {tr:?}");
        assert!(
            (roots[0].t - reference).abs() <= params.eps,
            "{method}: root {} vs reference {reference}",
            roots[0].t
        );
        assert!(tr.stats.steps < 200, "{method}: {} steps", tr.stats.steps);
    }
}

/// Regression: a ray of `hrbf-8` (ray 841 of 5,000, seed 1) on which
/// `interval` used to give up in transparent mode: after the entering root
/// the field stays within ~3·10⁻⁶ of 0 for 0.022 along the ray, and the
/// interval extension only excluded 0 on pieces ~10⁻⁶ long (24,000 steps).
/// Leaves with the same sign at both ends now try the forward linear
/// range first (`bisect.rs`).
#[test]
fn near_tangent_stretch_does_not_crawl() {
    use boundtrace::inclusion::Ray;
    use boundtrace::tracer::{Root, Side, Status, trace};
    let scene = Scene::<f64>::build("hrbf-8", DEFAULT_SEED).unwrap();
    let ray = Ray::new(
        [0.9532908965343808, 0.1842489809118596, -0.3234156990495527],
        [-1.0, 0.0, 0.0],
    );
    let span = [0.0, 1.9065817930687616];
    // The dense reference's roots on this ray.
    let reference = [
        (0.8551681442413626, Side::Entering),
        (0.8772272513671313, Side::Leaving),
    ];
    let params = Params::new();
    let mut roots = [Root {
        t: 0.0,
        side: Side::Touch,
    }; 8];
    let tr = trace(
        scene.field(),
        &ray,
        span,
        Method::Interval,
        Mode::Transparent,
        &params,
        &mut roots,
    );
    assert_eq!(tr.status, Status::Finished, "{tr:?}");
    assert_eq!(tr.roots, 2, "{tr:?}");
    for (r, (t, side)) in roots.iter().zip(reference) {
        assert_eq!(r.side, side);
        assert!(
            (r.t - t).abs() <= params.eps,
            "root {} vs reference {t}",
            r.t
        );
    }
}
