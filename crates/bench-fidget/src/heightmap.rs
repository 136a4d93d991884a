//! fidget's 3D heightmap render against our first-hit depth image, on the
//! same view and at the same resolution.
//!
//! The view: the cube `c ± h` around the scene's bounds (`c` their centre,
//! `h` their largest half-extent), seen orthographically along `−z`, `N × N`
//! pixels. fidget samples the voxel grid `N × N × N` of that cube
//! (`world_to_model` is set so that its samples are our pixel centres and
//! the voxel centres along `z`); we trace one ray per pixel centre from the
//! top of the cube, clipped to the scene's bounds. fidget's output is the
//! index (+1) of the highest voxel whose centre is inside; ours is the
//! first root along the ray within `eps`. Both give a hit mask and a depth,
//! which are compared (agreement %) before anything is timed.

use crate::translate::{TranslateError, blobtree_to_fidget, check_translation};
use boundtrace_fields::blobtree::FlatBlobtree;
use boundtrace_tracer::Method;
use boundtrace_tracer::camera::Camera;
use boundtrace_tracer::method::Params;
use boundtrace_tracer::render::{Frame, RenderSettings, render};
use boundtrace_tracer::sync_render::{SyncSettings, render_sync};
use fidget::context::{Context, Node};
use fidget::jit::JitShape;
use fidget::raster::voxel::{self, EvalConfig, RenderConfig};
use fidget::render::{CancelToken, ThreadPool, VoxelSize};
use fidget::vm::VmShape;
use std::time::{Duration, Instant};

/// The common view of one scene.
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// Centre of the cube.
    pub center: [f32; 3],
    /// Half side of the cube.
    pub half: f32,
    /// Pixels per side (and voxels along `z`).
    pub size: u32,
}

impl View {
    /// The view of a scene with `bounds`, `size` pixels per side.
    pub fn new(bounds: [[f32; 3]; 2], size: u32) -> Self {
        let [lo, hi] = bounds;
        let center = [0, 1, 2].map(|i| 0.5 * (lo[i] + hi[i]));
        let half = (0..3).map(|i| 0.5 * (hi[i] - lo[i])).fold(0.0f32, f32::max);
        View { center, half, size }
    }
    /// The voxel pitch `2h / N`.
    pub fn pitch(&self) -> f32 {
        2.0 * self.half / self.size as f32
    }
    /// fidget's world-to-model matrix: `model = c + h·(world + 1/N)`, so
    /// that fidget's samples (`world = −1 + 2i/N` along x and z, `1 −
    /// 2(j+1)/N` along y for screen row `j`) are our pixel and voxel centres.
    pub fn world_to_model(&self) -> nalgebra::Matrix4<f32> {
        let h = self.half;
        let s = h / self.size as f32;
        let [cx, cy, cz] = self.center;
        nalgebra::Matrix4::new(
            h,
            0.0,
            0.0,
            cx + s,
            0.0,
            h,
            0.0,
            cy + s,
            0.0,
            0.0,
            h,
            cz + s,
            0.0,
            0.0,
            0.0,
            1.0,
        )
    }
    /// Our orthographic camera: from the top face of the cube, looking
    /// along `−z`, `+y` up, a `2h × 2h` view rectangle.
    pub fn camera(&self) -> Result<Camera<f32>, String> {
        let [cx, cy, cz] = self.center;
        Camera::orthographic(
            [cx, cy, cz + self.half],
            [cx, cy, cz],
            [0.0, 1.0, 0.0],
            2.0 * self.half,
            1.0,
        )
        .map_err(|e| format!("camera: {e}"))
    }
    /// The voxel depth (fidget's convention: 1 + index of the highest
    /// voxel centre at or below the point, 0 for none) of the height `z`.
    pub fn voxel_depth(&self, z: f32) -> i64 {
        let base = self.center[2] - self.half;
        let k = ((z - base) / self.pitch() - 0.5).floor() as i64;
        (k + 1).clamp(0, self.size as i64)
    }
}

/// A scene prepared on both sides.
pub struct Prepared {
    /// Display name.
    pub name: String,
    /// Primitives in the tree.
    pub primitives: usize,
    /// Our tree.
    pub tree: FlatBlobtree,
    /// The fidget expression.
    pub ctx: Context,
    /// Its root.
    pub root: Node,
    /// Nodes of the fidget expression (after deduplication).
    pub fidget_nodes: usize,
    /// Largest relative difference of the two fields on random points.
    pub field_error: f32,
    /// Random points where the two signs differ.
    pub sign_differs: usize,
    /// The scene's bounds.
    pub bounds: [[f32; 3]; 2],
}

