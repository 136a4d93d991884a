//! The versioned JSON scene format (`"version": 1`): types, parsing with
//! precise errors, validation, conversion to a tracer [`Scene`], and the
//! export of the standard scenes ([`SceneFile::from_scene`]).
//!
//! The full reference with examples is `docs/scene-format.md`; in short:
//!
//! ```
//! use boundtrace_cli::scene_format::SceneFile;
//!
//! let text = r#"{
//!   "version": 1,
//!   "name": "two-blobs",
//!   "field": { "blobs": {
//!     "iso": 0.5,
//!     "blobs": [
//!       { "center": [-0.4, 0, 0], "kernel": { "compact": { "degree": 6, "sigma": 1 } } },
//!       { "center": [0.4, 0, 0], "kernel": { "compact": { "degree": 6, "sigma": 1 } } }
//!     ]
//!   } }
//! }"#;
//! let file = SceneFile::parse(text)?;
//! let scene = file.build::<f64>()?; // bounds computed from the compact supports
//! assert_eq!(scene.primitive_count(), 2);
//!
//! // A negative radius is rejected with the JSON path of the field.
//! let bad = text.replacen("\"sigma\": 1 }", "\"sigma\": -1 }", 1);
//! let err = SceneFile::parse(&bad).and_then(|f| f.build::<f64>().map(|_| ())).unwrap_err();
//! assert!(err.to_string().contains("field.blobs.blobs[0].kernel.compact.sigma"), "{err}");
//! # Ok::<(), boundtrace_cli::scene_format::FormatError>(())
//! ```
//!
//! Every number is an `f64`; files written by [`SceneFile::to_json`] round
//! trip exactly (`serde_json` with `float_roundtrip`), so a standard scene
//! exported with [`SceneFile::from_scene`] and built again in `f64` is
//! bit-identical to the generator's (tested in `tests/cli.rs`).
//!
//! Soundness: `bounds` and `lipschitz` are claims of the file. Computed
//! bounds (compact blobs and skeletons) are proven; given ones are checked
//! by sampling the box faces in [`SceneFile::check_bounds`] (`boundtrace
//! scene check`); a `lipschitz` value that is too small makes sphere
//! tracing miss roots, so only give one you have proven (the standard
//! scenes' are computed by their generators, see
//! `boundtrace_tracer::scenes`).

use boundtrace_fields::blobtree::{FlatBlobtree, Node};
use boundtrace_fields::density::UnionAll;
use boundtrace_fields::homothetic::{Segment, SegmentKernel};
use boundtrace_fields::homothetic_skeleton::HomotheticSkeleton;
use boundtrace_fields::hrbf::{Hrbf, HrbfCenter};
use boundtrace_fields::operator::{Operator, OperatorKind};
use boundtrace_fields::scalis::{ScalisSegment, ScalisSkeleton};
use boundtrace_fields::sdf::{Primitive, PrimitiveKind};
use boundtrace_fields::{Blobs, FieldError, Kernel, KernelKind, PointBlob};
use boundtrace_ia_core::Real;
use boundtrace_inclusion::Field;
use boundtrace_tracer::scenes::{Scene, SceneField, WithLipschitz, rotate};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::fmt;

/// The format version this crate reads and writes.
pub const VERSION: u32 = 1;

/// The largest accepted file (bytes), so a huge input fails early.
pub const MAX_FILE_BYTES: usize = 256 << 20;

/// The deepest accepted blobtree nesting (the conversion recurses; the
/// flat encoding has a smaller limit anyway).
pub const MAX_TREE_DEPTH: usize = 64;

/// A scene file that cannot be read or is invalid.
#[derive(Clone, Debug, PartialEq)]
pub struct FormatError {
    /// The JSON path of the offending value (`field.blobs[3].kernel.sigma`),
    /// empty for the whole document.
    pub path: String,
    /// `(line, column)` (1-based) for syntax and type errors.
    pub position: Option<(usize, usize)>,
    /// What is wrong.
    pub message: String,
}

impl FormatError {
    fn at(path: &str, message: impl Into<String>) -> Self {
        Self {
            path: path.to_string(),
            position: None,
            message: message.into(),
        }
    }
}

impl fmt::Display for FormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.position, self.path.is_empty()) {
            (Some((l, c)), true) => write!(f, "line {l}, column {c}: {}", self.message),
            (Some((l, c)), false) => {
                write!(f, "line {l}, column {c}: `{}`: {}", self.path, self.message)
            }
            (None, true) => f.write_str(&self.message),
            (None, false) => write!(f, "`{}`: {}", self.path, self.message),
        }
    }
}

impl std::error::Error for FormatError {}

/// A scene file (version 1).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Must be [`VERSION`].
    pub version: u32,
    /// A short name (used for output names); default `"scene"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// One line of description.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub description: Option<String>,
    /// The implicit field (positive outside, negative inside).
    pub field: FieldSpec,
    /// `[min, max]`, a box containing the whole surface; computed when
    /// absent for compact blobs and compact skeletons, required otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bounds: Option<[[f64; 3]; 2]>,
    /// A point inside (informational; the box centre when absent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inside: Option<[f64; 3]>,
    /// The camera; default: framing the bounds along `[-0.5, -0.6, -1]`
    /// with a 35° field of view.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera: Option<CameraSpec>,
    /// Directional lights; none means a headlight.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lights: Vec<LightSpec>,
    /// Surface and background colours and the ambient term.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<MaterialSpec>,
}

/// The field of a scene, by `"type"`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum FieldSpec {
    /// `f = iso − Σ wᵢ k(|p − cᵢ|)`.
    Blobs {
        /// The iso value.
        iso: f64,
        /// The blobs.
        blobs: Vec<BlobSpec>,
        /// An optional global Lipschitz bound the file vouches for.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        lipschitz: Option<f64>,
    },
    /// The sharp union (`min`) of blob sets, each `iso − Σ`.
    BlobGroups {
        /// The groups.
        groups: Vec<BlobGroupSpec>,
    },
    /// A skeleton of segments between vertices with radii.
    Skeleton(SkeletonSpec),
    /// A Hermite RBF (`φ = r³`).
    Hrbf(HrbfSpec),
    /// A blobtree of primitives and operators.
    Blobtree {
        /// The root node.
        root: NodeSpec,
    },
}

/// One point blob.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlobSpec {
    /// The centre.
    pub center: [f64; 3],
    /// The weight (default 1).
    #[serde(default = "one")]
    pub weight: f64,
    /// The kernel.
    pub kernel: KernelSpec,
}

fn one() -> f64 {
    1.0
}

/// One group of [`FieldSpec::BlobGroups`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlobGroupSpec {
    /// The iso value.
    pub iso: f64,
    /// The blobs.
    pub blobs: Vec<BlobSpec>,
}

/// A point-blob kernel (`boundtrace_fields::Kernel`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum KernelSpec {
    /// `(1 − (d/σ)²)^{n/2}` inside `σ` (compact support).
    Compact {
        /// `n ∈ [2, 64]`.
        degree: u32,
        /// `σ > 0`, the support radius.
        sigma: f64,
    },
    /// `(1 + (d/σ)²)^{−n/2}`.
    Cauchy {
        /// `n ∈ [2, 64]`.
        degree: u32,
        /// `σ > 0`.
        sigma: f64,
    },
    /// `e^{−(d/σ)²}`.
    Gaussian {
        /// `σ > 0`.
        sigma: f64,
    },
    /// `(d/σ)^{−n}`.
    Inverse {
        /// `n ∈ [2, 64]`.
        degree: u32,
        /// `σ > 0`.
        sigma: f64,
    },
}

/// The distance of a skeleton's segments.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Distance {
    /// SCALIS: scale-invariant integral surfaces (thesis Part III).
    Scalis,
    /// Homothetic distance: `iso − Σ k(h_S)/k(1)` (thesis Part II eq. 1.13;
    /// `boundtrace_fields::homothetic_skeleton`).
    Homothetic,
}

/// A segment kernel (`boundtrace_fields::homothetic::SegmentKernel`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum SegmentKernelSpec {
    /// Compact polynomial of even degree.
    Compact {
        /// Even `n ∈ [2, 64]`.
        degree: u32,
        /// `σ > 0`.
        sigma: f64,
    },
    /// Cauchy.
    Cauchy {
        /// `n ∈ [2, 64]`.
        degree: u32,
        /// `σ > 0`.
        sigma: f64,
    },
}

/// A skeleton: vertices with radii joined by edges (segments).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SkeletonSpec {
    /// `scalis` (default) or `homothetic`.
    #[serde(default = "scalis")]
    pub distance: Distance,
    /// The kernel of every segment.
    pub kernel: SegmentKernelSpec,
    /// The iso value (`> 0`).
    pub iso: f64,
    /// The vertices.
    pub vertices: Vec<VertexSpec>,
    /// Pairs of vertex indices.
    pub edges: Vec<[usize; 2]>,
    /// An optional global Lipschitz bound the file vouches for (default:
    /// the sum of the segments' bounds).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lipschitz: Option<f64>,
}

fn scalis() -> Distance {
    Distance::Scalis
}

/// A skeleton vertex.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VertexSpec {
    /// The position.
    pub position: [f64; 3],
    /// The radius (`> 0`).
    pub radius: f64,
}

