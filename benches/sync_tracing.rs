//! Synchronized tracing (synchronized-tracing paper §6, Alg. 3) against
//! full-tree evaluation with the same method (`sphere`), on the same image
//! of the `aggregate-N` scenes (10, 110, 1,110 primitives): a 16×16 view
//! zoomed on the scene's centre, 8×8 tiles, `M_overlap = 128`.
//!
//! Per scene (group `sync_aggregate_N`):
//! - `full`: [`render`] of the full tree (every node per evaluation);
//! - `sync`: [`render_sync`] (ABVs + tile A-buffer + ray processing);
//! - `abuffer`: ABVs + A-buffer only (paper Fig. 20's first step).
//!
//! `aggregate-4` (11,110 primitives) is measured by `sync` and `abuffer`
//! only: a full-tree render takes minutes (see the `sync_stats` example and
//! BENCHMARKS.md for its full-versus-synchronized ratio).
//!
//! Run with `cargo bench --bench sync_tracing`; compare lines of one group
//! as ratios.

use boundtrace::tracer::Method;
use boundtrace::tracer::camera::Camera;
use boundtrace::tracer::render::{RenderSettings, render};
use boundtrace::tracer::scenes::{DEFAULT_SEED, Scene, SceneField};
use boundtrace::tracer::sync_render::{SyncSettings, render_sync};
use boundtrace::tracer::tiles::{ABuffer, TileGrid};
use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::time::Duration;

const SIZE: u32 = 16;

fn bench(c: &mut Criterion) {
    for level in 1..=4u32 {
        let name = format!("aggregate-{level}");
        let scene: Scene<f64> = Scene::build(&name, DEFAULT_SEED).unwrap();
        let SceneField::Blobtree(tree) = scene.field() else {
            unreachable!("aggregate scenes are blobtrees")
        };
        let bounds = scene.bounds();
        let camera = Camera::framing(bounds, [-0.3, -0.4, -1.0], 20.0, 1.0).unwrap();
        let settings = RenderSettings::new(SIZE, SIZE, Method::Sphere).unwrap();
        let sync = SyncSettings::default();
        let mut g = c.benchmark_group(format!("sync_aggregate_{level}"));
        g.sample_size(10).measurement_time(Duration::from_secs(3));
        if level <= 3 {
            g.bench_function("full", |b| {
                b.iter(|| render(&tree.as_ref(), &camera, bounds, black_box(&settings)).unwrap())
            });
        }
        g.bench_function("sync", |b| {
            b.iter(|| render_sync(tree, &camera, bounds, black_box(&settings), &sync).unwrap())
        });
        let grid = TileGrid::new(SIZE, SIZE, sync.tile_size).unwrap();
        g.bench_function("abuffer", |b| {
            b.iter(|| {
                let abvs = tree.abvs::<f64>();
                ABuffer::build(&camera, grid, bounds, black_box(&abvs)).unwrap()
            })
        });
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