/// Translates `tree` and checks the translation on `points` random points
/// of `bounds`.
///
/// # Errors
/// A tree without an exact fidget expression, or fidget's errors.
pub fn prepare(
    name: &str,
    tree: FlatBlobtree,
    bounds: [[f32; 3]; 2],
    primitives: usize,
    points: usize,
) -> Result<Prepared, String> {
    let (ctx, root) =
        blobtree_to_fidget(&tree).map_err(|e: TranslateError| format!("{name}: {e}"))?;
    let mut rng = crate::intervals::Rng::new(0x5EED);
    let [lo, hi] = bounds;
    let pts: Vec<[f32; 3]> = (0..points)
        .map(|_| [0, 1, 2].map(|i| rng.range(lo[i] as f64, hi[i] as f64) as f32))
        .collect();
    let (field_error, sign_differs) =
        check_translation(&tree, &ctx, root, &pts, 1e-5).map_err(|e| format!("{name}: {e}"))?;
    Ok(Prepared {
        name: name.to_string(),
        primitives,
        fidget_nodes: ctx.len(),
        tree,
        ctx,
        root,
        field_error,
        sign_differs,
        bounds,
    })
}

/// Which renderer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Renderer {
    /// fidget, JIT evaluator.
    FidgetJit,
    /// fidget, VM (interpreter) evaluator.
    FidgetVm,
    /// Ours, full-tree evaluation with a method.
    Full(Method),
    /// Ours, synchronized tracing (A-buffer + pruned views) with a method.
    Sync(Method),
}

impl Renderer {
    /// The name in tables and options.
    pub fn name(self) -> String {
        match self {
            Renderer::FidgetJit => "fidget-jit".into(),
            Renderer::FidgetVm => "fidget-vm".into(),
            Renderer::Full(m) => format!("full:{m}"),
            Renderer::Sync(m) => format!("sync:{m}"),
        }
    }
    /// Parses `fidget-jit`, `fidget-vm`, `full:METHOD`, `sync:METHOD`.
    pub fn parse(s: &str) -> Result<Self, String> {
        match s {
            "fidget-jit" => return Ok(Renderer::FidgetJit),
            "fidget-vm" => return Ok(Renderer::FidgetVm),
            _ => {}
        }
        let (kind, m) = s.split_once(':').ok_or_else(|| {
            format!(
                "bad renderer `{s}`: expected fidget-jit, fidget-vm, full:METHOD or sync:METHOD"
            )
        })?;
        let m: Method = m.parse().map_err(|e| format!("renderer `{s}`: {e}"))?;
        match kind {
            "full" => Ok(Renderer::Full(m)),
            "sync" => Ok(Renderer::Sync(m)),
            _ => Err(format!(
                "bad renderer `{s}`: expected full:METHOD or sync:METHOD"
            )),
        }
    }
    /// `true` for fidget's renderers.
    pub fn is_fidget(self) -> bool {
        matches!(self, Renderer::FidgetJit | Renderer::FidgetVm)
    }
}

/// One rendered image in the common form: per pixel (row-major, top row
/// first), the voxel depth (0 = miss).
#[derive(Clone, Debug, PartialEq)]
pub struct DepthImage {
    /// Voxel depths.
    pub depth: Vec<i64>,
    /// Our first hit's ray parameter per pixel (empty for fidget's images).
    pub t: Vec<Option<f32>>,
}

/// Compiled fidget shapes (compilation is timed separately).
pub struct Shapes {
    /// JIT shape.
    pub jit: JitShape,
    /// VM shape.
    pub vm: VmShape,
    /// Time to build the JIT shape.
    pub jit_build: Duration,
}

/// Compiles the fidget shapes of `p`.
///
/// # Errors
/// fidget's errors.
pub fn shapes(p: &Prepared) -> Result<Shapes, String> {
    let t = Instant::now();
    let jit = JitShape::new(&p.ctx, p.root).map_err(|e| format!("{}: fidget JIT: {e}", p.name))?;
    let jit_build = t.elapsed();
    let vm = VmShape::new(&p.ctx, p.root).map_err(|e| format!("{}: fidget VM: {e}", p.name))?;
    Ok(Shapes { jit, vm, jit_build })
}

