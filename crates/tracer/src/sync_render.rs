//! Rendering a flat blobtree by synchronized tracing (synchronized-tracing
//! paper §6, Fig. 3): the A-buffer step ([`ABuffer::build`]) then the
//! per-tile ray processing ([`trace_tile`]), producing the same [`Frame`]
//! as [`render`](crate::render::render).
//!
//! Roots are found with the pruned field of the range they lie in, and
//! their normals are taken from that field too (near the surface it equals
//! the full field: every primitive whose ABV contains the point is
//! active). The images equal full-evaluation images up to the tracer's
//! `eps` (different steps reach the same roots); the equivalence tests in
//! `tests/tracer_sync.rs` check hit/miss identity and depths.
//!
//! With the `parallel` feature tiles (and the A-buffer build) run on
//! rayon's pool; each tile is computed by the same code from the same
//! inputs, so the frame does not depend on the number of threads.
//!
//! ```
//! use boundtrace_fields::blobtree::{FlatBlobtree, Node};
//! use boundtrace_fields::{Operator, Primitive};
//! use boundtrace_tracer::camera::Camera;
//! use boundtrace_tracer::render::{RenderSettings, render};
//! use boundtrace_tracer::sync_render::{SyncSettings, render_sync};
//! use boundtrace_tracer::Method;
//!
//! let s = |x: f64| Node::primitive(Primitive::sphere([x, 0.0, 0.0], 0.3).unwrap());
//! let u = Operator::compact_union(0.1, 0.2)?;
//! let tree = FlatBlobtree::from_node(&Node::op(u, Node::op(u, s(-0.5), s(0.0)), s(0.5)))?;
//! let bounds = [[-1.0; 3], [1.0; 3]];
//! let camera = Camera::framing(bounds, [0.0, 0.0, -1.0], 40.0, 1.0)?;
//! let settings = RenderSettings::new(16, 16, Method::Sphere)?;
//! let (frame, report) = render_sync(&tree, &camera, bounds, &settings, &SyncSettings::default())?;
//! let full = render(&tree.as_ref(), &camera, bounds, &settings)?;
//! for y in 0..16 {
//!     for x in 0..16 {
//!         assert_eq!(frame.depth(x, y).is_some(), full.depth(x, y).is_some());
//!     }
//! }
//! assert!(report.counters.views > 0 && report.counters.overflow_ranges == 0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::camera::Camera;
use crate::method::Mode;
use crate::render::{Frame, Hit, Pixel, RenderError, RenderSettings, Row, assemble, check};
use crate::sync::{
    InvalidSyncConfig, SyncConfig, SyncCounters, TileBuffers, TileJob, TileRay, empty_root,
    trace_tile,
};
use crate::tiles::{ABuffer, DEFAULT_TILE_SIZE, TileError, TileGrid};
use boundtrace_fields::blobtree::{BlobtreeRef, FlatBlobtree};
use boundtrace_ia_core::Real;
use core::fmt;
use std::time::{Duration, Instant};

/// Tile size and synchronization settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SyncSettings {
    /// Tile side in pixels (default [`DEFAULT_TILE_SIZE`] = 8).
    pub tile_size: u32,
    /// `M_overlap` and the fetch heuristic.
    pub config: SyncConfig,
}

impl Default for SyncSettings {
    fn default() -> Self {
        Self {
            tile_size: DEFAULT_TILE_SIZE,
            config: SyncConfig::default(),
        }
    }
}

/// Invalid input of synchronized rendering.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SyncError {
    /// Invalid render settings or bounds.
    Render(RenderError),
    /// Invalid tiling.
    Tiles(TileError),
    /// Invalid [`SyncConfig`].
    Config(InvalidSyncConfig),
    /// The A-buffer was built for another image size.
    GridMismatch,
}

impl fmt::Display for SyncError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SyncError::Render(e) => write!(f, "{e}"),
            SyncError::Tiles(e) => write!(f, "{e}"),
            SyncError::Config(e) => write!(f, "{e}"),
            SyncError::GridMismatch => {
                f.write_str("synchronized rendering: the A-buffer was built for another image size")
            }
        }
    }
}

impl std::error::Error for SyncError {}

impl From<RenderError> for SyncError {
    fn from(e: RenderError) -> Self {
        SyncError::Render(e)
    }
}

impl From<TileError> for SyncError {
    fn from(e: TileError) -> Self {
        SyncError::Tiles(e)
    }
}

