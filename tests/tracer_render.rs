//! Cameras, ray–box spans, PNG files, colormaps and rendering of the
//! tracer crate, through the facade.
//!
//! The PNG checks decode the encoder's output with an independent
//! (bit-by-bit) CRC-32 and Adler-32 and a stored-block inflater. The
//! rendering checks trace an off-centre ball (a signed distance with
//! Lipschitz bound 1) and compare every pixel with the analytic
//! ray–sphere intersection.

mod common;

use boundtrace::inclusion::{FieldNum, Ray};
use boundtrace::tracer::camera::{Camera, CameraError, Projection, ray_box_span};
use boundtrace::tracer::image::{Image, PNG_SIGNATURE, heat, viridis};
use boundtrace::tracer::render::{Frame, RenderSettings, Shading, render};
use boundtrace::tracer::{Method, Mode, Params, Side, Status};
use common::shapes::Ball;

// ---------------------------------------------------------------- helpers

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

fn at(r: &Ray<f64>, t: f64) -> [f64; 3] {
    [0, 1, 2].map(|i| r.origin[i] + t * r.dir[i])
}

/// A small deterministic generator (64-bit LCG, top 53 bits).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

// ---------------------------------------------------------------- cameras

#[test]
fn perspective_centre_ray_points_at_the_target() {
    let eye = [3.0, -2.0, 4.0];
    let target = [0.5, 0.25, -1.0];
    let cam = Camera::perspective(eye, target, [0.0, 0.0, 1.0], 50.0, 4.0 / 3.0).unwrap();
    assert_eq!(cam.projection, Projection::Perspective);
    // odd sizes: pixel (w/2, h/2) is centred on the optical axis
    let ray = cam.ray(200, 150, 401, 301);
    assert_eq!(ray.origin, eye);
    let to_target = sub(target, eye);
    let expect = to_target.map(|c| c / norm(to_target));
    for (d, e) in ray.dir.iter().zip(expect) {
        assert!((d - e).abs() < 1e-12, "{:?}", ray.dir);
    }
    // unit directions everywhere, so t is a distance
    for (x, y) in [(0, 0), (400, 0), (0, 300), (123, 77)] {
        assert!((norm(cam.ray(x, y, 401, 301).dir) - 1.0).abs() < 1e-12);
    }
    // the top row looks up (towards +z here), the left column to the left
    let top = cam.ray(200, 0, 401, 301);
    assert!(dot(top.dir, [0.0, 0.0, 1.0]) > dot(ray.dir, [0.0, 0.0, 1.0]));
    let left = cam.ray(0, 150, 401, 301);
    assert!(dot(left.dir, cam.right) < 0.0);
    // the corner ray makes the expected angle: tan = |(sx, sy)|
    let corner = cam.ray_ndc(1.0, 1.0);
    let cos = dot(corner.dir, cam.forward);
    let tan = (1.0 - cos * cos).sqrt() / cos;
    let half = 25f64.to_radians().tan();
    assert!((tan - half * (1.0 + (4.0f64 / 3.0).powi(2)).sqrt()).abs() < 1e-12);
}

#[test]
fn orthographic_rays_are_parallel() {
    let cam = Camera::orthographic([0.0, 5.0, 0.0], [0.0; 3], [0.0, 0.0, 1.0], 2.0, 1.0).unwrap();
    assert_eq!(cam.projection, Projection::Orthographic);
    let first = cam.ray(0, 0, 16, 16);
    for (x, y) in [(15, 0), (0, 15), (15, 15), (7, 9)] {
        let r = cam.ray(x, y, 16, 16);
        assert_eq!(r.dir, first.dir);
        // origins lie on the view plane through the eye
        assert!(dot(sub(r.origin, cam.eye), cam.forward).abs() < 1e-15);
    }
    assert_eq!(first.dir, [0.0, -1.0, 0.0]);
    // the view is 2 high: corner pixel centres at ±(1 − 1/16)
    assert!((first.origin[2] - 0.9375).abs() < 1e-15);
    let last = cam.ray(15, 15, 16, 16);
    assert!((last.origin[2] + 0.9375).abs() < 1e-15);
}

