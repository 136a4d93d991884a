//! Frame comparison for the blobtree tracing tests (`tracer_sync`,
//! `tracer_tile_programs`): a faster way of tracing the same tree against
//! full-tree evaluation. Small on purpose (no proptest, no reference
//! arithmetic), so those tests include it alone with `#[path]`.

use boundtrace::fields::blobtree::FlatBlobtree;
use boundtrace::tracer::render::Frame;
use boundtrace::tracer::scenes::{Scene, SceneField};

/// Asserts that `a` (the faster way) equals `b` (the full tree) on every
/// pixel: the same number of roots, each of the same side, depths within
/// `1e-4` relative, normals within 0.999 in cosine, and the same trace
/// status. Returns the number of roots compared; `what` names the case in
/// a failure.
pub fn assert_same(a: &Frame<f64>, b: &Frame<f64>, what: &str) -> usize {
    assert_eq!(
        (a.width(), a.height()),
        (b.width(), b.height()),
        "{what}: frame sizes"
    );
    let mut roots = 0;
    for y in 0..a.height() {
        for x in 0..a.width() {
            let (ha, hb) = (a.hits(x, y), b.hits(x, y));
            assert_eq!(
                ha.len(),
                hb.len(),
                "{what}: pixel ({x}, {y}) roots {ha:?} vs full {hb:?}"
            );
            for (p, q) in ha.iter().zip(hb) {
                roots += 1;
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
    roots
}

/// The flat blobtree of a blobtree scene (panics on another scene: a test
/// error).
pub fn tree(scene: &Scene<f64>) -> &FlatBlobtree {
    match scene.field() {
        SceneField::Blobtree(t) => t,
        _ => panic!("{} is not a blobtree scene", scene.name()),
    }
}