/// An HRBF: either `points` and `normals` (fitted), or fitted `centers`
/// and `poly` (exact).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HrbfSpec {
    /// Sample points on the surface.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub points: Vec<[f64; 3]>,
    /// Outward normals at the points.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub normals: Vec<[f64; 3]>,
    /// Fitted centers with weights.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub centers: Vec<HrbfCenterSpec>,
    /// The fitted polynomial `[a₀, a₁, a₂, b]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poly: Option<[f64; 4]>,
}

/// A fitted HRBF center.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HrbfCenterSpec {
    /// The center.
    pub center: [f64; 3],
    /// The scalar weight.
    pub alpha: f64,
    /// The vector weight.
    pub beta: [f64; 3],
}

/// A rigid transform: rotation quaternion `[x, y, z, w]` then translation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransformSpec {
    /// Unit quaternion `[x, y, z, w]` (normalised when not unit).
    #[serde(default = "identity_quat")]
    pub rotation: [f64; 4],
    /// Translation.
    #[serde(default)]
    pub translation: [f64; 3],
}

fn identity_quat() -> [f64; 4] {
    [0.0, 0.0, 0.0, 1.0]
}

impl Default for TransformSpec {
    fn default() -> Self {
        Self {
            rotation: identity_quat(),
            translation: [0.0; 3],
        }
    }
}

impl TransformSpec {
    fn is_identity(&self) -> bool {
        *self == Self::default()
    }
}

/// A blobtree node: a primitive (in its local frame, placed by
/// `transform`) or an operator over `children` (two or more, folded from
/// the left; a `transform` on an operator moves its whole subtree).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum NodeSpec {
    /// Ball of `radius` at the origin.
    Sphere {
        /// `> 0`.
        radius: f64,
        /// Placement.
        #[serde(default, skip_serializing_if = "TransformSpec::is_identity")]
        transform: TransformSpec,
    },
    /// Box with `half_extents`.
    Box {
        /// `> 0` each.
        half_extents: [f64; 3],
        /// Placement.
        #[serde(default, skip_serializing_if = "TransformSpec::is_identity")]
        transform: TransformSpec,
    },
    /// Box with rounded edges of radius `rounding`.
    RoundedBox {
        /// `> 0` each.
        half_extents: [f64; 3],
        /// `≥ 0`, at most the smallest half extent.
        rounding: f64,
        /// Placement.
        #[serde(default, skip_serializing_if = "TransformSpec::is_identity")]
        transform: TransformSpec,
    },
    /// Capsule along `z` from `−half_length` to `half_length`.
    Capsule {
        /// `> 0`.
        half_length: f64,
        /// `> 0`.
        radius: f64,
        /// Placement.
        #[serde(default, skip_serializing_if = "TransformSpec::is_identity")]
        transform: TransformSpec,
    },
    /// Capped cylinder along `z`.
    Cylinder {
        /// `> 0`.
        half_length: f64,
        /// `> 0`.
        radius: f64,
        /// Placement.
        #[serde(default, skip_serializing_if = "TransformSpec::is_identity")]
        transform: TransformSpec,
    },
    /// Torus around `z`.
    Torus {
        /// `> 0`.
        major: f64,
        /// `> 0`.
        minor: f64,
        /// Placement.
        #[serde(default, skip_serializing_if = "TransformSpec::is_identity")]
        transform: TransformSpec,
    },
    /// Half-space `z ≤ 0`.
    Plane {
        /// Placement.
        #[serde(default, skip_serializing_if = "TransformSpec::is_identity")]
        transform: TransformSpec,
    },
    /// Capped cone along `z`, radius `radius_a` at `−half_length`.
    Cone {
        /// `> 0`.
        half_length: f64,
        /// `≥ 0`.
        radius_a: f64,
        /// `≥ 0`.
        radius_b: f64,
        /// Placement.
        #[serde(default, skip_serializing_if = "TransformSpec::is_identity")]
        transform: TransformSpec,
    },
    /// Ellipsoid with `radii`.
    Ellipsoid {
        /// `> 0` each.
        radii: [f64; 3],
        /// Placement.
        #[serde(default, skip_serializing_if = "TransformSpec::is_identity")]
        transform: TransformSpec,
    },
    /// Gyroid sheet.
    Gyroid {
        /// `> 0`.
        period: f64,
        /// `> 0`.
        thickness: f64,
        /// Placement.
        #[serde(default, skip_serializing_if = "TransformSpec::is_identity")]
        transform: TransformSpec,
    },
    /// A compact blob as a distance-like primitive.
    Blob {
        /// Support radius `> 0`.
        radius: f64,
        /// Iso value in `(0, 1)`.
        iso: f64,
        /// Even kernel degree (default 6).
        #[serde(default = "six")]
        degree: u32,
        /// Placement.
        #[serde(default, skip_serializing_if = "TransformSpec::is_identity")]
        transform: TransformSpec,
    },
    /// `min` of the children.
    Union(OperatorSpec),
    /// `max` of the children.
    Intersection(OperatorSpec),
    /// `max(a, −b)`, folded from the left.
    Difference(OperatorSpec),
    /// Smooth union (`beta`).
    SmoothUnion(OperatorSpec),
    /// Smooth intersection (`beta`).
    SmoothIntersection(OperatorSpec),
    /// Smooth difference (`beta`).
    SmoothDifference(OperatorSpec),
    /// Compact smooth union `G∪` (`beta`, optional `r_o`).
    CompactUnion(OperatorSpec),
    /// Compact smooth intersection (`beta`, optional `r_o`).
    CompactIntersection(OperatorSpec),
    /// Compact smooth difference (`beta`, optional `r_o`).
    CompactDifference(OperatorSpec),
}

fn six() -> u32 {
    6
}

/// An operator node.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OperatorSpec {
    /// Blend width `β > 0` (smooth and compact operators).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beta: Option<f64>,
    /// Outer range `r_o` of the compact operators (default `2β`... see
    /// `Operator::default_r_o`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub r_o: Option<f64>,
    /// The operands (at least two), folded from the left.
    pub children: Vec<NodeSpec>,
    /// Moves the whole subtree.
    #[serde(default, skip_serializing_if = "TransformSpec::is_identity")]
    pub transform: TransformSpec,
}

/// An operator's name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OpName {
    /// `min`.
    Union,
    /// `max`.
    Intersection,
    /// `max(a, −b)`.
    Difference,
    /// Smooth union.
    SmoothUnion,
    /// Smooth intersection.
    SmoothIntersection,
    /// Smooth difference.
    SmoothDifference,
    /// Compact smooth union `G∪`.
    CompactUnion,
    /// Compact smooth intersection.
    CompactIntersection,
    /// Compact smooth difference.
    CompactDifference,
}

/// The camera.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", deny_unknown_fields)]
pub enum CameraSpec {
    /// Frames the scene's bounds, looking along `direction`.
    Framing {
        /// View direction (default `[-0.5, -0.6, -1]`).
        #[serde(default = "default_dir")]
        direction: [f64; 3],
        /// Vertical field of view in degrees (default 35).
        #[serde(default = "default_fov")]
        fov_deg: f64,
    },
    /// Perspective look-at.
    Perspective {
        /// Eye position.
        eye: [f64; 3],
        /// Looked-at point.
        target: [f64; 3],
        /// Up direction (default `+y`).
        #[serde(default = "default_up")]
        up: [f64; 3],
        /// Vertical field of view in degrees (default 35).
        #[serde(default = "default_fov")]
        fov_deg: f64,
    },
    /// Orthographic.
    Orthographic {
        /// Centre of the view rectangle.
        eye: [f64; 3],
        /// Looked-at point (gives the direction).
        target: [f64; 3],
        /// Up direction (default `+y`).
        #[serde(default = "default_up")]
        up: [f64; 3],
        /// Height of the view rectangle in world units.
        view_height: f64,
    },
}

fn default_dir() -> [f64; 3] {
    [-0.5, -0.6, -1.0]
}
fn default_fov() -> f64 {
    35.0
}
fn default_up() -> [f64; 3] {
    [0.0, 1.0, 0.0]
}

impl Default for CameraSpec {
    fn default() -> Self {
        CameraSpec::Framing {
            direction: default_dir(),
            fov_deg: default_fov(),
        }
    }
}

/// A directional light.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LightSpec {
    /// Direction *towards* the light (world space, need not be unit).
    pub direction: [f64; 3],
    /// Colour, components in `[0, 1]` (default white).
    #[serde(default = "white")]
    pub color: [f64; 3],
    /// Intensity `≥ 0` (default 1).
    #[serde(default = "one")]
    pub intensity: f64,
}

fn white() -> [f64; 3] {
    [1.0; 3]
}

/// Colours of the shaded image.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Surface colour (0–255).
    #[serde(default = "default_surface")]
    pub surface: [u8; 3],
    /// Background colour (0–255).
    #[serde(default = "default_background")]
    pub background: [u8; 3],
    /// Ambient term in `[0, 1]`.
    #[serde(default = "default_ambient")]
    pub ambient: f64,
}

fn default_surface() -> [u8; 3] {
    boundtrace_tracer::render::Shading::default().surface
}
fn default_background() -> [u8; 3] {
    boundtrace_tracer::render::Shading::default().background
}
fn default_ambient() -> f64 {
    boundtrace_tracer::render::Shading::default().ambient
}