#[test]
fn camera_errors() {
    let up = [0.0, 1.0, 0.0];
    let p = Camera::<f64>::perspective;
    assert_eq!(
        p([1.0; 3], [1.0; 3], up, 45.0, 1.0),
        Err(CameraError::EyeAtTarget)
    );
    assert_eq!(
        p([0.0, 3.0, 0.0], [0.0; 3], up, 45.0, 1.0),
        Err(CameraError::DegenerateUp)
    );
    assert_eq!(
        p([0.0, 0.0, 3.0], [0.0; 3], [0.0; 3], 45.0, 1.0),
        Err(CameraError::DegenerateUp)
    );
    assert_eq!(
        p([0.0, 0.0, 3.0], [0.0; 3], up, 0.0, 1.0),
        Err(CameraError::BadFieldOfView)
    );
    assert_eq!(
        p([0.0, 0.0, 3.0], [0.0; 3], up, 180.0, 1.0),
        Err(CameraError::BadFieldOfView)
    );
    assert_eq!(
        p([0.0, 0.0, 3.0], [0.0; 3], up, 45.0, -2.0),
        Err(CameraError::BadAspect)
    );
    assert_eq!(
        p([0.0, 0.0, f64::INFINITY], [0.0; 3], up, 45.0, 1.0),
        Err(CameraError::NotFinite)
    );
    let o = Camera::<f64>::orthographic;
    assert_eq!(
        o([0.0, 0.0, 3.0], [0.0; 3], up, -1.0, 1.0),
        Err(CameraError::BadViewHeight)
    );
    let f = Camera::<f64>::framing;
    assert_eq!(
        f([[0.0; 3], [-1.0; 3]], [1.0, 0.0, 0.0], 45.0, 1.0),
        Err(CameraError::BadBounds)
    );
    assert_eq!(
        f([[0.0; 3], [1.0; 3]], [0.0; 3], 45.0, 1.0),
        Err(CameraError::ZeroViewDirection)
    );
    // framing straight down the y axis picks +z as the image's top
    let cam = f([[0.0; 3], [1.0; 3]], [0.0, -1.0, 0.0], 45.0, 1.0).unwrap();
    assert!(cam.up[2] > 0.99);
    // errors are readable
    let e: Box<dyn std::error::Error> = Box::new(CameraError::BadFieldOfView);
    assert!(e.to_string().contains("field of view"));
}

// ---------------------------------------------------------------- spans

#[test]
fn span_cases() {
    let b = [[-1.0, -2.0, -3.0], [1.0, 2.0, 3.0]];
    // starting inside: t0 = 0
    let s = ray_box_span(&Ray::new([0.0; 3], [0.0, 0.0, 1.0]), &b).unwrap();
    assert_eq!(s[0], 0.0);
    assert!((s[1] - 3.0).abs() < 1e-14 && s[1] >= 3.0);
    // a miss, and a box behind the origin
    assert_eq!(
        ray_box_span(&Ray::new([5.0, 0.0, 0.0], [0.0, 1.0, 0.0]), &b),
        None
    );
    assert_eq!(
        ray_box_span(&Ray::new([5.0, 0.0, 0.0], [1.0, 0.0, 0.0]), &b),
        None
    );
    // axis-parallel rays: two zero components, along each axis
    for axis in 0..3 {
        let mut o = [0.5, -0.5, 0.25];
        let mut d = [0.0; 3];
        o[axis] = -10.0;
        d[axis] = 2.0;
        let s = ray_box_span(&Ray::new(o, d), &b).unwrap();
        let (lo, hi) = (b[0][axis], b[1][axis]);
        assert!((s[0] - (lo + 10.0) / 2.0).abs() < 1e-13, "axis {axis}");
        assert!((s[1] - (hi + 10.0) / 2.0).abs() < 1e-13, "axis {axis}");
        // shifted just outside the slab of another axis: miss
        let other = (axis + 1) % 3;
        o[other] = b[1][other] * 1.0001;
        assert_eq!(ray_box_span(&Ray::new(o, d), &b), None, "axis {axis}");
    }
    // negative zero direction components behave like zero
    let s = ray_box_span(&Ray::new([-5.0, 0.0, 0.0], [1.0, -0.0, -0.0]), &b).unwrap();
    assert!((s[0] - 4.0).abs() < 1e-14);
    // a flat box (zero thickness) is hit by a ray crossing it
    let flat = [[-1.0, -1.0, 0.0], [1.0, 1.0, 0.0]];
    let s = ray_box_span(&Ray::new([0.0, 0.0, -1.0], [0.0, 0.0, 1.0]), &flat).unwrap();
    assert!(s[0] <= 1.0 && s[1] >= 1.0 && s[1] - s[0] < 1e-14);
}