/// What [`render_sync`] did and how long each step took (paper Fig. 20).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SyncReport {
    /// Computing the ABVs (ROI propagation, [`FlatBlobtree::abvs`]).
    pub abvs_time: Duration,
    /// Building the tile A-buffer.
    pub abuffer_time: Duration,
    /// Ray processing (every tile).
    pub trace_time: Duration,
    /// A-buffer fragments in all.
    pub entries: usize,
    /// The largest number of fragments of one tile.
    pub max_tile_entries: usize,
    /// Counters of the ray processing.
    pub counters: SyncCounters,
}

/// Renders `tree` by synchronized tracing: ABVs, the tile A-buffer, then
/// [`render_tiles`]; with the time of each step.
///
/// # Errors
/// Invalid settings, bounds, tile size or [`SyncConfig`].
pub fn render_sync<T: Real + Send + Sync>(
    tree: &FlatBlobtree,
    camera: &Camera<T>,
    bounds: [[T; 3]; 2],
    settings: &RenderSettings<T>,
    sync: &SyncSettings,
) -> Result<(Frame<T>, SyncReport), SyncError> {
    check(&bounds, settings)?;
    sync.config.validate().map_err(SyncError::Config)?;
    let grid = TileGrid::new(settings.width, settings.height, sync.tile_size)?;
    let t = Instant::now();
    let abvs = tree.abvs::<T>();
    let abvs_time = t.elapsed();
    let t = Instant::now();
    let ab = ABuffer::build(camera, grid, bounds, &abvs)?;
    let abuffer_time = t.elapsed();
    let t = Instant::now();
    let (frame, counters) =
        render_tiles(tree.as_ref(), &ab, camera, bounds, settings, &sync.config)?;
    let trace_time = t.elapsed();
    Ok((
        frame,
        SyncReport {
            abvs_time,
            abuffer_time,
            trace_time,
            entries: ab.entries().len(),
            max_tile_entries: ab.max_tile_len(),
            counters,
        },
    ))
}

/// The ray-processing step: every tile of `abuffer` traced by
/// [`trace_tile`] (in parallel with the `parallel` feature), assembled into
/// a [`Frame`] like [`render`](crate::render::render)'s.
///
/// # Errors
/// Invalid settings or bounds, an invalid `config`, or an A-buffer built
/// for another image size ([`SyncError::GridMismatch`]).
pub fn render_tiles<T: Real + Send + Sync>(
    tree: BlobtreeRef<'_>,
    abuffer: &ABuffer<T>,
    camera: &Camera<T>,
    bounds: [[T; 3]; 2],
    settings: &RenderSettings<T>,
    config: &SyncConfig,
) -> Result<(Frame<T>, SyncCounters), SyncError> {
    check(&bounds, settings)?;
    config.validate().map_err(SyncError::Config)?;
    let grid = *abuffer.grid();
    if grid.width != settings.width || grid.height != settings.height {
        return Err(SyncError::GridMismatch);
    }
    let run = |i: usize| run_tile(tree, abuffer, i, camera, &bounds, settings, config);
    #[cfg(feature = "parallel")]
    let tiles: Vec<TileOut<T>> = {
        use rayon::prelude::*;
        (0..grid.tile_count()).into_par_iter().map(run).collect()
    };
    #[cfg(not(feature = "parallel"))]
    let tiles: Vec<TileOut<T>> = (0..grid.tile_count()).map(run).collect();
    let mut counters = SyncCounters::default();
    for t in &tiles {
        counters = counters + t.counters;
    }
    let ts = grid.tile_size;
    let rows = (0..grid.height)
        .map(|y| {
            let mut row = Row {
                pixels: Vec::with_capacity(grid.width as usize),
                hits: Vec::new(),
            };
            for x in 0..grid.width {
                let i = ((y / ts) * grid.tiles_x + x / ts) as usize;
                let (xs, ys) = grid.pixels(i);
                let k = ((y - ys[0]) * (xs[1] - xs[0]) + (x - xs[0])) as usize;
                let tile = &tiles[i];
                let p = tile.pixels[k];
                let start = tile.hit_start[k];
                row.hits
                    .extend_from_slice(&tile.hits[start..start + p.trace.roots as usize]);
                row.pixels.push(p);
            }
            row
        })
        .collect();
    Ok((assemble(*camera, *settings, rows), counters))
}

/// One tile's pixels (row-major within the tile), hits and counters.
struct TileOut<T> {
    pixels: Vec<Pixel<T>>,
    hits: Vec<Hit<T>>,
    hit_start: Vec<usize>,
    counters: SyncCounters,
}

