//! Synchronized tracing (issue 8) against full-tree evaluation on every
//! standard blobtree scene: the same hits and misses, depths within
//! `1e-4` relative, the same normals, for `sphere` and `quadratic-mixed`
//! (plus every method in both modes on a small scene), at a small resolution; and
//! an edit of primitive parameters (not structure) followed by new ABVs and
//! a new A-buffer renders like a fresh build.
//!
//! `aggregate-3*`/`aggregate-4*` are compared on small, zoomed images (their
//! full-tree evaluation is what synchronized tracing avoids: up to 11,110
//! primitives per evaluation; the full-tree `quadratic-mixed` reference takes
//! about 20 s in release on `aggregate-4-smooth`).

use boundtrace::fields::blobtree::FlatBlobtree;
use boundtrace::tracer::camera::Camera;
use boundtrace::tracer::render::{RenderSettings, render};
use boundtrace::tracer::scenes::{DEFAULT_SEED, NAMES, Scene, SceneField};
use boundtrace::tracer::sync_render::{SyncSettings, render_sync};
use boundtrace::tracer::{Method, Mode};
use std::time::Instant;

#[path = "common/frames.rs"]
mod frames;
use frames::{assert_same, tree};

/// Renders `name` both ways at `size²` pixels through a camera of vertical
/// field of view `fov` (degrees) looking at the scene's centre, with 4×4
/// tiles (so that small images still have several tiles).
fn compare(name: &str, size: u32, fov: f64, method: Method, mode: Mode) {
    let scene: Scene<f64> = Scene::build(name, DEFAULT_SEED).unwrap();
    let flat = tree(&scene);
    let bounds = scene.bounds();
    let camera = Camera::framing(bounds, [-0.3, -0.4, -1.0], fov, 1.0).unwrap();
    let settings = RenderSettings::new(size, size, method)
        .unwrap()
        .with_mode(mode);
    let sync = SyncSettings {
        tile_size: 4,
        ..SyncSettings::default()
    };
    let start = Instant::now();
    let (a, report) = render_sync(flat, &camera, bounds, &settings, &sync).unwrap();
    let sync_time = start.elapsed();
    let start = Instant::now();
    let b = render(&flat.as_ref(), &camera, bounds, &settings).unwrap();
    let full_time = start.elapsed();
    let what = format!("{name} × {method} × {mode:?}");
    let hits = assert_same(&a, &b, &what);
    if matches!(
        method,
        Method::LinearTaylor | Method::QuadraticTaylor | Method::ScalisQuadratic
    ) {
        // No Taylor bounds on a blobtree, and `scalis-quadratic` needs a
        // SCALIS skeleton: nothing traced, both ways.
        assert_eq!(a.totals().unsupported, a.totals().box_rays, "{what}");
    } else {
        assert!(hits > 0, "{what}: no hit at all");
    }
    assert_eq!(report.counters.overflow_ranges, 0, "{what}");
    eprintln!(
        "{what}: {size}x{size}, {hits} hits, sync {sync_time:?}, full {full_time:?}, {:?}",
        report.counters
    );
}

#[test]
fn every_blobtree_scene_is_a_blobtree_scene() {
    // The scenes compared here are all the standard blobtree scenes.
    let blobtrees: Vec<&str> = NAMES
        .iter()
        .copied()
        .filter(|n| {
            let s: Scene<f64> = Scene::build(n, DEFAULT_SEED).unwrap();
            matches!(s.field(), SceneField::Blobtree(_))
        })
        .collect();
    assert_eq!(
        blobtrees,
        [
            "aggregate-1",
            "aggregate-1-smooth",
            "aggregate-2",
            "aggregate-2-smooth",
            "aggregate-3",
            "aggregate-3-smooth",
            "aggregate-4",
            "aggregate-4-smooth",
        ]
    );
}

