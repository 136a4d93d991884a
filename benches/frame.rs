//! Whole frames on the CPU (issue 12): a full-frame render single- and
//! multi-threaded, the tile A-buffer build of synchronized tracing, and
//! slicing on a small grid.
//!
//! - group `frame/<scene>:<method>` (32×32 pixels, perspective camera
//!   framing the scene, opaque, default parameters, `f64`): `serial`
//!   ([`render_serial`], one thread) and `parallel` ([`render`] on rayon's
//!   pool, every core; only with `--features parallel`, otherwise the same
//!   as `serial` and left out). The images are identical (the renderer
//!   guarantees it), so the ratio is the parallel speed-up.
//! - group `abuffer/<scene>` (128×128 pixels, 8×8 tiles): `abvs` (ROI
//!   propagation, [`FlatBlobtree::abvs`]) and `build` ([`ABuffer::build`]
//!   from the ABVs) of the `aggregate-N` blobtrees.
//! - group `slice/scalis-tree` (32×32×32 voxels): the column classifier
//!   [`slice_scalis`] against per-voxel sampling [`sample_scalis`] (the
//!   baseline of thesis Table 2.1).
//!
//! Run with `cargo bench --features parallel --bench frame`; compare lines
//! of one group as ratios.

use boundtrace::fields::blobtree::FlatBlobtree;
use boundtrace::tracer::camera::Camera;
use boundtrace::tracer::render::{RenderSettings, render, render_serial};
use boundtrace::tracer::scenes::{DEFAULT_SEED, Scene, SceneField};
use boundtrace::tracer::slice::{SliceSettings, sample_scalis, slice_scalis};
use boundtrace::tracer::tiles::{ABuffer, TileGrid};
use boundtrace::tracer::{Method, Params};
use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;

mod timing;
use timing::times;

/// Frame side in pixels.
const SIZE: u32 = 32;

fn frames(c: &mut Criterion) {
    let cases = [
        ("blobs", Method::Segment),
        ("blobs", Method::QuadraticTaylor),
        ("hrbf-17", Method::Interval),
        ("aggregate-1", Method::Sphere),
    ];
    for (name, method) in cases {
        let scene: Scene<f64> = Scene::build(name, DEFAULT_SEED).unwrap();
        let bounds = scene.bounds();
        let camera = Camera::framing(bounds, [-0.3, -0.4, -1.0], 40.0, 1.0).unwrap();
        let settings = RenderSettings::new(SIZE, SIZE, method).unwrap();
        let field = scene.field();
        let mut g = c.benchmark_group(format!("frame/{name}:{method}"));
        g.sample_size(10)
            .warm_up_time(times(500, 3000).0)
            .measurement_time(times(500, 3000).1);
        g.bench_function("serial", |b| {
            b.iter(|| render_serial(field, &camera, bounds, black_box(&settings)).unwrap())
        });
        if cfg!(feature = "parallel") {
            g.bench_function("parallel", |b| {
                b.iter(|| render(field, &camera, bounds, black_box(&settings)).unwrap())
            });
        }
        g.finish();
    }
}

fn abuffers(c: &mut Criterion) {
    for level in 1..=4u32 {
        let name = format!("aggregate-{level}");
        let scene: Scene<f64> = Scene::build(&name, DEFAULT_SEED).unwrap();
        let SceneField::Blobtree(tree) = scene.field() else {
            unreachable!("aggregate scenes are blobtrees")
        };
        let tree: &FlatBlobtree = tree;
        let bounds = scene.bounds();
        let camera = Camera::framing(bounds, [-0.3, -0.4, -1.0], 40.0, 1.0).unwrap();
        let grid = TileGrid::new(128, 128, 8).unwrap();
        let abvs = tree.abvs::<f64>();
        let mut g = c.benchmark_group(format!("abuffer/{name}"));
        g.sample_size(10)
            .warm_up_time(times(300, 2000).0)
            .measurement_time(times(300, 2000).1);
        g.bench_function("abvs", |b| b.iter(|| black_box(tree).abvs::<f64>()));
        g.bench_function("build", |b| {
            b.iter(|| ABuffer::build(&camera, grid, bounds, black_box(&abvs)).unwrap())
        });
        g.finish();
    }
}

fn slicing(c: &mut Criterion) {
    let scene: Scene<f64> = Scene::build("scalis-tree", DEFAULT_SEED).unwrap();
    let SceneField::Scalis(w) = scene.field() else {
        unreachable!("scalis-tree is a SCALIS skeleton")
    };
    let settings = SliceSettings {
        width: 32,
        height: 32,
        slices: 32,
    };
    let params = Params::new();
    let bounds = scene.bounds();
    let mut g = c.benchmark_group("slice/scalis-tree");
    g.sample_size(10)
        .warm_up_time(times(300, 2000).0)
        .measurement_time(times(300, 2000).1);
    g.bench_function("sample", |b| {
        b.iter(|| sample_scalis(w.field(), bounds, black_box(settings), &params).unwrap())
    });
    g.bench_function("classify", |b| {
        b.iter(|| slice_scalis(w.field(), bounds, black_box(settings), &params).unwrap())
    });
    g.finish();
}

criterion_group!(benches, frames, abuffers, slicing);
criterion_main!(benches);