impl Default for MaterialSpec {
    fn default() -> Self {
        Self {
            surface: default_surface(),
            background: default_background(),
            ambient: default_ambient(),
        }
    }
}

// ---------------------------------------------------------------- parsing

impl SceneFile {
    /// Parses and checks the version (values are validated by
    /// [`build`](Self::build)).
    ///
    /// # Errors
    /// Syntax and type errors with line, column and JSON path; an
    /// unsupported version; a file over [`MAX_FILE_BYTES`].
    pub fn parse(text: &str) -> Result<Self, FormatError> {
        if text.len() > MAX_FILE_BYTES {
            return Err(FormatError::at(
                "",
                format!(
                    "file too large ({} bytes, at most {MAX_FILE_BYTES})",
                    text.len()
                ),
            ));
        }
        let mut de = serde_json::Deserializer::from_str(text);
        let file: SceneFile = serde_path_to_error::deserialize(&mut de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            let (line, column) = (inner.line(), inner.column());
            // serde_json appends " at line L column C"; we print it first.
            let msg = inner.to_string();
            let msg = msg
                .rsplit_once(" at line ")
                .map_or(msg.as_str(), |(m, _)| m)
                .to_string();
            FormatError {
                path: if path == "." { String::new() } else { path },
                position: Some((line, column)),
                message: msg,
            }
        })?;
        de.end().map_err(|e| FormatError {
            path: String::new(),
            position: Some((e.line(), e.column())),
            message: "trailing characters after the scene".into(),
        })?;
        if file.version != VERSION {
            return Err(FormatError::at(
                "version",
                format!(
                    "unsupported version {} (this build reads version {VERSION})",
                    file.version
                ),
            ));
        }
        Ok(file)
    }

    /// Parses bytes (UTF-8 checked first).
    ///
    /// # Errors
    /// As [`parse`](Self::parse), and for bytes that are not UTF-8.
    pub fn parse_bytes(bytes: &[u8]) -> Result<Self, FormatError> {
        let text = std::str::from_utf8(bytes).map_err(|e| {
            FormatError::at("", format!("not UTF-8 text (byte {})", e.valid_up_to()))
        })?;
        Self::parse(text)
    }

    /// Pretty-printed JSON (exact round trip of every number).
    pub fn to_json(&self) -> String {
        // Serialising these plain data types cannot fail (finite or not,
        // serde_json writes `null` for non-finite floats).
        serde_json::to_string_pretty(self).unwrap_or_default() + "\n"
    }

    /// The name, `"scene"` when absent.
    pub fn scene_name(&self) -> &str {
        self.name.as_deref().unwrap_or("scene")
    }

    /// The camera spec (the default framing when absent).
    pub fn camera_spec(&self) -> CameraSpec {
        self.camera.unwrap_or_default()
    }

    /// The material (defaults when absent).
    pub fn material_spec(&self) -> MaterialSpec {
        self.material.unwrap_or_default()
    }
}

// ------------------------------------------------------------- validation

fn fe(path: &str, e: FieldError) -> FormatError {
    match e {
        FieldError::InvalidParameter { name, reason } => {
            FormatError::at(path, format!("invalid {name}: {reason}"))
        }
        other => FormatError::at(path, other.to_string()),
    }
}

fn finite(path: &str, x: f64) -> Result<f64, FormatError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(FormatError::at(path, "must be a finite number"))
    }
}

fn positive(path: &str, x: f64) -> Result<f64, FormatError> {
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(FormatError::at(
            path,
            format!("must be finite and > 0, got {x}"),
        ))
    }
}

fn nonneg(path: &str, x: f64) -> Result<f64, FormatError> {
    if x.is_finite() && x >= 0.0 {
        Ok(x)
    } else {
        Err(FormatError::at(
            path,
            format!("must be finite and ≥ 0, got {x}"),
        ))
    }
}

fn finite3(path: &str, v: [f64; 3]) -> Result<[f64; 3], FormatError> {
    for (k, x) in v.iter().enumerate() {
        finite(&format!("{path}[{k}]"), *x)?;
    }
    Ok(v)
}

fn degree(path: &str, n: u32) -> Result<u32, FormatError> {
    if (2..=64).contains(&n) {
        Ok(n)
    } else {
        Err(FormatError::at(path, format!("must be in 2..=64, got {n}")))
    }
}

fn cvt<T: Real>(v: [f64; 3]) -> [T; 3] {
    v.map(T::from_f64)
}

/// Validates the parameters shared by every kernel under `path` (the
/// kernel's key path): the degree, when the kernel has one, then `σ`.
fn kernel_params(path: &str, n: Option<u32>, sigma: f64) -> Result<f64, FormatError> {
    if let Some(n) = n {
        degree(&format!("{path}.degree"), n)?;
    }
    positive(&format!("{path}.sigma"), sigma)
}

impl KernelSpec {
    /// `(key, degree, σ)`.
    fn parts(&self) -> (&'static str, Option<u32>, f64) {
        match *self {
            KernelSpec::Compact { degree, sigma } => ("compact", Some(degree), sigma),
            KernelSpec::Cauchy { degree, sigma } => ("cauchy", Some(degree), sigma),
            KernelSpec::Gaussian { sigma } => ("gaussian", None, sigma),
            KernelSpec::Inverse { degree, sigma } => ("inverse", Some(degree), sigma),
        }
    }

    fn build<T: Real>(&self, path: &str) -> Result<Kernel<T>, FormatError> {
        let (key, n, sigma) = self.parts();
        let path = &format!("{path}.{key}");
        let s = T::from_f64(kernel_params(path, n, sigma)?);
        let r = match *self {
            KernelSpec::Compact { degree: n, .. } => Kernel::compact(n, s),
            KernelSpec::Cauchy { degree: n, .. } => Kernel::cauchy(n, s),
            KernelSpec::Gaussian { .. } => Kernel::gaussian(s),
            KernelSpec::Inverse { degree: n, .. } => Kernel::inverse(n, s),
        };
        r.map_err(|e| fe(path, e))
    }

    /// The spec of a kernel.
    pub fn of<T: Real>(k: &Kernel<T>) -> Self {
        let (n, sigma) = (k.degree(), k.sigma().as_f64());
        match k.kind() {
            KernelKind::Compact => KernelSpec::Compact { degree: n, sigma },
            KernelKind::Cauchy => KernelSpec::Cauchy { degree: n, sigma },
            KernelKind::Gaussian => KernelSpec::Gaussian { sigma },
            KernelKind::Inverse => KernelSpec::Inverse { degree: n, sigma },
        }
    }
}

fn build_blobs<T: Real>(
    path: &str,
    iso: f64,
    blobs: &[BlobSpec],
) -> Result<Blobs<T, Vec<PointBlob<T>>>, FormatError> {
    finite(&format!("{path}.iso"), iso)?;
    if blobs.is_empty() {
        return Err(FormatError::at(
            &format!("{path}.blobs"),
            "needs at least one blob",
        ));
    }
    let mut out = Vec::with_capacity(blobs.len());
    for (i, b) in blobs.iter().enumerate() {
        let p = format!("{path}.blobs[{i}]");
        let c = finite3(&format!("{p}.center"), b.center)?;
        let w = finite(&format!("{p}.weight"), b.weight)?;
        let k = b.kernel.build::<T>(&format!("{p}.kernel"))?;
        out.push(PointBlob::new(cvt(c), T::from_f64(w), k).map_err(|e| fe(&p, e))?);
    }
    Blobs::new(T::from_f64(iso), out).map_err(|e| fe(path, e))
}

/// The box of compact blob supports, or `None` when a kernel is not
/// compact or `iso ≤ 0` (then `f` is not positive outside the supports).
fn blob_box(iso: f64, blobs: &[BlobSpec]) -> Option<[[f64; 3]; 2]> {
    if !(iso > 0.0) {
        return None;
    }
    let mut b = [[f64::INFINITY; 3], [f64::NEG_INFINITY; 3]];
    for blob in blobs {
        let KernelSpec::Compact { sigma, .. } = blob.kernel else {
            return None;
        };
        for (k, c) in blob.center.iter().enumerate() {
            b[0][k] = b[0][k].min(c - sigma);
            b[1][k] = b[1][k].max(c + sigma);
        }
    }
    Some(b)
}

fn grow(b: [[f64; 3]; 2]) -> [[f64; 3]; 2] {
    let m = (0..3).map(|k| b[1][k] - b[0][k]).fold(0.0, f64::max) * 0.02;
    [b[0].map(|x| x - m), b[1].map(|x| x + m)]
}

fn union_box(a: Option<[[f64; 3]; 2]>, b: Option<[[f64; 3]; 2]>) -> Option<[[f64; 3]; 2]> {
    let (a, b) = (a?, b?);
    Some([
        [0, 1, 2].map(|k| a[0][k].min(b[0][k])),
        [0, 1, 2].map(|k| a[1][k].max(b[1][k])),
    ])
}

