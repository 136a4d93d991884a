//! Per-tile blobtree programs (`tracer::tile_programs`, the GPU's tiled
//! dispatch) against full-tree evaluation on the standard blobtree
//! scenes: the same roots per pixel (count and side), depths within
//! `1e-4` relative, the same normals, the same trace status, by sphere
//! tracing in both modes; and the programs are smaller than the tree.

use boundtrace::tracer::camera::Camera;
use boundtrace::tracer::render::{RenderSettings, render_serial};
use boundtrace::tracer::scenes::{DEFAULT_SEED, Scene};
use boundtrace::tracer::tile_programs::{TileProgramError, TilePrograms, render_tile_programs};
use boundtrace::tracer::{Method, Mode};

#[path = "common/frames.rs"]
mod frames;
use frames::{assert_same, tree};

/// Renders `name` both ways at `size²` pixels (vertical field of view
/// `fov` degrees, looking at the scene's centre) in both modes.
fn compare(name: &str, size: u32, fov: f64) {
    let scene: Scene<f64> = Scene::build(name, DEFAULT_SEED).unwrap();
    let flat = tree(&scene);
    let bounds = scene.bounds();
    let camera = Camera::framing(bounds, [-0.3, -0.4, -1.0], fov, 1.0).unwrap();
    let programs = TilePrograms::build(flat, &camera, bounds, size, size).unwrap();
    assert_eq!(
        programs.grid().tile_count(),
        size.div_ceil(8).pow(2) as usize
    );
    assert!(
        programs.mean_nodes() < flat.len() as f64,
        "{name}: tiles of {:.1} nodes on average, tree {}",
        programs.mean_nodes(),
        flat.len()
    );
    for mode in [Mode::Opaque, Mode::Transparent] {
        let settings = RenderSettings::new(size, size, Method::Sphere)
            .unwrap()
            .with_mode(mode);
        let a = render_tile_programs(&programs, flat.as_ref(), &camera, bounds, &settings).unwrap();
        let b = render_serial(&flat.as_ref(), &camera, bounds, &settings).unwrap();
        let roots = assert_same(&a, &b, &format!("{name} {mode:?}"));
        eprintln!(
            "{name} {mode:?}: {roots} roots agree; tiles of {:.1} nodes on average \
             (max {}, {} whole), tree {}",
            programs.mean_nodes(),
            programs.max_nodes(),
            programs.whole_tiles(),
            flat.len()
        );
        assert!(roots > 0, "{name}: nothing hit");
    }
}

#[test]
fn tile_programs_match_the_full_tree_on_small_aggregates() {
    for name in [
        "aggregate-1",
        "aggregate-1-smooth",
        "aggregate-2",
        "aggregate-2-smooth",
    ] {
        compare(name, 24, 40.0);
    }
}

#[test]
fn tile_programs_match_the_full_tree_on_aggregate_3() {
    for name in ["aggregate-3", "aggregate-3-smooth"] {
        compare(name, 16, 40.0);
    }
}

#[test]
fn tile_programs_refuse_another_image_size() {
    let scene: Scene<f64> = Scene::build("aggregate-1", DEFAULT_SEED).unwrap();
    let flat = tree(&scene);
    let bounds = scene.bounds();
    let camera = Camera::framing(bounds, [0.0, 0.0, -1.0], 40.0, 1.0).unwrap();
    let programs = TilePrograms::build(flat, &camera, bounds, 16, 16).unwrap();
    let settings = RenderSettings::new(24, 16, Method::Sphere).unwrap();
    let r = render_tile_programs(&programs, flat.as_ref(), &camera, bounds, &settings);
    assert_eq!(r.unwrap_err(), TileProgramError::SizeMismatch);
    assert!(matches!(
        TilePrograms::build(flat, &camera, bounds, 0, 16),
        Err(TileProgramError::Tiles(_))
    ));
}

/// Each tile's Lipschitz bound (computed in `f32` from its program when
/// the programs are built) holds between sampled points of the scene
/// box, for the tile's field, within `f32` rounding of the bound.
#[test]
fn tile_lipschitz_bounds_hold_between_sampled_points() {
    use boundtrace::inclusion::Field;
    let mut state = 0x7153_u64;
    let mut unit = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut checked = 0;
    for name in ["aggregate-2", "aggregate-2-smooth", "aggregate-3"] {
        let scene: Scene<f64> = Scene::build(name, DEFAULT_SEED).unwrap();
        let flat = tree(&scene);
        let [lo, hi] = scene.bounds();
        let camera = Camera::framing([lo, hi], [-0.3, -0.4, -1.0], 40.0, 1.0).unwrap();
        let programs = TilePrograms::build(flat, &camera, [lo, hi], 24, 24).unwrap();
        for ty in 0..3 {
            for tx in 0..3 {
                let f = programs.field(flat.params(), tx * 8, ty * 8);
                if f.is_empty() {
                    continue;
                }
                let l: f64 = f.lipschitz().unwrap();
                assert!(l > 0.0 && l.is_finite(), "{name} tile ({tx}, {ty}): {l}");
                for _ in 0..200 {
                    let p = [0, 1, 2].map(|k| lo[k] + unit() * (hi[k] - lo[k]));
                    let d = [0, 1, 2].map(|_| (unit() - 0.5) * 0.04);
                    let q = [0, 1, 2].map(|k| p[k] + d[k]);
                    let (fp, fq): (f64, f64) = (f.eval(p), f.eval(q));
                    let dist = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    assert!(
                        (fp - fq).abs() <= l * dist * (1.0 + 1e-6) + 1e-12,
                        "{name} tile ({tx}, {ty}): |Δf| = {} > L·|Δp| = {}",
                        (fp - fq).abs(),
                        l * dist
                    );
                    checked += 1;
                }
            }
        }
    }
    assert!(checked >= 2000, "{checked}");
}