/// `sphere` and `quadratic-mixed` (the latter at a lower resolution: the
/// full-tree reference of forward quadratic marching costs ~1,400 bound
/// evaluations per ray on the aggregates). The larger scenes are looked at
/// through a narrower field of view, so that most pixels hit.
macro_rules! equivalence {
    ($($(#[$attr:meta])* $test:ident => $name:literal, $method:expr, $size:expr, $fov:expr;)*) => {$(
        #[test]
        $(#[$attr])*
        fn $test() {
            compare($name, $size, $fov, $method, Mode::Opaque);
        }
    )*};
}

equivalence! {
    aggregate_1_sphere => "aggregate-1", Method::Sphere, 16, 25.0;
    aggregate_1_quadratic => "aggregate-1", Method::QuadraticMixed, 8, 25.0;
    aggregate_1_smooth_sphere => "aggregate-1-smooth", Method::Sphere, 16, 25.0;
    aggregate_1_smooth_quadratic => "aggregate-1-smooth", Method::QuadraticMixed, 8, 25.0;
    aggregate_2_sphere => "aggregate-2", Method::Sphere, 12, 25.0;
    aggregate_2_quadratic => "aggregate-2", Method::QuadraticMixed, 6, 25.0;
    aggregate_2_smooth_sphere => "aggregate-2-smooth", Method::Sphere, 12, 25.0;
    aggregate_2_smooth_quadratic => "aggregate-2-smooth", Method::QuadraticMixed, 6, 25.0;
    aggregate_3_sphere => "aggregate-3", Method::Sphere, 8, 12.0;
    aggregate_3_smooth_sphere => "aggregate-3-smooth", Method::Sphere, 8, 12.0;
    aggregate_4_sphere => "aggregate-4", Method::Sphere, 4, 6.0;
    aggregate_4_smooth_sphere => "aggregate-4-smooth", Method::Sphere, 4, 6.0;
    aggregate_3_quadratic => "aggregate-3", Method::QuadraticMixed, 4, 12.0;
    aggregate_3_smooth_quadratic => "aggregate-3-smooth", Method::QuadraticMixed, 4, 12.0;
    aggregate_4_quadratic => "aggregate-4", Method::QuadraticMixed, 4, 6.0;
    aggregate_4_smooth_quadratic => "aggregate-4-smooth", Method::QuadraticMixed, 4, 6.0;
}

#[test]
fn every_method_both_modes_on_aggregate_1_smooth() {
    for method in Method::ALL {
        for mode in [Mode::Opaque, Mode::Transparent] {
            compare("aggregate-1-smooth", 8, 25.0, method, mode);
        }
    }
}

#[test]
fn editing_parameters_then_new_abvs_and_abuffer_renders_like_a_fresh_build() {
    let scene: Scene<f64> = Scene::build("aggregate-2-smooth", DEFAULT_SEED).unwrap();
    let original = tree(&scene);
    let bounds = scene.bounds();
    let camera = Camera::framing(bounds, [-0.3, -0.4, -1.0], 25.0, 1.0).unwrap();
    let settings = RenderSettings::new(20, 20, Method::Sphere).unwrap();
    let sync = SyncSettings::default();
    // Edit: move every third primitive (its translation, parameter slot 1),
    // keeping the node words (the structure) as they are.
    let (nodes, mut params) = original.clone().into_raw();
    let r = original.as_ref();
    for i in original.primitive_indices().into_iter().step_by(3) {
        let at = r.offset(i).unwrap() as usize * 4 + 4;
        params[at] += 0.04;
        params[at + 1] -= 0.03;
    }
    let edited = FlatBlobtree::from_raw(nodes, params).unwrap();
    // `render_sync` recomputes the ABVs and the A-buffer from the data.
    let (a, _) = render_sync(&edited, &camera, bounds, &settings, &sync).unwrap();
    let fresh = FlatBlobtree::from_node(&edited.to_node::<f64>().unwrap()).unwrap();
    let (b, _) = render_sync(&fresh, &camera, bounds, &settings, &sync).unwrap();
    let full = render(&edited.as_ref(), &camera, bounds, &settings).unwrap();
    assert_same(&a, &b, "edited vs fresh build");
    assert_same(&a, &full, "edited vs full tree");
    // The edit changed the image.
    let (before, _) = render_sync(original, &camera, bounds, &settings, &sync).unwrap();
    let changed = (0..20)
        .flat_map(|y| (0..20).map(move |x| (x, y)))
        .filter(|&(x, y)| before.depth(x, y) != a.depth(x, y))
        .count();
    assert!(changed > 10, "only {changed} pixels changed");
}