impl SegmentKernelSpec {
    /// Validates and builds the kernel (`path` is the `kernel` path).
    fn build<T: Real>(&self, path: &str) -> Result<SegmentKernel<T>, FormatError> {
        let (key, n, sigma) = match *self {
            SegmentKernelSpec::Compact { degree, sigma } => ("compact", degree, sigma),
            SegmentKernelSpec::Cauchy { degree, sigma } => ("cauchy", degree, sigma),
        };
        let p = &format!("{path}.{key}");
        let s = T::from_f64(kernel_params(p, Some(n), sigma)?);
        match self {
            SegmentKernelSpec::Compact { .. } => {
                if n % 2 != 0 {
                    return Err(FormatError::at(
                        &format!("{p}.degree"),
                        format!("the compact segment kernel needs an even degree, got {n}"),
                    ));
                }
                SegmentKernel::compact_polynomial(n, s)
            }
            SegmentKernelSpec::Cauchy { .. } => SegmentKernel::cauchy(n, s),
        }
        .map_err(|e| fe(p, e))
    }

    /// The spec of a kernel.
    fn of<T: Real>(k: SegmentKernel<T>) -> Self {
        match k {
            SegmentKernel::CompactPolynomial { degree, sigma } => SegmentKernelSpec::Compact {
                degree,
                sigma: sigma.as_f64(),
            },
            SegmentKernel::Cauchy { degree, sigma } => SegmentKernelSpec::Cauchy {
                degree,
                sigma: sigma.as_f64(),
            },
        }
    }
}

/// A built skeleton field, its box of compact supports (if any) and its
/// segment count.
type BuiltSkeleton<T> = (SceneField<T>, Option<[[f64; 3]; 2]>, usize);

impl SkeletonSpec {
    /// The validated vertices and edges as segments.
    fn segments<T: Real>(&self, path: &str) -> Result<Vec<Segment<T>>, FormatError> {
        for (i, v) in self.vertices.iter().enumerate() {
            let p = format!("{path}.vertices[{i}]");
            finite3(&format!("{p}.position"), v.position)?;
            positive(&format!("{p}.radius"), v.radius)?;
        }
        if self.edges.is_empty() {
            return Err(FormatError::at(
                &format!("{path}.edges"),
                "needs at least one edge",
            ));
        }
        let mut out = Vec::with_capacity(self.edges.len());
        for (i, &[a, b]) in self.edges.iter().enumerate() {
            let p = format!("{path}.edges[{i}]");
            let n = self.vertices.len();
            for (j, v) in [a, b].into_iter().enumerate() {
                if v >= n {
                    return Err(FormatError::at(
                        &format!("{p}[{j}]"),
                        format!("vertex index {v} out of range ({n} vertices)"),
                    ));
                }
            }
            let (va, vb) = (self.vertices[a], self.vertices[b]);
            if va.position == vb.position {
                return Err(FormatError::at(
                    &p,
                    format!("zero-length segment (vertices {a} and {b} coincide)"),
                ));
            }
            let seg = Segment::new(
                cvt(va.position),
                T::from_f64(va.radius),
                cvt(vb.position),
                T::from_f64(vb.radius),
            )
            .map_err(|e| fe(&p, e))?;
            out.push(seg);
        }
        Ok(out)
    }

    /// Validates every value and builds the field (`path` is the
    /// skeleton's path).
    fn build<T: Real>(&self, path: &str) -> Result<BuiltSkeleton<T>, FormatError> {
        let iso = T::from_f64(positive(&format!("{path}.iso"), self.iso)?);
        let kernel = self.kernel.build::<T>(&format!("{path}.kernel"))?;
        let segs = self.segments::<T>(path)?;
        let n = segs.len();
        let lipschitz = match self.lipschitz {
            Some(l) => Some(T::from_f64(positive(&format!("{path}.lipschitz"), l)?)),
            None => None,
        };
        let to_f64 = |[lo, hi]: [[T; 3]; 2]| [lo.map(|x| x.as_f64()), hi.map(|x| x.as_f64())];
        let mut bx: Option<[[f64; 3]; 2]> = None;
        match self.distance {
            Distance::Scalis => {
                let mut scalis = Vec::with_capacity(n);
                for (i, seg) in segs.into_iter().enumerate() {
                    let s = ScalisSegment::new(seg, kernel, iso)
                        .map_err(|e| fe(&format!("{path}.edges[{i}]"), e))?;
                    let sb = s.support_box().map(to_f64);
                    bx = if i == 0 { sb } else { union_box(bx, sb) };
                    scalis.push(s);
                }
                let sk = ScalisSkeleton::new(scalis).map_err(|e| fe(path, e))?;
                let l = lipschitz.unwrap_or_else(|| sk.lipschitz().unwrap_or(T::INFINITY));
                Ok((SceneField::Scalis(WithLipschitz::new(sk, l)), bx, n))
            }
            Distance::Homothetic => {
                if let SegmentKernel::CompactPolynomial { sigma, .. } = kernel {
                    if !(sigma > T::ONE) {
                        return Err(FormatError::at(
                            &format!("{path}.kernel.compact.sigma"),
                            "a homothetic skeleton's compact kernel needs sigma > 1 \
                             (the kernel vanishes at the prescribed radius otherwise)",
                        ));
                    }
                }
                let sk = HomotheticSkeleton::new(segs, kernel, iso)
                    .map_err(|e| fe(&format!("{path}.kernel"), e))?;
                for (i, seg) in sk.segments().iter().enumerate() {
                    let sb = sk.support_box(seg).map(to_f64);
                    bx = if i == 0 { sb } else { union_box(bx, sb) };
                }
                let l = lipschitz.unwrap_or_else(|| sk.lipschitz().unwrap_or(T::INFINITY));
                Ok((SceneField::Homothetic(WithLipschitz::new(sk, l)), bx, n))
            }
        }
    }
}

impl HrbfSpec {
    fn build<T: Real>(&self, path: &str) -> Result<Hrbf<T, Vec<HrbfCenter<T>>>, FormatError> {
        if !self.centers.is_empty() || self.poly.is_some() {
            if !self.points.is_empty() || !self.normals.is_empty() {
                return Err(FormatError::at(
                    path,
                    "give either `points` and `normals` or `centers` and `poly`, not both",
                ));
            }
            let poly = self.poly.ok_or_else(|| {
                FormatError::at(&format!("{path}.poly"), "required with `centers`")
            })?;
            if self.centers.is_empty() {
                return Err(FormatError::at(
                    &format!("{path}.centers"),
                    "needs at least one center",
                ));
            }
            let mut cs = Vec::with_capacity(self.centers.len());
            for (i, c) in self.centers.iter().enumerate() {
                let p = format!("{path}.centers[{i}]");
                cs.push(HrbfCenter {
                    center: cvt(finite3(&format!("{p}.center"), c.center)?),
                    alpha: T::from_f64(finite(&format!("{p}.alpha"), c.alpha)?),
                    beta: cvt(finite3(&format!("{p}.beta"), c.beta)?),
                });
            }
            for (k, x) in poly.iter().enumerate() {
                finite(&format!("{path}.poly[{k}]"), *x)?;
            }
            return Hrbf::from_parts(cs, poly.map(T::from_f64)).map_err(|e| fe(path, e));
        }
        if self.points.is_empty() {
            return Err(FormatError::at(
                &format!("{path}.points"),
                "needs at least one point (or `centers` and `poly`)",
            ));
        }
        if self.points.len() != self.normals.len() {
            return Err(FormatError::at(
                &format!("{path}.normals"),
                format!(
                    "{} normals for {} points",
                    self.normals.len(),
                    self.points.len()
                ),
            ));
        }
        if self.points.len() > boundtrace_fields::hrbf::MAX_FIT_POINTS {
            return Err(FormatError::at(
                &format!("{path}.points"),
                format!(
                    "too many points to fit ({}, at most {})",
                    self.points.len(),
                    boundtrace_fields::hrbf::MAX_FIT_POINTS
                ),
            ));
        }
        let mut pts = Vec::with_capacity(self.points.len());
        let mut nrm = Vec::with_capacity(self.points.len());
        for (i, (p, n)) in self.points.iter().zip(&self.normals).enumerate() {
            pts.push(cvt(finite3(&format!("{path}.points[{i}]"), *p)?));
            let n = finite3(&format!("{path}.normals[{i}]"), *n)?;
            if n == [0.0; 3] {
                return Err(FormatError::at(
                    &format!("{path}.normals[{i}]"),
                    "zero normal",
                ));
            }
            nrm.push(cvt(n));
        }
        Hrbf::fit(&pts, &nrm).map_err(|e| fe(path, e))
    }
}

fn quat(path: &str, t: &TransformSpec) -> Result<[f64; 4], FormatError> {
    for (k, x) in t.rotation.iter().enumerate() {
        finite(&format!("{path}.rotation[{k}]"), *x)?;
    }
    finite3(&format!("{path}.translation"), t.translation)?;
    let n = t.rotation.iter().map(|x| x * x).sum::<f64>().sqrt();
    if !(n > 1e-12) {
        return Err(FormatError::at(
            &format!("{path}.rotation"),
            "zero quaternion",
        ));
    }
    // keep an already unit quaternion bit-for-bit (exact round trips)
    if (n - 1.0).abs() <= 1e-6 {
        Ok(t.rotation)
    } else {
        Ok(t.rotation.map(|x| x / n))
    }
}

