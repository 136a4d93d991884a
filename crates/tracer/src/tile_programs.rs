//! Per-tile blobtree programs: the tile lists of the A-buffer
//! (synchronized-tracing paper §6, [`ABuffer`]) turned into one pruned
//! post-order program per 8 × 8 image tile, for the GPU's tiled dispatch
//! (one workgroup per tile, `boundtrace-gpu`) and its CPU twin
//! ([`render_tile_programs`]).
//!
//! A tile's program is the sparse traversal of the tree over every
//! primitive whose ABV meets the tile's pixel rays inside the scene bounds
//! (the union of the tile's A-buffer entries over depth): a
//! [`PrunedView`] of its nodes. Inside the tile's rays it has the full
//! tree's surface (the ABV property the synchronized tracer relies on),
//! with fewer nodes per evaluation. Unlike [`crate::sync_render`], the
//! program is the same along the whole ray (no per-depth ranges): one
//! upload, no per-ray bookkeeping on the GPU. Each tile carries its own
//! Lipschitz bound, that of its program. A tile whose program would need
//! more than [`MAX_TILE_NODES`] nodes or more than the interpreter's stack
//! uses the whole tree, stored once.
//!
//! The buffer ([`TilePrograms::words`]) is the layout of
//! [`BlobtreeWindow::tile`]: a table of [`TILE_TABLE_WORDS`] words per
//! tile (first node pair, node count, Lipschitz bits), padded to an even
//! length, then node pairs `(word, parameter offset)` whose offsets index
//! the tree's own parameters.
//!
//! ```
//! use boundtrace_tracer::camera::Camera;
//! use boundtrace_tracer::render::{RenderSettings, render_serial};
//! use boundtrace_tracer::scenes::{DEFAULT_SEED, Scene, SceneField};
//! use boundtrace_tracer::tile_programs::{TilePrograms, render_tile_programs};
//! use boundtrace_tracer::Method;
//!
//! let scene = Scene::<f32>::build("aggregate-2", DEFAULT_SEED)?;
//! let SceneField::Blobtree(tree) = scene.field() else { unreachable!() };
//! let camera = Camera::framing(scene.bounds(), [0.0, 0.0, -1.0], 40.0, 1.0)?;
//! let programs = TilePrograms::build(tree, &camera, scene.bounds(), 16, 16)?;
//! assert!(programs.max_nodes() < tree.len());
//! let settings = RenderSettings::new(16, 16, Method::Sphere)?;
//! let tiled = render_tile_programs(&programs, tree.as_ref(), &camera, scene.bounds(), &settings)?;
//! let full = render_serial(&tree.as_ref(), &camera, scene.bounds(), &settings)?;
//! let same = (0..16 * 16)
//!     .filter(|i| tiled.depth(i % 16, i / 16).is_some() == full.depth(i % 16, i / 16).is_some())
//!     .count();
//! assert!(same >= 255);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::camera::Camera;
use crate::render::{Frame, RenderError, RenderSettings, render_serial_with};
use crate::tiles::{ABuffer, TileError, TileGrid};
use boundtrace_fields::AllPrimitives;
use boundtrace_fields::blobtree::{
    BlobtreeRef, BlobtreeWindow, FlatBlobtree, PrunedView, STACK_CAPACITY, TILE_TABLE_WORDS,
};
use boundtrace_ia_core::Real;
use core::fmt;

/// Why tile programs could not be built or rendered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TileProgramError {
    /// The tile grid or A-buffer (an empty image, bad bounds, …).
    Tiles(TileError),
    /// The A-buffer's tiles are not [`TILE_SIZE`] pixels wide.
    TileSize(u32),
    /// The buffer would exceed `u32` indices.
    TooLarge,
    /// The programs were built for another image size than the render's.
    SizeMismatch,
    /// The render settings or bounds.
    Render(RenderError),
}

impl fmt::Display for TileProgramError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Tiles(e) => write!(f, "tile programs: {e}"),
            Self::TileSize(s) => write!(
                f,
                "tile programs: the A-buffer's tiles are {s} pixels wide, not {TILE_SIZE}"
            ),
            Self::TooLarge => f.write_str("tile programs: the buffer exceeds u32 indices"),
            Self::SizeMismatch => {
                f.write_str("tile programs: built for another image size than the render's")
            }
            Self::Render(e) => write!(f, "tile programs: {e}"),
        }
    }
}

impl std::error::Error for TileProgramError {}

impl From<TileError> for TileProgramError {
    fn from(e: TileError) -> Self {
        Self::Tiles(e)
    }
}

impl From<RenderError> for TileProgramError {
    fn from(e: RenderError) -> Self {
        Self::Render(e)
    }
}

/// The tile side in pixels: the GPU's workgroup side.
pub const TILE_SIZE: u32 = 8;

/// The most nodes a tile's own program may have; a larger one is the
/// whole tree's.
pub const MAX_TILE_NODES: usize = 4096;

/// The per-tile programs of one image size and camera (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct TilePrograms {
    grid: TileGrid,
    words: Vec<u32>,
    whole_tiles: usize,
    max_nodes: usize,
    total_nodes: usize,
}