/// Our settings: `method`, `eps`.
fn settings(view: &View, method: Method, eps: f32) -> Result<RenderSettings<f32>, String> {
    let params = Params::new()
        .with_eps(eps)
        .map_err(|e| format!("eps: {e}"))?;
    RenderSettings::new(view.size, view.size, method)
        .and_then(|s| s.with_params(params))
        .map_err(|e| format!("render settings: {e}"))
}

fn from_frame(view: &View, frame: &Frame<f32>) -> DepthImage {
    let n = view.size;
    let top = view.center[2] + view.half;
    let mut depth = Vec::with_capacity((n * n) as usize);
    let mut ts = Vec::with_capacity((n * n) as usize);
    for y in 0..n {
        for x in 0..n {
            let t = frame.depth(x, y);
            ts.push(t);
            depth.push(match t {
                Some(t) => view.voxel_depth(top - t).max(1),
                None => 0,
            });
        }
    }
    DepthImage { depth, t: ts }
}

fn from_fidget(image: &voxel::Image) -> DepthImage {
    DepthImage {
        depth: image.iter().map(|p| i64::from(p.depth)).collect(),
        t: Vec::new(),
    }
}

/// Renders once with `renderer` on `threads` threads (`pool` has that many);
/// returns the image and the wall time of the render call.
///
/// # Errors
/// Render errors of either side.
pub fn render_once(
    p: &Prepared,
    s: &Shapes,
    view: &View,
    renderer: Renderer,
    eps: f32,
    pool: &rayon::ThreadPool,
    fidget_pool: Option<&ThreadPool>,
) -> Result<(DepthImage, Duration), String> {
    match renderer {
        Renderer::FidgetJit | Renderer::FidgetVm => {
            let cfg = RenderConfig {
                image_size: VoxelSize::from(view.size),
                world_to_model: view.world_to_model(),
            };
            let eval = EvalConfig {
                tile_sizes: None,
                threads: fidget_pool,
                cancel: CancelToken::new(),
            };
            let vars = fidget::shape::ShapeVars::new();
            let t = Instant::now();
            let img = if renderer == Renderer::FidgetJit {
                let b = s.jit.bind(&vars).map_err(|e| format!("{e}"))?;
                voxel::render(b, &cfg, &eval)
            } else {
                let b = s.vm.bind(&vars).map_err(|e| format!("{e}"))?;
                voxel::render(b, &cfg, &eval)
            };
            let dt = t.elapsed();
            let img = img.ok_or("fidget render cancelled")?;
            Ok((from_fidget(&img), dt))
        }
        Renderer::Full(m) => {
            let camera = view.camera()?;
            let set = settings(view, m, eps)?;
            let t = Instant::now();
            let frame = pool
                .install(|| render(&p.tree.as_ref(), &camera, p.bounds, &set))
                .map_err(|e| format!("render: {e}"))?;
            let dt = t.elapsed();
            Ok((from_frame(view, &frame), dt))
        }
        Renderer::Sync(m) => {
            let camera = view.camera()?;
            let set = settings(view, m, eps)?;
            let t = Instant::now();
            let (frame, _) = pool
                .install(|| render_sync(&p.tree, &camera, p.bounds, &set, &SyncSettings::default()))
                .map_err(|e| format!("render_sync: {e}"))?;
            let dt = t.elapsed();
            Ok((from_frame(view, &frame), dt))
        }
    }
}

/// Agreement of two depth images.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Agreement {
    /// Pixels.
    pub pixels: usize,
    /// Pixels hit by both.
    pub both: usize,
    /// Pixels hit only by `a`.
    pub only_a: usize,
    /// Pixels hit only by `b`.
    pub only_b: usize,
    /// Pixels hit by both whose voxel depths differ by at most 1.
    pub depth_close: usize,
}

impl Agreement {
    /// Compares `a` and `b` (same size).
    pub fn of(a: &DepthImage, b: &DepthImage) -> Self {
        let mut g = Agreement {
            pixels: a.depth.len().min(b.depth.len()),
            ..Default::default()
        };
        for (x, y) in a.depth.iter().zip(&b.depth) {
            match (*x > 0, *y > 0) {
                (true, true) => {
                    g.both += 1;
                    if (x - y).abs() <= 1 {
                        g.depth_close += 1;
                    }
                }
                (true, false) => g.only_a += 1,
                (false, true) => g.only_b += 1,
                _ => {}
            }
        }
        g
    }
    /// Share of pixels with the same hit/miss, in %.
    pub fn mask_percent(&self) -> f64 {
        100.0 * (self.pixels - self.only_a - self.only_b) as f64 / self.pixels.max(1) as f64
    }
    /// Share of common hits with voxel depths within 1, in %.
    pub fn depth_percent(&self) -> f64 {
        100.0 * self.depth_close as f64 / self.both.max(1) as f64
    }
}