/// `outer ∘ inner` of (quaternion, translation) pairs.
fn compose(outer: ([f64; 4], [f64; 3]), inner: ([f64; 4], [f64; 3])) -> ([f64; 4], [f64; 3]) {
    let (a, b) = (outer.0, inner.0);
    let q = [
        a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
        a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
        a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
        a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2],
    ];
    let t = rotate(a, inner.1);
    (q, [0, 1, 2].map(|k| t[k] + outer.1[k]))
}

type Placement = Option<([f64; 4], [f64; 3])>;

impl NodeSpec {
    fn build<T: Real>(
        &self,
        path: &str,
        outer: Placement,
        depth: usize,
    ) -> Result<Node<T>, FormatError> {
        if depth > MAX_TREE_DEPTH {
            return Err(FormatError::at(
                path,
                format!("tree nested deeper than {MAX_TREE_DEPTH} levels"),
            ));
        }
        let key = match self {
            NodeSpec::Sphere { .. } => "sphere",
            NodeSpec::Box { .. } => "box",
            NodeSpec::RoundedBox { .. } => "rounded-box",
            NodeSpec::Capsule { .. } => "capsule",
            NodeSpec::Cylinder { .. } => "cylinder",
            NodeSpec::Torus { .. } => "torus",
            NodeSpec::Plane { .. } => "plane",
            NodeSpec::Cone { .. } => "cone",
            NodeSpec::Ellipsoid { .. } => "ellipsoid",
            NodeSpec::Gyroid { .. } => "gyroid",
            NodeSpec::Blob { .. } => "blob",
            _ => "",
        };
        let prim_path = format!("{path}.{key}");
        let path_outer = path;
        let path = prim_path.as_str();
        let pp = |name: &str| format!("{path}.{name}");
        let (kind, shape, transform) = match self {
            NodeSpec::Union(o) => return o.build(OpName::Union, path_outer, outer, depth),
            NodeSpec::Intersection(o) => {
                return o.build(OpName::Intersection, path_outer, outer, depth);
            }
            NodeSpec::Difference(o) => {
                return o.build(OpName::Difference, path_outer, outer, depth);
            }
            NodeSpec::SmoothUnion(o) => {
                return o.build(OpName::SmoothUnion, path_outer, outer, depth);
            }
            NodeSpec::SmoothIntersection(o) => {
                return o.build(OpName::SmoothIntersection, path_outer, outer, depth);
            }
            NodeSpec::SmoothDifference(o) => {
                return o.build(OpName::SmoothDifference, path_outer, outer, depth);
            }
            NodeSpec::CompactUnion(o) => {
                return o.build(OpName::CompactUnion, path_outer, outer, depth);
            }
            NodeSpec::CompactIntersection(o) => {
                return o.build(OpName::CompactIntersection, path_outer, outer, depth);
            }
            NodeSpec::CompactDifference(o) => {
                return o.build(OpName::CompactDifference, path_outer, outer, depth);
            }
            NodeSpec::Sphere { radius, transform } => (
                PrimitiveKind::Sphere,
                [positive(&pp("radius"), *radius)?, 0.0, 0.0, 0.0],
                transform,
            ),
            NodeSpec::Box {
                half_extents: h,
                transform,
            } => {
                for (k, x) in h.iter().enumerate() {
                    positive(&format!("{path}.half_extents[{k}]"), *x)?;
                }
                (PrimitiveKind::Box, [h[0], h[1], h[2], 0.0], transform)
            }
            NodeSpec::RoundedBox {
                half_extents: h,
                rounding,
                transform,
            } => {
                for (k, x) in h.iter().enumerate() {
                    positive(&format!("{path}.half_extents[{k}]"), *x)?;
                }
                let r = nonneg(&pp("rounding"), *rounding)?;
                if r > h[0].min(h[1]).min(h[2]) {
                    return Err(FormatError::at(
                        &pp("rounding"),
                        "must not exceed the smallest half extent",
                    ));
                }
                (PrimitiveKind::RoundedBox, [h[0], h[1], h[2], r], transform)
            }
            NodeSpec::Capsule {
                half_length,
                radius,
                transform,
            } => (
                PrimitiveKind::Capsule,
                [
                    positive(&pp("half_length"), *half_length)?,
                    positive(&pp("radius"), *radius)?,
                    0.0,
                    0.0,
                ],
                transform,
            ),
            NodeSpec::Cylinder {
                half_length,
                radius,
                transform,
            } => (
                PrimitiveKind::Cylinder,
                [
                    positive(&pp("half_length"), *half_length)?,
                    positive(&pp("radius"), *radius)?,
                    0.0,
                    0.0,
                ],
                transform,
            ),
            NodeSpec::Torus {
                major,
                minor,
                transform,
            } => (
                PrimitiveKind::Torus,
                [
                    positive(&pp("major"), *major)?,
                    positive(&pp("minor"), *minor)?,
                    0.0,
                    0.0,
                ],
                transform,
            ),
            NodeSpec::Plane { transform } => (PrimitiveKind::Plane, [0.0; 4], transform),
            NodeSpec::Cone {
                half_length,
                radius_a,
                radius_b,
                transform,
            } => (
                PrimitiveKind::Cone,
                [
                    positive(&pp("half_length"), *half_length)?,
                    nonneg(&pp("radius_a"), *radius_a)?,
                    nonneg(&pp("radius_b"), *radius_b)?,
                    0.0,
                ],
                transform,
            ),
            NodeSpec::Ellipsoid { radii, transform } => {
                for (k, x) in radii.iter().enumerate() {
                    positive(&format!("{path}.radii[{k}]"), *x)?;
                }
                (
                    PrimitiveKind::Ellipsoid,
                    [radii[0], radii[1], radii[2], 0.0],
                    transform,
                )
            }
            NodeSpec::Gyroid {
                period,
                thickness,
                transform,
            } => (
                PrimitiveKind::Gyroid,
                [
                    positive(&pp("period"), *period)?,
                    positive(&pp("thickness"), *thickness)?,
                    0.0,
                    0.0,
                ],
                transform,
            ),
            NodeSpec::Blob {
                radius,
                iso,
                degree: n,
                transform,
            } => {
                degree(&pp("degree"), *n)?;
                let iso = positive(&pp("iso"), *iso)?;
                if !(iso < 1.0) {
                    return Err(FormatError::at(&pp("iso"), "must be in (0, 1)"));
                }
                (
                    PrimitiveKind::Blob,
                    [positive(&pp("radius"), *radius)?, iso, f64::from(*n), 0.0],
                    transform,
                )
            }
        };
        let q = quat(&pp("transform"), transform)?;
        let (q, t) = match outer {
            Some(o) => compose(o, (q, transform.translation)),
            None => (q, transform.translation),
        };
        let mut params = [0f32; 12];
        let all = [
            q[0], q[1], q[2], q[3], t[0], t[1], t[2], 0.0, shape[0], shape[1], shape[2], shape[3],
        ];
        for (k, v) in all.iter().enumerate() {
            let f = *v as f32;
            if !f.is_finite() {
                return Err(FormatError::at(path, "a parameter overflows f32"));
            }
            params[k] = f;
        }
        let prim = Primitive::<T>::read_params(kind, &params)
            .ok_or_else(|| FormatError::at(path, "invalid primitive parameters for this type"))?;
        Ok(Node::primitive(prim))
    }
}

impl OperatorSpec {
    fn build<T: Real>(
        &self,
        name: OpName,
        path: &str,
        outer: Placement,
        depth: usize,
    ) -> Result<Node<T>, FormatError> {
        let path = &format!("{path}.{}", name.key());
        let beta = |need: bool| -> Result<f64, FormatError> {
            match (self.beta, need) {
                (Some(b), true) => positive(&format!("{path}.beta"), b),
                (None, true) => Err(FormatError::at(
                    &format!("{path}.beta"),
                    "required for smooth and compact operators",
                )),
                (Some(_), false) => Err(FormatError::at(
                    &format!("{path}.beta"),
                    "only smooth and compact operators have a blend width",
                )),
                (None, false) => Ok(0.0),
            }
        };
        let compact = matches!(
            name,
            OpName::CompactUnion | OpName::CompactIntersection | OpName::CompactDifference
        );
        if self.r_o.is_some() && !compact {
            return Err(FormatError::at(
                &format!("{path}.r_o"),
                "only compact operators have an outer range",
            ));
        }
        let smooth = !matches!(
            name,
            OpName::Union | OpName::Intersection | OpName::Difference
        );
        let b = T::from_f64(beta(smooth)?);
        let r_o = |kind: OperatorKind| -> Result<T, FormatError> {
            match self.r_o {
                Some(r) => Ok(T::from_f64(positive(&format!("{path}.r_o"), r)?)),
                None => Ok(Operator::<T>::default_r_o(b).max(Operator::<T>::min_r_o(kind, b))),
            }
        };
        let op = match name {
            OpName::Union => Ok(Operator::union()),
            OpName::Intersection => Ok(Operator::intersection()),
            OpName::Difference => Ok(Operator::difference()),
            OpName::SmoothUnion => Operator::smooth_union(b),
            OpName::SmoothIntersection => Operator::smooth_intersection(b),
            OpName::SmoothDifference => Operator::smooth_difference(b),
            OpName::CompactUnion => Operator::compact_union(b, r_o(OperatorKind::CompactUnion)?),
            OpName::CompactIntersection => {
                Operator::compact_intersection(b, r_o(OperatorKind::CompactIntersection)?)
            }
            OpName::CompactDifference => {
                Operator::compact_difference(b, r_o(OperatorKind::CompactDifference)?)
            }
        }
        .map_err(|e| fe(path, e))?;
        if self.children.is_empty() {
            return Err(FormatError::at(
                &format!("{path}.children"),
                "empty tree: an operator needs at least two children",
            ));
        }
        if self.children.len() < 2 {
            return Err(FormatError::at(
                &format!("{path}.children"),
                "an operator needs at least two children",
            ));
        }
        let own = if self.transform.is_identity() {
            None
        } else {
            let tp = format!("{path}.transform");
            Some((quat(&tp, &self.transform)?, self.transform.translation))
        };
        let placement = match (outer, own) {
            (Some(o), Some(i)) => Some(compose(o, i)),
            (o, i) => o.or(i),
        };
        let mut acc: Option<Node<T>> = None;
        for (i, c) in self.children.iter().enumerate() {
            let n = c.build(&format!("{path}.children[{i}]"), placement, depth + 1)?;
            acc = Some(match acc {
                None => n,
                Some(a) => Node::op(op, a, n),
            });
        }
        acc.ok_or_else(|| FormatError::at(path, "empty tree"))
    }
}

