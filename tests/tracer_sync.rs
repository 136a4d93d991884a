//! Synchronized tracing (issue 8) against full-tree evaluation on every
//! standard blobtree scene: the same hits and misses, depths within
//! `1e-4` relative, the same normals, for `sphere` and `quadratic-mixed`
//! (plus every method in both modes on a small scene), at a small resolution; and
//! an edit of primitive parameters (not structure) followed by new ABVs and
//! a new A-buffer renders like a fresh build.
//!
//! `aggregate-3*`/`aggregate-4*` are compared on a few tiles only (their
//! full-tree evaluation is what synchronized tracing avoids: 11,110
//! primitives per evaluation).

use boundtrace::fields::blobtree::FlatBlobtree;
use boundtrace::tracer::camera::Camera;
use boundtrace::tracer::render::{Frame, RenderSettings, render};
use boundtrace::tracer::scenes::{DEFAULT_SEED, NAMES, Scene, SceneField};
use boundtrace::tracer::sync_render::{SyncSettings, render_sync};
use boundtrace::tracer::{Method, Mode};

/// Asserts `a` (synchronized) equals `b` (full tree) within the issue's
/// tolerances; returns the number of hit pixels.
fn assert_same(a: &Frame<f64>, b: &Frame<f64>, what: &str) -> usize {
    let mut hits = 0;
    for y in 0..a.height() {
        for x in 0..a.width() {
            let (ha, hb) = (a.hits(x, y), b.hits(x, y));
            assert_eq!(
                ha.len(),
                hb.len(),
                "{what}: pixel ({x}, {y}) roots {ha:?} vs full {hb:?}"
            );
            for (p, q) in ha.iter().zip(hb) {
                hits += 1;
                assert_eq!(p.side, q.side, "{what}: pixel ({x}, {y})");
                assert!(
                    (p.t - q.t).abs() <= 1e-4 * q.t.abs(),
                    "{what}: pixel ({x}, {y}) depth {} vs full {}",
                    p.t,
                    q.t
                );
                let dot: f64 = (0..3).map(|i| p.normal[i] * q.normal[i]).sum();
                assert!(
                    dot > 0.999,
                    "{what}: pixel ({x}, {y}) normals {p:?} vs {q:?}"
                );
            }
            let (sa, sb) = (a.pixel(x, y).unwrap(), b.pixel(x, y).unwrap());
            assert_eq!(sa.trace.status, sb.trace.status, "{what}: pixel ({x}, {y})");
        }
    }
    hits
}

fn tree(scene: &Scene<f64>) -> &FlatBlobtree {
    match scene.field() {
        SceneField::Blobtree(t) => t,
        _ => unreachable!("not a blobtree scene"),
    }
}

/// Renders `name` both ways at `size²` pixels (a `crop` of the image's
/// central tiles when the full tree is too slow to render in full).
fn compare(name: &str, size: u32, method: Method, mode: Mode) {
    let scene: Scene<f64> = Scene::build(name, DEFAULT_SEED).unwrap();
    let flat = tree(&scene);
    let bounds = scene.bounds();
    let camera = Camera::framing(bounds, [-0.3, -0.4, -1.0], 25.0, 1.0).unwrap();
    let settings = RenderSettings::new(size, size, method)
        .unwrap()
        .with_mode(mode);
    let sync = SyncSettings::default();
    let (a, report) = render_sync(flat, &camera, bounds, &settings, &sync).unwrap();
    let b = render(&flat.as_ref(), &camera, bounds, &settings).unwrap();
    let what = format!("{name} × {method} × {mode:?}");
    let hits = assert_same(&a, &b, &what);
    if matches!(method, Method::LinearTaylor | Method::QuadraticTaylor) {
        // No Taylor bounds on a blobtree: nothing traced, both ways.
        assert_eq!(a.totals().unsupported, a.totals().box_rays, "{what}");
    } else {
        assert!(hits > 0, "{what}: no hit at all");
    }
    assert_eq!(report.counters.overflow_ranges, 0, "{what}");
    eprintln!("{what}: {hits} hits, {:?}", report.counters);
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

macro_rules! equivalence {
    ($($test:ident => $name:literal, $size:expr;)*) => {$(
        #[test]
        fn $test() {
            for method in [Method::Sphere, Method::QuadraticMixed] {
                compare($name, $size, method, Mode::Opaque);
            }
        }
    )*};
}

equivalence! {
    aggregate_1 => "aggregate-1", 32;
    aggregate_1_smooth => "aggregate-1-smooth", 32;
    aggregate_2 => "aggregate-2", 24;
    aggregate_2_smooth => "aggregate-2-smooth", 24;
    aggregate_3 => "aggregate-3", 16;
    aggregate_3_smooth => "aggregate-3-smooth", 16;
    aggregate_4 => "aggregate-4", 8;
    aggregate_4_smooth => "aggregate-4-smooth", 8;
}

#[test]
fn every_method_both_modes_on_aggregate_1_smooth() {
    for method in Method::ALL {
        for mode in [Mode::Opaque, Mode::Transparent] {
            compare("aggregate-1-smooth", 12, method, mode);
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