fn run_tile<T: Real>(
    tree: BlobtreeRef<'_>,
    abuffer: &ABuffer<T>,
    i: usize,
    camera: &Camera<T>,
    bounds: &[[T; 3]; 2],
    settings: &RenderSettings<T>,
    config: &SyncConfig,
) -> TileOut<T> {
    let grid = abuffer.grid();
    let (xs, ys) = grid.pixels(i);
    let size = [grid.width, grid.height];
    let mut rays = Vec::with_capacity(((xs[1] - xs[0]) * (ys[1] - ys[0])) as usize);
    for py in ys[0]..ys[1] {
        for px in xs[0]..xs[1] {
            rays.push(TileRay::new(camera, [px, py], size, bounds));
        }
    }
    let rpr = match settings.mode {
        Mode::Opaque => 1,
        Mode::Transparent => settings.max_roots as usize,
    };
    let n = rays.len();
    let mut roots = vec![empty_root::<T>(); n * rpr];
    let mut normals = vec![[T::ZERO; 3]; n * rpr];
    let m = config.m_overlap as usize;
    let mut active = vec![0u32; m];
    let mut nodes = vec![0u32; m];
    let job = TileJob {
        tree,
        entries: abuffer.tile(i),
        method: settings.method,
        mode: settings.mode,
        params: settings.params,
        config: *config,
    };
    let counters = trace_tile(
        &job,
        &mut TileBuffers {
            rays: &mut rays,
            roots: &mut roots,
            normals: &mut normals,
            roots_per_ray: rpr,
            active: &mut active,
            nodes: &mut nodes,
        },
    );
    let mut out = TileOut {
        pixels: Vec::with_capacity(n),
        hits: Vec::new(),
        hit_start: Vec::with_capacity(n),
        counters,
    };
    for (k, r) in rays.iter().enumerate() {
        out.hit_start.push(out.hits.len());
        let got = (r.trace.roots as usize).min(rpr);
        for j in 0..got {
            let root = roots[k * rpr + j];
            out.hits.push(Hit {
                t: root.t,
                side: root.side,
                normal: normals[k * rpr + j],
            });
        }
        out.pixels.push(Pixel {
            span: r.span,
            trace: crate::trace::Trace {
                roots: got as u32,
                ..r.trace
            },
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::method::Method;
    use boundtrace_fields::blobtree::Node;
    use boundtrace_fields::{Operator, Primitive};

    #[test]
    fn bad_input_is_refused() {
        let s = Node::primitive(Primitive::sphere([0.0, 0.0, 0.0], 0.3).unwrap());
        let tree = FlatBlobtree::from_node(&s).unwrap();
        let bounds = [[-1.0; 3], [1.0; 3]];
        let cam = Camera::framing(bounds, [0.0, 0.0, -1.0], 40.0, 1.0).unwrap();
        let st = RenderSettings::new(8, 8, Method::Sphere).unwrap();
        let bad_tile = SyncSettings {
            tile_size: 0,
            ..SyncSettings::default()
        };
        assert_eq!(
            render_sync(&tree, &cam, bounds, &st, &bad_tile).err(),
            Some(SyncError::Tiles(TileError::TileSize))
        );
        let bad_m = SyncSettings {
            config: SyncConfig {
                m_overlap: 0,
                max_fetch: 8,
            },
            ..SyncSettings::default()
        };
        assert!(matches!(
            render_sync(&tree, &cam, bounds, &st, &bad_m),
            Err(SyncError::Config(_))
        ));
        let ab =
            ABuffer::build(&cam, TileGrid::new(4, 4, 8).unwrap(), bounds, &tree.abvs()).unwrap();
        assert_eq!(
            render_tiles(
                tree.as_ref(),
                &ab,
                &cam,
                bounds,
                &st,
                &SyncConfig::default()
            )
            .err(),
            Some(SyncError::GridMismatch)
        );
    }

    #[test]
    fn transparent_mode_registers_boundary_roots_once() {
        // Two separate spheres along the view: four roots per central ray,
        // with ranges cut between and inside them; two ABVs overlap in depth
        // (an overflow for M = 1).
        let s = |z: f64| Node::primitive(Primitive::sphere([0.0, 0.0, z], 0.3).unwrap());
        let u = Operator::compact_union(0.05, 0.1).unwrap();
        let small = Node::primitive(Primitive::sphere([0.0, 0.0, -0.35], 0.2).unwrap());
        let tree =
            FlatBlobtree::from_node(&Node::op(u, Node::op(u, s(-0.5), small), s(0.5))).unwrap();
        let bounds = [[-1.0f64; 3], [1.0; 3]];
        let cam = Camera::framing(bounds, [0.0, 0.0, -1.0], 40.0, 1.0).unwrap();
        let st = RenderSettings::new(9, 9, Method::Segment)
            .unwrap()
            .with_mode(Mode::Transparent);
        for m in [1, 2, 128] {
            let sync = SyncSettings {
                tile_size: 3,
                config: SyncConfig {
                    m_overlap: m,
                    max_fetch: 0,
                },
            };
            let (frame, report) = render_sync(&tree, &cam, bounds, &st, &sync).unwrap();
            let full = crate::render::render(&tree.as_ref(), &cam, bounds, &st).unwrap();
            assert_eq!(frame.hits(4, 4).len(), 4, "M = {m}");
            for y in 0..9 {
                for x in 0..9 {
                    let (a, b) = (frame.hits(x, y), full.hits(x, y));
                    assert_eq!(a.len(), b.len(), "({x}, {y}) M = {m}");
                    for (h, g) in a.iter().zip(b) {
                        assert_eq!(h.side, g.side);
                        assert!((h.t - g.t).abs() <= 2.0 * st.params.eps);
                    }
                }
            }
            if m == 1 {
                assert!(report.counters.overflow_ranges > 0);
            }
        }
    }

    #[test]
    fn a_view_needing_too_much_stack_falls_back_to_the_full_tree() {
        // A right comb of 12 overlapping spheres: its pruned view needs an
        // evaluation stack of 12 > VIEW_STACK = 8, so the view is refused and
        // the range is traced with the full tree (counted), same image.
        let u = Operator::compact_union(0.05, 0.1).unwrap();
        let mut node = Node::primitive(Primitive::sphere([0.55, 0.0, 0.0], 0.2).unwrap());
        for k in (0..11).rev() {
            let x = -0.55 + 0.1 * k as f64;
            let s =
                Node::primitive(Primitive::sphere([x, 0.05 * k as f64 - 0.2, 0.0], 0.2).unwrap());
            node = Node::op(u, s, node);
        }
        let tree = FlatBlobtree::from_node(&node).unwrap();
        assert!(tree.stack_need() > 8);
        let bounds = [[-1.0f64; 3], [1.0; 3]];
        let cam = Camera::framing(bounds, [0.0, 0.0, -1.0], 40.0, 1.0).unwrap();
        let st = RenderSettings::new(12, 12, Method::Sphere).unwrap();
        let sync = SyncSettings {
            tile_size: 12,
            ..SyncSettings::default()
        };
        let (frame, report) = render_sync(&tree, &cam, bounds, &st, &sync).unwrap();
        assert!(report.counters.view_failures > 0, "{:?}", report.counters);
        let full = crate::render::render(&tree.as_ref(), &cam, bounds, &st).unwrap();
        let mut hits = 0;
        for y in 0..12 {
            for x in 0..12 {
                let (a, b) = (frame.depth(x, y), full.depth(x, y));
                assert_eq!(a.is_some(), b.is_some(), "({x}, {y})");
                if let (Some(a), Some(b)) = (a, b) {
                    assert!((a - b).abs() <= 2.0 * st.params.eps);
                    hits += 1;
                }
            }
        }
        assert!(hits > 0);
    }

    #[test]
    fn f32_frames_match_the_full_tree() {
        // The GPU's number type: f32 depths in the A-buffer, f32 tracing.
        let s = |x: f64, y: f64| Node::primitive(Primitive::sphere([x, y, 0.1 * x], 0.25).unwrap());
        let u = Operator::compact_union(0.08, 0.16).unwrap();
        let tree = FlatBlobtree::from_node(&Node::op(
            u,
            Node::op(u, s(-0.4, 0.0), s(0.0, 0.2)),
            Node::op(u, s(0.4, 0.0), s(0.1, -0.4)),
        ))
        .unwrap();
        let bounds = [[-1.0f32; 3], [1.0; 3]];
        let cam = Camera::framing(bounds, [0.2, -0.1, -1.0], 40.0, 1.0).unwrap();
        for method in [Method::Sphere, Method::Segment, Method::QuadraticMixed] {
            let st = RenderSettings::<f32>::new(16, 16, method).unwrap();
            let (frame, _) =
                render_sync(&tree, &cam, bounds, &st, &SyncSettings::default()).unwrap();
            let full = crate::render::render(&tree.as_ref(), &cam, bounds, &st).unwrap();
            let mut hits = 0;
            for y in 0..16 {
                for x in 0..16 {
                    let (a, b) = (frame.depth(x, y), full.depth(x, y));
                    assert_eq!(a.is_some(), b.is_some(), "{method} ({x}, {y})");
                    if let (Some(a), Some(b)) = (a, b) {
                        assert!((a - b).abs() <= 1e-4 * b.abs() + 2.0 * st.params.eps);
                        hits += 1;
                    }
                }
            }
            assert!(hits > 10, "{method}: {hits} hits");
        }
    }
}