impl NodeSpec {
    /// `(nodes, stack)`: the node count of the binary tree this node
    /// becomes (an operator with `k` children folds into `k − 1` binary
    /// nodes) and the evaluation stack its flat post-order needs, with the
    /// operand reordering of `FlatBlobtree::from_node_reordered`
    /// (Sethi–Ullman: the operands of union- and intersection-like
    /// operators may be swapped, those of differences may not). Counts
    /// saturate; the recursion depth is bounded by the parser's nesting
    /// limit.
    fn encoding_needs(&self) -> (usize, usize) {
        let (op, swappable) = match self {
            NodeSpec::Union(o)
            | NodeSpec::Intersection(o)
            | NodeSpec::SmoothUnion(o)
            | NodeSpec::SmoothIntersection(o)
            | NodeSpec::CompactUnion(o)
            | NodeSpec::CompactIntersection(o) => (o, true),
            NodeSpec::Difference(o)
            | NodeSpec::SmoothDifference(o)
            | NodeSpec::CompactDifference(o) => (o, false),
            _ => return (1, 1),
        };
        let mut acc: Option<(usize, usize)> = None;
        for c in &op.children {
            let (n, s) = c.encoding_needs();
            acc = Some(match acc {
                None => (n, s),
                Some((an, a)) => {
                    let need = if swappable {
                        a.max(s).max(a.min(s).saturating_add(1))
                    } else {
                        a.max(s.saturating_add(1))
                    };
                    (an.saturating_add(n).saturating_add(1), need)
                }
            });
        }
        acc.unwrap_or((1, 1))
    }
}

/// Rejects a blobtree that the flat encoding cannot hold (more than
/// [`MAX_NODES`](boundtrace_fields::blobtree::MAX_NODES) nodes, or an
/// evaluation stack deeper than
/// [`STACK_CAPACITY`](boundtrace_fields::blobtree::STACK_CAPACITY)), before
/// anything is built.
fn check_encoding(root: &NodeSpec, path: &str) -> Result<(), FormatError> {
    use boundtrace_fields::blobtree::{MAX_NODES, STACK_CAPACITY};
    let (nodes, stack) = root.encoding_needs();
    if nodes > MAX_NODES {
        return Err(FormatError::at(
            path,
            format!(
                "tree too large for the encoding: {nodes} nodes after folding operators \
                 into binary ones (the flat blobtree holds at most {MAX_NODES})"
            ),
        ));
    }
    if stack > STACK_CAPACITY {
        return Err(FormatError::at(
            path,
            format!(
                "tree too large for the encoding: evaluating it needs a stack of {stack} \
                 entries (at most {STACK_CAPACITY}); nest deep subtrees as the first operand \
                 of difference operators (e.g. subtract one union of the cut-outs instead of \
                 nesting differences), or balance the tree"
            ),
        ));
    }
    Ok(())
}

impl OpName {
    /// The key of the operator in the file (`"compact-union"`, …).
    pub fn key(self) -> &'static str {
        match self {
            OpName::Union => "union",
            OpName::Intersection => "intersection",
            OpName::Difference => "difference",
            OpName::SmoothUnion => "smooth-union",
            OpName::SmoothIntersection => "smooth-intersection",
            OpName::SmoothDifference => "smooth-difference",
            OpName::CompactUnion => "compact-union",
            OpName::CompactIntersection => "compact-intersection",
            OpName::CompactDifference => "compact-difference",
        }
    }
}

impl SceneFile {
    /// Validates every value and builds the tracer scene in `T`.
    ///
    /// # Errors
    /// A [`FormatError`] naming the JSON path of the first invalid value.
    pub fn build<T: Real>(&self) -> Result<Scene<T>, FormatError> {
        let (field, computed, count): (SceneField<T>, Option<[[f64; 3]; 2]>, usize) =
            match &self.field {
                FieldSpec::Blobs {
                    iso,
                    blobs,
                    lipschitz,
                } => {
                    let b = build_blobs::<T>("field.blobs", *iso, blobs)?;
                    let f = match lipschitz {
                        Some(l) => SceneField::Molecule(WithLipschitz::new(
                            b,
                            T::from_f64(positive("field.blobs.lipschitz", *l)?),
                        )),
                        None => SceneField::Blobs(b),
                    };
                    (f, blob_box(*iso, blobs), blobs.len())
                }
                FieldSpec::BlobGroups { groups } => {
                    if groups.is_empty() {
                        return Err(FormatError::at(
                            "field.blob-groups.groups",
                            "needs at least one group",
                        ));
                    }
                    let mut sets = Vec::with_capacity(groups.len());
                    let mut bx = None;
                    let mut n = 0;
                    for (i, g) in groups.iter().enumerate() {
                        let p = format!("field.blob-groups.groups[{i}]");
                        sets.push(build_blobs::<T>(&p, g.iso, &g.blobs)?);
                        let gb = blob_box(g.iso, &g.blobs);
                        bx = if i == 0 { gb } else { union_box(bx, gb) };
                        n += g.blobs.len();
                    }
                    let u = UnionAll::new(sets).map_err(|e| fe("field.blob-groups.groups", e))?;
                    (SceneField::BlobGroups(u), bx, n)
                }
                FieldSpec::Skeleton(s) => s.build::<T>("field.skeleton")?,
                FieldSpec::Hrbf(h) => {
                    let f = h.build::<T>("field.hrbf")?;
                    let n = f.centers().len();
                    (SceneField::Hrbf(f), None, n)
                }
                FieldSpec::Blobtree { root } => {
                    check_encoding(root, "field.blobtree.root")?;
                    let node = root.build::<f64>("field.blobtree.root", None, 0)?;
                    let flat = FlatBlobtree::from_node_reordered(&node)
                        .map_err(|e| fe("field.blobtree.root", e))?;
                    let n = flat.primitive_indices().len();
                    (SceneField::Blobtree(flat), None, n)
                }
            };
        let bounds = match (self.bounds, computed) {
            (Some(b), _) => {
                for (i, c) in b.iter().enumerate() {
                    finite3(&format!("bounds[{i}]"), *c)?;
                }
                if !(0..3).all(|k| b[0][k] < b[1][k]) {
                    return Err(FormatError::at("bounds", "needs min < max on every axis"));
                }
                b
            }
            (None, Some(b)) => grow(b),
            (None, None) => {
                return Err(FormatError::at(
                    "bounds",
                    "required for this field (only compact blobs with iso > 0 and \
                     compact skeletons have computed bounds)",
                ));
            }
        };
        let inside = match self.inside {
            Some(p) => finite3("inside", p)?,
            None => [0, 1, 2].map(|k| 0.5 * (bounds[0][k] + bounds[1][k])),
        };
        for (i, l) in self.lights.iter().enumerate() {
            let p = format!("lights[{i}]");
            let d = finite3(&format!("{p}.direction"), l.direction)?;
            if d == [0.0; 3] {
                return Err(FormatError::at(&format!("{p}.direction"), "zero direction"));
            }
            for (k, c) in l.color.iter().enumerate() {
                if !(0.0..=1.0).contains(c) {
                    return Err(FormatError::at(
                        &format!("{p}.color[{k}]"),
                        "must be in [0, 1]",
                    ));
                }
            }
            nonneg(&format!("{p}.intensity"), l.intensity)?;
        }
        if let Some(m) = &self.material {
            if !(0.0..=1.0).contains(&m.ambient) {
                return Err(FormatError::at("material.ambient", "must be in [0, 1]"));
            }
        }
        let name = self.scene_name();
        let description = self
            .description
            .clone()
            .unwrap_or_else(|| format!("scene file `{name}`"));
        Scene::from_parts(
            name,
            description,
            [cvt(bounds[0]), cvt(bounds[1])],
            cvt(inside),
            field,
            count,
        )
        .map_err(|e| FormatError::at("bounds", e.to_string()))
    }