impl TilePrograms {
    /// The programs of `tree` for a `width × height` image of `camera`
    /// inside `bounds`: ABVs, the A-buffer ([`ABuffer::build`]), then
    /// [`from_abuffer`](Self::from_abuffer).
    ///
    /// # Errors
    /// [`TileProgramError::Tiles`] as [`TileGrid::new`] and
    /// [`ABuffer::build`] (an empty image, bad bounds, too many entries);
    /// [`TileProgramError::TooLarge`].
    pub fn build<T: Real + Send + Sync>(
        tree: &FlatBlobtree,
        camera: &Camera<T>,
        bounds: [[T; 3]; 2],
        width: u32,
        height: u32,
    ) -> Result<Self, TileProgramError> {
        let grid = TileGrid::new(width, height, TILE_SIZE)?;
        let abvs = tree.abvs::<T>();
        let ab = ABuffer::build(camera, grid, bounds, &abvs)?;
        Self::from_abuffer(tree.as_ref(), &ab)
    }

    /// The programs from an A-buffer of `tree` (the grid's tiles must be
    /// [`TILE_SIZE`] wide).
    ///
    /// # Errors
    /// [`TileProgramError::TooLarge`] when the buffer would exceed `u32`
    /// indices; [`TileProgramError::TileSize`] for another tile size.
    pub fn from_abuffer<T>(
        tree: BlobtreeRef<'_>,
        ab: &ABuffer<T>,
    ) -> Result<Self, TileProgramError> {
        let grid = *ab.grid();
        if grid.tile_size != TILE_SIZE {
            return Err(TileProgramError::TileSize(grid.tile_size));
        }
        let tiles = grid.tile_count();
        let table = TILE_TABLE_WORDS * tiles;
        let mut words = vec![0u32; table + table % 2];
        let mut whole_at: Option<usize> = None;
        let (mut whole_tiles, mut max_nodes, mut total_nodes) = (0, 0, 0);
        let mut active = Vec::new();
        for i in 0..tiles {
            active.clear();
            active.extend(ab.tile(i).iter().map(|e| e.node));
            active.sort_unstable();
            active.dedup();
            let view =
                PrunedView::<'_, MAX_TILE_NODES, 0, STACK_CAPACITY>::build(tree, &active).ok();
            let (first, len) = match view {
                Some(v) => {
                    let first = words.len() / 2;
                    for (&node, &w) in v.node_indices().iter().zip(v.node_words()) {
                        words.push(w);
                        words.push(tree.offset(node).unwrap_or(u32::MAX));
                    }
                    (first, v.len())
                }
                None => {
                    whole_tiles += 1;
                    let first = *whole_at.get_or_insert_with(|| {
                        let first = words.len() / 2;
                        words.extend_from_slice(tree.nodes());
                        first
                    });
                    (first, tree.len())
                }
            };
            if words.len() > u32::MAX as usize {
                return Err(TileProgramError::TooLarge);
            }
            max_nodes = max_nodes.max(len);
            total_nodes += len;
            let at = TILE_TABLE_WORDS * i;
            words[at] = first as u32;
            words[at + 1] = len as u32;
            let l = BlobtreeWindow::<AllPrimitives>::tile(&words, tree.params(), i)
                .program_lipschitz::<f32>()
                .unwrap_or(f32::NAN);
            words[at + 2] = l.to_bits();
        }
        Ok(Self {
            grid,
            words,
            whole_tiles,
            max_nodes,
            total_nodes,
        })
    }

    /// The tiling of the image.
    pub fn grid(&self) -> &TileGrid {
        &self.grid
    }

    /// The buffer: table, then node pairs (module docs).
    pub fn words(&self) -> &[u32] {
        &self.words
    }

    /// The field of pixel `(x, y)`: its tile's program over the tree's
    /// parameters `params`.
    pub fn field<'a>(
        &'a self,
        params: &'a [f32],
        x: u32,
        y: u32,
    ) -> BlobtreeWindow<'a, AllPrimitives> {
        let tile = (y / TILE_SIZE) as usize * self.grid.tiles_x as usize + (x / TILE_SIZE) as usize;
        BlobtreeWindow::tile(&self.words, params, tile)
    }

    /// Tiles that use the whole tree (their program was too large).
    pub fn whole_tiles(&self) -> usize {
        self.whole_tiles
    }

    /// The largest program's node count.
    pub fn max_nodes(&self) -> usize {
        self.max_nodes
    }

    /// The mean node count per tile.
    pub fn mean_nodes(&self) -> f64 {
        self.total_nodes as f64 / self.grid.tile_count().max(1) as f64
    }
}

/// The CPU twin of the GPU's tiled blobtree dispatch: every pixel traced
/// with its tile's program ([`render_serial_with`]), so the same frame
/// bit for bit on a driver that computes like the CPU (`f32`).
///
/// # Errors
/// [`TileProgramError::Render`] for invalid settings or bounds;
/// [`TileProgramError::SizeMismatch`] when the programs were built for
/// another image size.
pub fn render_tile_programs<T: Real>(
    programs: &TilePrograms,
    tree: BlobtreeRef<'_>,
    camera: &Camera<T>,
    bounds: [[T; 3]; 2],
    settings: &RenderSettings<T>,
) -> Result<Frame<T>, TileProgramError> {
    let g = programs.grid();
    if g.width != settings.width || g.height != settings.height {
        return Err(TileProgramError::SizeMismatch);
    }
    let params = tree.params();
    Ok(render_serial_with(
        |x, y| programs.field(params, x, y),
        camera,
        bounds,
        settings,
    )?)
}