#[test]
fn span_points_are_in_the_box_and_its_ends_on_its_faces() {
    let b = [[-1.0, -0.5, 0.0], [2.0, 0.5, 1.5]];
    let inside =
        |p: [f64; 3], tol: f64| (0..3).all(|i| p[i] >= b[0][i] - tol && p[i] <= b[1][i] + tol);
    let mut rng = Lcg(7);
    let (mut hits, mut misses) = (0, 0);
    for _ in 0..2000 {
        let o = [0, 1, 2].map(|_| rng.range(-4.0, 4.0));
        // aim at a point of a larger box around the box, or anywhere
        let aim = [0, 1, 2].map(|i| rng.range(2.0 * b[0][i] - 0.5, 2.0 * b[1][i] + 0.5));
        let mut d = if rng.next() < 0.7 {
            sub(aim, o)
        } else {
            [0, 1, 2].map(|_| rng.range(-1.0, 1.0))
        };
        // a third of the rays have a zero component
        if rng.next() < 0.33 {
            d[(rng.next() * 3.0) as usize % 3] = 0.0;
        }
        let ray = Ray::new(o, d);
        match ray_box_span(&ray, &b) {
            Some([t0, t1]) => {
                hits += 1;
                assert!(0.0 <= t0 && t0 <= t1);
                for k in 0..=8 {
                    let t = t0 + (t1 - t0) * k as f64 / 8.0;
                    assert!(inside(at(&ray, t), 1e-9), "{ray:?} t = {t}");
                }
                // just beyond the far end the point is outside
                let beyond = t1 + 1e-6 * (1.0 + t1);
                assert!(!inside(at(&ray, beyond), 0.0) || norm(d) * (beyond - t1) < 1e-12);
                // just before the near end (if it is not the origin) too
                if t0 > 1e-3 {
                    assert!(!inside(at(&ray, t0 * (1.0 - 1e-6)), 0.0), "{ray:?}");
                }
            }
            None => {
                misses += 1;
                // no sample along the ray is in the box
                for k in 0..=200 {
                    let t = 10.0 * k as f64 / 200.0;
                    assert!(!inside(at(&ray, t), -1e-9), "{ray:?} t = {t}");
                }
            }
        }
    }
    assert!(hits > 100 && misses > 100, "{hits} {misses}");
}

// ---------------------------------------------------------------- PNG