/// Of the pixels that `ours` hits and `fidget` misses, how many have a
/// point with `f < 0` (our `f32` interpreter) within one voxel pitch of our
/// hit along the ray (64 samples): the surface is really there, between
/// fidget's voxel centres. Returns (checked, confirmed).
pub fn confirm_only_ours(
    p: &Prepared,
    view: &View,
    ours: &DepthImage,
    fidget: &DepthImage,
) -> (usize, usize) {
    let n = view.size;
    let (mut checked, mut confirmed) = (0, 0);
    let top = view.center[2] + view.half;
    let tree = p.tree.as_ref();
    for (i, (a, b)) in ours.depth.iter().zip(&fidget.depth).enumerate() {
        let Some(Some(t)) = ours.t.get(i).copied() else {
            continue;
        };
        if !(*a > 0 && *b == 0) {
            continue;
        }
        checked += 1;
        let (px, py) = ((i as u32 % n) as f32, (i as u32 / n) as f32);
        let x = view.center[0] + view.half * ((2.0 * px + 1.0) / n as f32 - 1.0);
        let y = view.center[1] + view.half * (1.0 - (2.0 * py + 1.0) / n as f32);
        let pitch = view.pitch();
        let inside = (0..=64).any(|k| {
            let z = top - t - pitch + 2.0 * pitch * k as f32 / 64.0;
            tree.eval_full::<f32, f32>([x, y, z]) < 0.0
        });
        if inside {
            confirmed += 1;
        }
    }
    (checked, confirmed)
}

/// min, median and max of `v` (sorted in place); zeros for an empty slice.
pub fn min_med_max(v: &mut [f64]) -> [f64; 3] {
    if v.is_empty() {
        return [0.0; 3];
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let med = if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    };
    [v[0], med, v[n - 1]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use boundtrace_fields::blobtree::Node as TreeNode;
    use boundtrace_fields::{Operator, Primitive};

    #[test]
    fn statistics_of_small_sets() {
        assert_eq!(min_med_max(&mut [3.0, 1.0, 2.0]), [1.0, 2.0, 3.0]);
        assert_eq!(min_med_max(&mut [4.0, 1.0, 2.0, 3.0]), [1.0, 2.5, 4.0]);
        assert_eq!(min_med_max(&mut []), [0.0; 3]);
    }

    #[test]
    fn voxel_depth_convention() {
        let v = View::new([[-1.0; 3], [1.0; 3]], 4);
        // voxel centres at z = −0.75, −0.25, 0.25, 0.75
        assert_eq!(v.voxel_depth(-0.8), 0);
        assert_eq!(v.voxel_depth(-0.75), 1);
        assert_eq!(v.voxel_depth(0.3), 3);
        assert_eq!(v.voxel_depth(0.99), 4);
    }

    #[test]
    fn both_renderers_see_the_same_sphere() {
        // an off-centre sphere and box: the masks must agree almost
        // everywhere, and the image must not be mirrored (x or y)
        let node = TreeNode::op(
            Operator::union(),
            TreeNode::primitive(Primitive::sphere([0.3, 0.2, 0.0], 0.35).unwrap()),
            TreeNode::primitive(Primitive::cuboid([-0.4, -0.3, 0.1], [0.2, 0.1, 0.3]).unwrap()),
        );
        let tree = FlatBlobtree::from_node(&node).unwrap();
        let bounds = [[-0.8f32, -0.7, -0.5], [0.8, 0.7, 0.6]];
        let p = prepare("t", tree, bounds, 2, 200).unwrap();
        assert_eq!(p.sign_differs, 0);
        let s = shapes(&p).unwrap();
        let view = View::new(bounds, 48);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        let (a, _) = render_once(&p, &s, &view, Renderer::FidgetVm, 1e-4, &pool, None).unwrap();
        let (b, _) = render_once(
            &p,
            &s,
            &view,
            Renderer::Full(Method::Sphere),
            1e-4,
            &pool,
            None,
        )
        .unwrap();
        let g = Agreement::of(&a, &b);
        assert!(g.both > 300, "{g:?}");
        assert!(g.mask_percent() > 99.0, "{g:?}");
        assert!(g.depth_percent() > 99.0, "{g:?}");
    }
}