    /// Samples `f` on a `g × g` grid of each face of the bounds: the surface
    /// must stay inside (`f > 0` on the faces). Returns the number of
    /// samples, or the first sample where `f ≤ 0` (or NaN) as an error.
    ///
    /// # Errors
    /// A [`FormatError`] at `bounds` naming the point and value.
    pub fn check_bounds(scene: &Scene<f64>, g: usize) -> Result<usize, FormatError> {
        let [lo, hi] = scene.bounds();
        let field = scene.field();
        let g = g.max(2);
        let mut n = 0;
        for axis in 0..3 {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            for side in [lo[axis], hi[axis]] {
                for i in 0..g {
                    for j in 0..g {
                        let mut p = [0.0; 3];
                        p[axis] = side;
                        p[u] = lo[u] + (hi[u] - lo[u]) * i as f64 / (g - 1) as f64;
                        p[v] = lo[v] + (hi[v] - lo[v]) * j as f64 / (g - 1) as f64;
                        let f: f64 = field.eval(p);
                        if !(f > 0.0) {
                            return Err(FormatError::at(
                                "bounds",
                                format!(
                                    "the surface leaves the box: f = {f} at {p:?} on a face \
                                     (f must be > 0 there)"
                                ),
                            ));
                        }
                        n += 1;
                    }
                }
            }
        }
        Ok(n)
    }

    /// The file of a standard scene (or any [`Scene`]): its exact data,
    /// bounds and inside point, and the default camera. Building it again
    /// in `f64` gives a bit-identical field.
    ///
    /// # Errors
    /// A [`FormatError`] when the scene cannot be expressed (a skeleton
    /// whose segments have different kernels or iso values, a blobtree
    /// that does not decode).
    pub fn from_scene(scene: &Scene<f64>) -> Result<Self, FormatError> {
        let blob = |b: &PointBlob<f64>| BlobSpec {
            center: b.center(),
            weight: b.weight(),
            kernel: KernelSpec::of(&b.kernel()),
        };
        let field = match scene.field() {
            SceneField::BlobGroups(u) => FieldSpec::BlobGroups {
                groups: u
                    .children()
                    .iter()
                    .map(|g| BlobGroupSpec {
                        iso: g.iso(),
                        blobs: g.blobs().iter().map(blob).collect(),
                    })
                    .collect(),
            },
            SceneField::Blobs(b) => FieldSpec::Blobs {
                iso: b.iso(),
                blobs: b.blobs().iter().map(blob).collect(),
                lipschitz: None,
            },
            SceneField::Molecule(w) => FieldSpec::Blobs {
                iso: w.field().iso(),
                blobs: w.field().blobs().iter().map(blob).collect(),
                lipschitz: Some(w.bound()),
            },
            SceneField::Hrbf(h) => FieldSpec::Hrbf(HrbfSpec {
                points: Vec::new(),
                normals: Vec::new(),
                centers: h
                    .centers()
                    .iter()
                    .map(|c| HrbfCenterSpec {
                        center: c.center,
                        alpha: c.alpha,
                        beta: c.beta,
                    })
                    .collect(),
                poly: Some(h.poly()),
            }),
            SceneField::Scalis(_) | SceneField::Homothetic(_) => {
                FieldSpec::Skeleton(skeleton_spec(scene.field())?)
            }
            SceneField::Blobtree(flat) => {
                let node: Node<f64> = flat.to_node().map_err(|e| fe("field.root", e))?;
                FieldSpec::Blobtree {
                    root: node_spec(&node)?,
                }
            }
        };
        Ok(SceneFile {
            version: VERSION,
            name: Some(scene.name().to_string()),
            description: Some(scene.description().to_string()),
            field,
            bounds: Some(scene.bounds()),
            inside: Some(scene.inside_point()),
            camera: Some(CameraSpec::default()),
            lights: Vec::new(),
            material: None,
        })
    }
}

fn skeleton_spec(field: &SceneField<f64>) -> Result<SkeletonSpec, FormatError> {
    // (segment, kernel, iso) of every edge, and the skeleton's shared ones
    let (distance, segs, lipschitz): (Distance, Vec<_>, f64) = match field {
        SceneField::Scalis(w) => (
            Distance::Scalis,
            w.field()
                .segments()
                .iter()
                .map(|s| (*s.segment(), s.kernel(), s.iso()))
                .collect(),
            w.bound(),
        ),
        SceneField::Homothetic(w) => {
            let sk = w.field();
            (
                Distance::Homothetic,
                sk.segments()
                    .iter()
                    .map(|s| (*s, sk.kernel(), sk.iso()))
                    .collect(),
                w.bound(),
            )
        }
        _ => return Err(FormatError::at("field", "not a skeleton")),
    };
    let &(_, kernel, iso) = segs
        .first()
        .ok_or_else(|| FormatError::at("field.edges", "no segments"))?;
    let mut vertices: Vec<VertexSpec> = Vec::new();
    let mut index: HashMap<[u64; 4], usize> = HashMap::new();
    let mut vertex = |p: [f64; 3], r: f64| {
        let key = [p[0].to_bits(), p[1].to_bits(), p[2].to_bits(), r.to_bits()];
        *index.entry(key).or_insert_with(|| {
            vertices.push(VertexSpec {
                position: p,
                radius: r,
            });
            vertices.len() - 1
        })
    };
    let mut edges = Vec::with_capacity(segs.len());
    for (i, (g, k, s_iso)) in segs.iter().enumerate() {
        if *k != kernel || *s_iso != iso {
            return Err(FormatError::at(
                &format!("field.edges[{i}]"),
                "segments with different kernels or iso values cannot be written",
            ));
        }
        let a = vertex(g.a(), g.ra());
        let b = vertex(g.b(), g.rb());
        edges.push([a, b]);
    }
    Ok(SkeletonSpec {
        distance,
        kernel: SegmentKernelSpec::of(kernel),
        iso,
        vertices,
        edges,
        lipschitz: Some(lipschitz),
    })
}

fn transform_of(p: &Primitive<f64>) -> TransformSpec {
    TransformSpec {
        rotation: p.rigid().rotation(),
        translation: p.rigid().translation_vector(),
    }
}