/// CRC-32, bit by bit (independent of the encoder's table).
fn crc32_bitwise(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 == 1 {
                (c >> 1) ^ 0xedb8_8320
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// Decodes an RGB8 PNG made of stored deflate blocks, checking every
/// chunk CRC, the zlib header and the Adler-32.
fn decode(png: &[u8]) -> (u32, u32, Vec<[u8; 3]>) {
    assert_eq!(png[..8], PNG_SIGNATURE);
    let mut i = 8;
    let (mut w, mut h) = (0, 0);
    let mut z = Vec::new();
    let mut order = Vec::new();
    while i < png.len() {
        let len = u32::from_be_bytes(png[i..i + 4].try_into().unwrap()) as usize;
        let body = &png[i + 4..i + 8 + len];
        let crc = u32::from_be_bytes(png[i + 8 + len..i + 12 + len].try_into().unwrap());
        assert_eq!(crc, crc32_bitwise(body), "chunk CRC");
        let (kind, data) = (&body[..4], &body[4..]);
        order.push(String::from_utf8(kind.to_vec()).unwrap());
        match kind {
            b"IHDR" => {
                assert_eq!(len, 13);
                w = u32::from_be_bytes(data[0..4].try_into().unwrap());
                h = u32::from_be_bytes(data[4..8].try_into().unwrap());
                assert_eq!(
                    data[8..],
                    [8, 2, 0, 0, 0],
                    "8-bit RGB, deflate, no interlace"
                );
            }
            b"IDAT" => z.extend_from_slice(data),
            b"IEND" => assert_eq!(len, 0),
            _ => panic!("unexpected chunk"),
        }
        i += 12 + len;
    }
    assert_eq!(i, png.len());
    assert_eq!(order.first().map(String::as_str), Some("IHDR"));
    assert_eq!(order.last().map(String::as_str), Some("IEND"));
    // zlib: CMF/FLG check, then stored blocks
    assert_eq!((u16::from(z[0]) << 8 | u16::from(z[1])) % 31, 0);
    assert_eq!(z[0] & 0x0f, 8);
    let mut raw = Vec::new();
    let mut k = 2;
    loop {
        let last = z[k] & 1 == 1;
        assert_eq!(z[k] & 0b110, 0, "stored block");
        let len = u16::from_le_bytes([z[k + 1], z[k + 2]]) as usize;
        assert_eq!(!u16::from_le_bytes([z[k + 3], z[k + 4]]) as usize, len);
        raw.extend_from_slice(&z[k + 5..k + 5 + len]);
        k += 5 + len;
        if last {
            break;
        }
    }
    let (mut a, mut b) = (1u32, 0u32);
    for &x in &raw {
        a = (a + u32::from(x)) % 65_521;
        b = (b + a) % 65_521;
    }
    assert_eq!(z[k..], ((b << 16) | a).to_be_bytes(), "Adler-32");
    let row = 1 + 3 * w as usize;
    assert_eq!(raw.len(), row * h as usize);
    let mut pixels = Vec::new();
    for line in raw.chunks_exact(row) {
        assert_eq!(line[0], 0, "filter type None");
        pixels.extend(line[1..].chunks_exact(3).map(|c| [c[0], c[1], c[2]]));
    }
    (w, h, pixels)
}

#[test]
fn png_round_trips_through_an_independent_decoder() {
    // 250 × 100 RGB: 75 100 bytes of rows, two stored blocks
    let img = Image::from_fn(250, 100, |x, y| {
        [(x * 7) as u8, (y * 3) as u8, (x + y) as u8]
    })
    .unwrap();
    let (w, h, pixels) = decode(&img.to_png());
    assert_eq!((w, h), (250, 100));
    assert_eq!(pixels, img.pixels());
    // a 1 × 1 image
    let one = Image::new(1, 1, [1, 2, 3]).unwrap();
    assert_eq!(decode(&one.to_png()).2, [[1, 2, 3]]);
    // and through a file
    let path = std::env::temp_dir().join(format!("boundtrace-png-{}.png", std::process::id()));
    img.write_png(&path).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let _ = std::fs::remove_file(&path);
    assert_eq!(bytes, img.to_png());
    // a bad path is an error, not a panic
    assert!(
        img.write_png(std::env::temp_dir().join("no-such-dir/x/y.png"))
            .is_err()
    );
}

#[test]
fn heatmap_is_monotone_and_clamped() {
    let lum =
        |c: [u8; 3]| 0.2126 * f64::from(c[0]) + 0.7152 * f64::from(c[1]) + 0.0722 * f64::from(c[2]);
    for max in [1, 10, 75, 500] {
        let mut last = f64::NEG_INFINITY;
        // monotone up to the rounding of each channel to 8 bits (the
        // luminance of a rounded colour is within 0.5 of the exact one)
        for s in 0..=max {
            let l = lum(heat(s, max));
            assert!(l >= last - 1.0, "max {max}, step {s}");
            last = last.max(l);
        }
        assert_eq!(heat(max + 1, max), heat(max, max));
        assert_eq!(heat(u32::MAX, max), heat(max, max));
    }
    let mut last = f64::NEG_INFINITY;
    for k in 0..=1000 {
        let l = lum(viridis(f64::from(k) / 1000.0));
        assert!(l >= last - 1.0, "{k}");
        last = last.max(l);
    }
    // at the papers' display clamp of 75 steps, strictly increasing
    for s in 1..=75 {
        assert!(lum(heat(s, 75)) > lum(heat(s - 1, 75)), "step {s}");
    }
    assert!(lum(heat(75, 75)) - lum(heat(0, 75)) > 150.0); // uses the range
}

// ---------------------------------------------------------------- rendering

const BALL: Ball = Ball {
    c: [0.2, -0.1, 0.3],
    r: 0.8,
};

fn ball_bounds() -> [[f64; 3]; 2] {
    [BALL.c.map(|c| c - 1.0), BALL.c.map(|c| c + 1.0)]
}

/// The ray's roots on the ball, when the chord is clearly long (grazing
/// rays are left out): `Some([entry, exit])`, `None` when the ray clearly
/// misses; `Err(())` near the silhouette.
fn analytic(ray: &Ray<f64>) -> Result<Option<[f64; 2]>, ()> {
    let oc = sub(ray.origin, BALL.c);
    let b = dot(ray.dir, oc);
    let disc = b * b - (dot(oc, oc) - BALL.r * BALL.r);
    if disc > 1e-3 {
        Ok(Some([-b - disc.sqrt(), -b + disc.sqrt()]))
    } else if disc < -1e-3 {
        Ok(None)
    } else {
        Err(())
    }
}

fn camera() -> Camera<f64> {
    Camera::framing(ball_bounds(), [0.4, -0.3, -1.0], 45.0, 1.25).unwrap()
}

#[test]
fn render_bookkeeping_matches_the_camera_and_spans() {
    let bounds = ball_bounds();
    let cam = camera();
    for mode in [Mode::Opaque, Mode::Transparent] {
        let s = RenderSettings::new(40, 32, Method::Segment)
            .unwrap()
            .with_mode(mode);
        let frame = render(&BALL, &cam, bounds, &s).unwrap();
        assert_eq!((frame.width(), frame.height()), (40, 32));
        let t = frame.totals();
        assert_eq!(t.rays, 40 * 32);
        assert_eq!(
            t.count(Status::Finished) + t.max_steps + t.buffer_full + t.unsupported,
            t.box_rays
        );
        let mut box_rays = 0;
        for y in 0..32 {
            for x in 0..40 {
                let ray = cam.ray(x, y, 40, 32);
                let p = frame.pixel(x, y).unwrap();
                assert_eq!(p.span, ray_box_span(&ray, &bounds));
                box_rays += u64::from(p.span.is_some());
                let hits = frame.hits(x, y);
                assert_eq!(hits.len(), p.trace.roots as usize);
                assert!(hits.windows(2).all(|w| w[0].t <= w[1].t));
                if let Some(span) = p.span {
                    for h in hits {
                        assert!(span[0] <= h.t && h.t <= span[1]);
                    }
                }
            }
        }
        assert_eq!(box_rays, t.box_rays);
        // the framed box is fully in view, so rays near the centre cross it
        assert!(frame.pixel(20, 16).unwrap().span.is_some());
    }
    // bad input is an error
    let s = RenderSettings::new(4, 4, Method::Segment).unwrap();
    assert!(render(&BALL, &cam, [[0.0; 3], [f64::INFINITY; 3]], &s).is_err());
    assert!(RenderSettings::<f64>::new(4, 0, Method::Segment).is_err());
}

/// Checks a frame of the ball against the analytic intersections, as the
/// tracing contract states it: an `Entering`/`Leaving` root lies within
/// `eps` of the true crossing (`2·eps` allowed for rounding), a `Touch` root
/// is a point where the field is tiny, nothing lies past the first crossing
/// in opaque mode, and transparent mode finds both crossings once. Returns
/// the number of `Touch` roots seen.
fn check_ball_frame(frame: &Frame<f64>, cam: &Camera<f64>, mode: Mode, eps: f64) -> usize {
    let (w, h) = (frame.width(), frame.height());
    let (mut checked, mut touches) = (0, 0);
    let name = frame.settings().method;
    for y in 0..h {
        for x in 0..w {
            let ray = cam.ray(x, y, w, h);
            let p = frame.pixel(x, y).unwrap();
            let hits = frame.hits(x, y);
            assert_ne!(p.trace.status, Status::Unsupported, "{name}");
            let Ok(expected) = analytic(&ray) else {
                continue;
            };
            checked += 1;
            let Some([t_in, t_out]) = expected else {
                assert!(hits.is_empty(), "{name} ({x}, {y}): {hits:?}");
                continue;
            };
            assert_eq!(p.trace.status, Status::Finished, "{name} ({x}, {y})");
            assert!(!hits.is_empty(), "{name} ({x}, {y})");
            assert_eq!(frame.depth(x, y), Some(hits[0].t));
            for hit in hits {
                let q = sub(at(&ray, hit.t), BALL.c);
                match hit.side {
                    Side::Entering => assert!(
                        (hit.t - t_in).abs() <= 2.0 * eps,
                        "{name} ({x}, {y}): {hits:?}"
                    ),
                    Side::Leaving => assert!(
                        (hit.t - t_out).abs() <= 2.0 * eps,
                        "{name} ({x}, {y}): {hits:?}"
                    ),
                    Side::Touch => {
                        touches += 1;
                        assert!(
                            (norm(q) - BALL.r).abs() <= 1e-3,
                            "{name} ({x}, {y}): {hits:?}"
                        );
                    }
                }
                // the normal is the radial direction
                let radial = q.map(|c| c / norm(q));
                assert!(dot(hit.normal, radial) > 0.999, "{name} ({x}, {y})");
            }
            let sides = |s: Side| hits.iter().filter(|h| h.side == s).count();
            match mode {
                Mode::Opaque => {
                    assert_eq!(hits.len(), 1, "{name} ({x}, {y}): {hits:?}");
                    assert!(
                        hits[0].t <= t_in + 2.0 * eps,
                        "{name} ({x}, {y}): past the surface"
                    );
                    assert_ne!(hits[0].side, Side::Leaving);
                }
                Mode::Transparent => {
                    assert_eq!(sides(Side::Entering), 1, "{name} ({x}, {y}): {hits:?}");
                    assert_eq!(sides(Side::Leaving), 1, "{name} ({x}, {y}): {hits:?}");
                }
            }
        }
    }
    assert!(checked > (w * h / 2) as usize);
    touches
}

#[test]
fn ball_renders_match_the_analytic_intersections() {
    let bounds = ball_bounds();
    let cam = camera();
    let params = Params::new();
    for method in Method::ALL {
        for mode in [Mode::Opaque, Mode::Transparent] {
            // room for the `Touch` roots that grazing rays may add
            let s = RenderSettings::new(45, 36, method)
                .unwrap()
                .with_mode(mode)
                .with_max_roots(64)
                .unwrap();
            let frame = render(&BALL, &cam, bounds, &s).unwrap();
            if matches!(
                method,
                Method::LinearTaylor | Method::QuadraticTaylor | Method::ScalisQuadratic
            ) {
                // the ball has no Taylor bound and is no SCALIS skeleton:
                // nothing is traced
                let t = frame.totals();
                assert_eq!(t.unsupported, t.box_rays, "{method}");
                assert_eq!(t.roots, 0);
                continue;
            }
            let touches = check_ball_frame(&frame, &cam, mode, params.eps);
            eprintln!(
                "{method} {mode:?}: {touches} touch roots, {}",
                frame.totals()
            );
        }
    }
}

#[test]
fn ball_images() {
    let cam = camera();
    let opaque = RenderSettings::new(45, 36, Method::Segment).unwrap();
    let frame = render(&BALL, &cam, ball_bounds(), &opaque).unwrap();
    let shading = Shading::default();
    let shaded = frame.shaded_image();
    let depth = frame.depth_image();
    let (mut lit, mut background) = (0, 0);
    for y in 0..36 {
        for x in 0..45 {
            let hit = !frame.hits(x, y).is_empty();
            let c = shaded.get(x, y).unwrap();
            if hit {
                lit += 1;
                assert_ne!(depth.get(x, y).unwrap(), [0; 3]);
                // never brighter than the surface colour
                assert!((0..3).all(|k| c[k] <= shading.surface[k]));
            } else {
                background += 1;
                assert_eq!(c, shading.background);
                assert_eq!(depth.get(x, y).unwrap(), [0; 3]);
            }
        }
    }
    assert!(lit > 100 && background > 100);
    // headlight: the centre of the ball (facing the eye) is the brightest
    let brightest = (0..36)
        .flat_map(|y| (0..45).map(move |x| (x, y)))
        .filter(|&(x, y)| !frame.hits(x, y).is_empty())
        .max_by_key(|&(x, y)| shaded.get(x, y).unwrap()[0])
        .unwrap();
    let ray = cam.ray(brightest.0, brightest.1, 45, 36);
    let to_centre = sub(BALL.c, ray.origin);
    let cos = dot(ray.dir, to_centre) / norm(to_centre);
    assert!(cos > 0.99, "{brightest:?}");
    // transparent: two layers darken the middle of the ball against the
    // (darker) background less than the silhouette
    let transparent = opaque.with_mode(Mode::Transparent);
    let tframe = render(&BALL, &cam, ball_bounds(), &transparent).unwrap();
    let timg = tframe.shaded_image();
    let (bx, by) = brightest;
    assert_eq!(tframe.hits(bx, by).len(), 2);
    let opaque_c = shaded.get(bx, by).unwrap();
    let trans_c = timg.get(bx, by).unwrap();
    assert_ne!(opaque_c, trans_c);
    // steps heatmap: rays through the box but off the ball take steps
    let heat_img = frame.heatmap_image(75);
    assert_eq!(
        heat_img.get(0, 0),
        Some(heat(frame.pixel(0, 0).unwrap().trace.stats.steps, 75))
    );
}

#[cfg(feature = "parallel")]
#[test]
fn parallel_rendering_is_bit_identical() {
    let cam = camera();
    for method in [Method::Segment, Method::QuadraticBottomUp, Method::Affine] {
        for mode in [Mode::Opaque, Mode::Transparent] {
            let s = RenderSettings::new(37, 29, method).unwrap().with_mode(mode);
            let par = render(&BALL, &cam, ball_bounds(), &s).unwrap();
            let ser =
                boundtrace::tracer::render::render_serial(&BALL, &cam, ball_bounds(), &s).unwrap();
            assert_eq!(par, ser, "{method}");
            for y in 0..29 {
                for x in 0..37 {
                    let (a, b) = (par.hits(x, y), ser.hits(x, y));
                    assert!(a.iter().zip(b).all(|(a, b)| a.t.to_bits() == b.t.to_bits()));
                }
            }
            assert_eq!(par.shaded_image().to_png(), ser.shaded_image().to_png());
            assert_eq!(par.totals(), ser.totals());
        }
    }
}

/// `render_scene` dispatches `scalis-quadratic` (and the per-ray Lipschitz
/// `sphere`) on a SCALIS scene through `boundtrace::tracer::scalis`; the
/// generic `render` cannot trace it. Their images agree with segment
/// tracing pixel by pixel (hit or miss, depth within 2 eps).
#[test]
fn render_scene_traces_scalis_methods() {
    use boundtrace::tracer::render::render_scene;
    use boundtrace::tracer::scenes::Scene;
    let scene = Scene::<f64>::build("scalis-random", 2023).unwrap();
    let camera = Camera::framing(scene.bounds(), [-0.5, -0.6, -1.0], 35.0, 1.0).unwrap();
    let frame = |m: Method| {
        let s = RenderSettings::new(20, 20, m).unwrap();
        render_scene(&scene, &camera, &s).unwrap()
    };
    let seg = frame(Method::Segment);
    let generic = render(
        scene.field(),
        &camera,
        scene.bounds(),
        &RenderSettings::new(20, 20, Method::ScalisQuadratic).unwrap(),
    )
    .unwrap();
    assert!(generic.totals().count(Status::Unsupported) > 0);
    assert_eq!(generic.totals().count(Status::Finished), 0);
    let eps = Params::<f64>::new().eps;
    let mut hits = 0;
    for m in [Method::ScalisQuadratic, Method::Sphere] {
        let f = frame(m);
        assert_eq!(f.totals().count(Status::Unsupported), 0, "{m}");
        for y in 0..20 {
            for x in 0..20 {
                match (f.depth(x, y), seg.depth(x, y)) {
                    (Some(a), Some(b)) => {
                        assert!((a - b).abs() <= 2.0 * eps, "{m} ({x}, {y}): {a} vs {b}");
                        hits += 1;
                    }
                    (None, None) => {}
                    (a, b) => panic!("{m} ({x}, {y}): {a:?} vs segment {b:?}"),
                }
            }
        }
    }
    assert!(hits > 10, "{hits}");
}