fn node_spec(node: &Node<f64>) -> Result<NodeSpec, FormatError> {
    // explicit stack: trees from files may be deep (recursion-free export)
    enum Task<'a> {
        Visit(&'a Node<f64>),
        Build(&'a Operator<f64>),
    }
    let mut tasks = vec![Task::Visit(node)];
    let mut done: Vec<NodeSpec> = Vec::new();
    while let Some(t) = tasks.pop() {
        match t {
            Task::Visit(n) => {
                if let Some(p) = n.as_primitive() {
                    done.push(primitive_spec(p)?);
                } else if let Some((op, a, b)) = n.as_operator() {
                    tasks.push(Task::Build(op));
                    tasks.push(Task::Visit(b));
                    tasks.push(Task::Visit(a));
                }
            }
            Task::Build(op) => {
                let (b, a) = (done.pop(), done.pop());
                let (Some(a), Some(b)) = (a, b) else {
                    return Err(FormatError::at("field.root", "malformed tree"));
                };
                let name = match op.kind() {
                    OperatorKind::Union => OpName::Union,
                    OperatorKind::Intersection => OpName::Intersection,
                    OperatorKind::Difference => OpName::Difference,
                    OperatorKind::SmoothUnion => OpName::SmoothUnion,
                    OperatorKind::SmoothIntersection => OpName::SmoothIntersection,
                    OperatorKind::SmoothDifference => OpName::SmoothDifference,
                    OperatorKind::CompactUnion => OpName::CompactUnion,
                    OperatorKind::CompactIntersection => OpName::CompactIntersection,
                    OperatorKind::CompactDifference => OpName::CompactDifference,
                };
                let smooth = !matches!(
                    name,
                    OpName::Union | OpName::Intersection | OpName::Difference
                );
                let compact = matches!(
                    name,
                    OpName::CompactUnion | OpName::CompactIntersection | OpName::CompactDifference
                );
                let body = OperatorSpec {
                    beta: smooth.then(|| op.beta()),
                    r_o: compact.then(|| op.r_o()),
                    children: vec![a, b],
                    transform: TransformSpec::default(),
                };
                done.push(match name {
                    OpName::Union => NodeSpec::Union(body),
                    OpName::Intersection => NodeSpec::Intersection(body),
                    OpName::Difference => NodeSpec::Difference(body),
                    OpName::SmoothUnion => NodeSpec::SmoothUnion(body),
                    OpName::SmoothIntersection => NodeSpec::SmoothIntersection(body),
                    OpName::SmoothDifference => NodeSpec::SmoothDifference(body),
                    OpName::CompactUnion => NodeSpec::CompactUnion(body),
                    OpName::CompactIntersection => NodeSpec::CompactIntersection(body),
                    OpName::CompactDifference => NodeSpec::CompactDifference(body),
                });
            }
        }
    }
    match (done.pop(), done.is_empty()) {
        (Some(n), true) => Ok(n),
        _ => Err(FormatError::at("field.root", "malformed tree")),
    }
}

fn primitive_spec(p: &Primitive<f64>) -> Result<NodeSpec, FormatError> {
    let s = p.shape_params();
    let transform = transform_of(p);
    Ok(match p.kind() {
        PrimitiveKind::Sphere => NodeSpec::Sphere {
            radius: s[0],
            transform,
        },
        PrimitiveKind::Box => NodeSpec::Box {
            half_extents: [s[0], s[1], s[2]],
            transform,
        },
        PrimitiveKind::RoundedBox => NodeSpec::RoundedBox {
            half_extents: [s[0], s[1], s[2]],
            rounding: s[3],
            transform,
        },
        PrimitiveKind::Capsule => NodeSpec::Capsule {
            half_length: s[0],
            radius: s[1],
            transform,
        },
        PrimitiveKind::Cylinder => NodeSpec::Cylinder {
            half_length: s[0],
            radius: s[1],
            transform,
        },
        PrimitiveKind::Torus => NodeSpec::Torus {
            major: s[0],
            minor: s[1],
            transform,
        },
        PrimitiveKind::Plane => NodeSpec::Plane { transform },
        PrimitiveKind::Cone => NodeSpec::Cone {
            half_length: s[0],
            radius_a: s[1],
            radius_b: s[2],
            transform,
        },
        PrimitiveKind::Ellipsoid => NodeSpec::Ellipsoid {
            radii: [s[0], s[1], s[2]],
            transform,
        },
        PrimitiveKind::Gyroid => NodeSpec::Gyroid {
            period: s[0],
            thickness: s[1],
            transform,
        },
        PrimitiveKind::Blob => NodeSpec::Blob {
            radius: s[0],
            iso: s[1],
            degree: s[2] as u32,
            transform,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_err(text: &str) -> FormatError {
        match SceneFile::parse(text) {
            Err(e) => e,
            Ok(f) => f.build::<f64>().map(|_| ()).unwrap_err(),
        }
    }

    #[test]
    fn syntax_errors_have_line_and_column() {
        let e = parse_err("{\n  \"version\": 1,\n  \"field\": {\"type\": \"blobs\",, }\n}");
        assert_eq!(e.position.map(|p| p.0), Some(3), "{e}");
        assert!(e.to_string().starts_with("line 3, column"), "{e}");
    }

    #[test]
    fn unknown_kernel_names_the_path() {
        let e = parse_err(
            r#"{"version": 1, "field": {"blobs": {"iso": 0.5, "blobs": [
            {"center": [0,0,0], "kernel": {"wendland": {"sigma": 1}}}]}}}"#,
        );
        let s = e.to_string();
        assert!(
            s.contains("field.blobs.blobs[0].kernel") && s.contains("wendland"),
            "{s}"
        );
    }

    #[test]
    fn zero_length_segment_and_bad_index() {
        let base = |edges: &str| {
            format!(
                r#"{{"version": 1, "field": {{"skeleton": {{"iso": 1,
                "kernel": {{"compact": {{"degree": 6, "sigma": 2}}}},
                "vertices": [{{"position": [0,0,0], "radius": 0.1}},
                             {{"position": [0,0,0], "radius": 0.2}},
                             {{"position": [1,0,0], "radius": 0.1}}],
                "edges": {edges}}}}}}}"#
            )
        };
        let e = parse_err(&base("[[0, 1]]"));
        assert!(
            e.to_string().contains("field.skeleton.edges[0]") && e.message.contains("zero-length")
        );
        let e = parse_err(&base("[[0, 7]]"));
        assert!(e.to_string().contains("field.skeleton.edges[0][1]"), "{e}");
        assert!(
            SceneFile::parse(&base("[[0, 2]]"))
                .unwrap()
                .build::<f64>()
                .is_ok()
        );
    }

    /// A right comb of `depth` differences of spheres, as JSON.
    fn difference_comb(depth: usize) -> String {
        let sphere = r#"{"sphere": {"radius": 0.5}}"#;
        let mut node = sphere.to_string();
        for _ in 0..depth {
            node = format!(r#"{{"difference": {{"children": [{sphere}, {node}]}}}}"#);
        }
        format!(
            r#"{{"version": 1, "bounds": [[-1,-1,-1],[1,1,1]], "field": {{"blobtree": {{"root": {node}}}}}}}"#
        )
    }

    /// The pre-check agrees with the flat encoding: node counts equal the
    /// built tree's, and the stack limit is refused exactly where
    /// `FlatBlobtree::from_node_reordered` refuses it.
    #[test]
    fn encoding_needs_match_the_flat_tree() {
        use boundtrace_fields::blobtree::STACK_CAPACITY;
        for depth in [1, 5, STACK_CAPACITY - 1, STACK_CAPACITY, STACK_CAPACITY + 3] {
            let file = SceneFile::parse(&difference_comb(depth)).unwrap();
            let FieldSpec::Blobtree { root } = &file.field else {
                unreachable!()
            };
            let (nodes, stack) = root.encoding_needs();
            assert_eq!((nodes, stack), (2 * depth + 1, depth + 1));
            let node = root.build::<f64>("r", None, 0).unwrap();
            let flat = FlatBlobtree::from_node_reordered(&node);
            assert_eq!(flat.is_ok(), stack <= STACK_CAPACITY, "depth {depth}");
            if let Ok(flat) = flat {
                assert_eq!(flat.len(), nodes);
            }
            let built = file.build::<f64>();
            assert_eq!(built.is_ok(), stack <= STACK_CAPACITY);
            if let Err(e) = built {
                assert_eq!(e.path, "field.blobtree.root");
                assert!(e.message.contains("too large for the encoding"), "{e}");
            }
        }
        // n-ary union-like operators fold into balanced-enough trees
        let text = r#"{"version": 1, "bounds": [[-1,-1,-1],[1,1,1]], "field": {"blobtree":
            {"root": {"smooth-union": {"beta": 0.1, "children": [
              {"sphere": {"radius": 0.5}}, {"box": {"half_extents": [0.2, 0.2, 0.2]}},
              {"union": {"children": [{"sphere": {"radius": 0.1}}, {"sphere": {"radius": 0.2}},
                                      {"sphere": {"radius": 0.3}}]}}]}}}}}"#;
        let file = SceneFile::parse(text).unwrap();
        let FieldSpec::Blobtree { root } = &file.field else {
            unreachable!()
        };
        let flat =
            FlatBlobtree::from_node_reordered(&root.build::<f64>("r", None, 0).unwrap()).unwrap();
        assert_eq!(root.encoding_needs().0, flat.len());
        assert_eq!(flat.len(), 9);
    }

    #[test]
    fn homothetic_skeleton_builds_and_round_trips() {
        let text = r#"{"version": 1, "field": {"skeleton": {"distance": "homothetic",
            "iso": 1, "kernel": {"compact": {"degree": 4, "sigma": 1.5}},
            "vertices": [{"position": [0,0,0], "radius": 0.2},
                         {"position": [1,0,0], "radius": 0.3},
                         {"position": [1,1,0], "radius": 0.1}],
            "edges": [[0, 1], [1, 2]]}}}"#;
        let file = SceneFile::parse(text).unwrap();
        let scene = file.build::<f64>().unwrap();
        assert!(matches!(scene.field(), SceneField::Homothetic(_)));
        assert_eq!(scene.primitive_count(), 2);
        // computed bounds: the σ-scaled supports, grown by 2 %
        let [lo, hi] = scene.bounds();
        assert!(lo[0] < -0.45 && hi[0] > 1.45 && hi[1] > 1.45);
        assert!(SceneFile::check_bounds(&scene, 9).is_ok());
        let field = scene.field();
        assert!(field.eval([0.5, 0.0, 0.0]) < 0.0);
        // export and rebuild: the same field
        let again = SceneFile::parse(&SceneFile::from_scene(&scene).unwrap().to_json())
            .unwrap()
            .build::<f64>()
            .unwrap();
        let p = [0.4, 0.2, 0.05];
        assert_eq!(field.eval(p), again.field().eval(p));
        // σ ≤ 1 names the kernel's sigma
        let e = parse_err(&text.replace("\"sigma\": 1.5", "\"sigma\": 0.9"));
        assert_eq!(e.path, "field.skeleton.kernel.compact.sigma", "{e}");
        let e = parse_err(&text.replace("\"degree\": 4", "\"degree\": 3"));
        assert_eq!(e.path, "field.skeleton.kernel.compact.degree", "{e}");
    }

    #[test]
    fn transforms_compose_like_rigid() {
        use boundtrace_fields::transform::Rigid;
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let a = ([0.0, 0.0, h, h], [1.0, 2.0, 3.0]);
        let b = ([h, 0.0, 0.0, h], [0.5, -1.0, 0.25]);
        let (q, t) = compose(a, b);
        let ra = Rigid::new(a.0, a.1).unwrap();
        let rb = Rigid::new(b.0, b.1).unwrap();
        let r = ra.then_after(&rb);
        let p = [0.3, -0.7, 1.1];
        let want = r.to_world_point(p);
        let got = rotate(q, p);
        for k in 0..3 {
            assert!(
                (got[k] + t[k] - want[k]).abs() < 1e-12,
                "{got:?} {t:?} {want:?}"
            );
        }
    }

    #[test]
    fn empty_tree_and_version() {
        let e = parse_err(
            r#"{"version": 1, "bounds": [[-1,-1,-1],[1,1,1]], "field": {"blobtree":
            {"root": {"union": {"children": []}}}}}"#,
        );
        assert!(
            e.to_string().contains("field.blobtree.root.union.children")
                && e.message.contains("empty")
        );
        let e = parse_err(r#"{"version": 2, "field": {"blobs": {"iso": 1, "blobs": []}}}"#);
        assert!(e.to_string().contains("version 2"), "{e}");
    }
}
