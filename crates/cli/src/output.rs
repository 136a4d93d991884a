//! Outputs of the command: atomic file writes (a temporary file in the same
//! directory, renamed over the target only once complete), the steps
//! heatmap's colour-bar legend, and shading with the scene file's lights.
//!
//! ```
//! use boundtrace_cli::output::{heat_legend, write_atomic};
//! use boundtrace_tracer::image::Image;
//!
//! let img = Image::new(40, 30, [0, 0, 0])?;
//! let with_bar = heat_legend(&img, 75)?; // wider: bar and labels on the right
//! assert!(with_bar.width() > img.width() && with_bar.height() == img.height());
//! let dir = std::env::temp_dir().join(format!("bt-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//! let path = dir.join("x.png");
//! write_atomic(&path, &with_bar.to_png())?;
//! assert!(std::fs::read(&path)?.starts_with(&[0x89, b'P']));
//! # std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::scene_format::{LightSpec, MaterialSpec};
use boundtrace_ia_core::Real;
use boundtrace_tracer::image::{Image, ImageError, heat};
use boundtrace_tracer::render::Frame;
use std::io::Write;
use std::path::{Path, PathBuf};

/// A temporary sibling of `path` (same directory, so the rename is atomic
/// on one file system).
fn temp_sibling(path: &Path, tag: &str) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.subsec_nanos())
        .unwrap_or(0);
    path.with_file_name(format!(".{name}.{tag}-{}-{nanos}.tmp", std::process::id()))
}

/// Writes `bytes` to `path` atomically: to a temporary file in the same
/// directory, flushed and synced, then renamed over `path`. On any error
/// the temporary file is removed and an existing `path` is left untouched.
/// The directory must exist.
///
/// # Errors
/// I/O errors, with the path in the message.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !dir.is_dir() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::NotFound,
            format!("directory {} does not exist", dir.display()),
        ));
    }
    if path.is_dir() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("{} is a directory", path.display()),
        ));
    }
    let tmp = temp_sibling(path, "part");
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(|e| std::io::Error::new(e.kind(), format!("writing {}: {e}", path.display())))
}

/// Writes files into `dir` so that no partial set is ever visible: every
/// file goes to a temporary directory next to `dir` first; only when all
/// are written are they moved into `dir` (created if needed). On error the
/// temporary directory is removed and `dir` is untouched.
///
/// # Errors
/// I/O errors and the errors of `fill` (which writes into the directory it
/// is given).
pub fn write_dir_atomic(
    dir: &Path,
    fill: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<Vec<PathBuf>, String> {
    let parent = match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !parent.is_dir() {
        return Err(format!("directory {} does not exist", parent.display()));
    }
    if dir.exists() && !dir.is_dir() {
        return Err(format!("{} exists and is not a directory", dir.display()));
    }
    let tmp = temp_sibling(dir, "dir");
    std::fs::create_dir(&tmp).map_err(|e| format!("creating {}: {e}", tmp.display()))?;
    let result = (|| {
        fill(&tmp)?;
        std::fs::create_dir_all(dir).map_err(|e| format!("creating {}: {e}", dir.display()))?;
        let mut names: Vec<PathBuf> = std::fs::read_dir(&tmp)
            .map_err(|e| format!("reading {}: {e}", tmp.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .collect();
        names.sort();
        let mut out = Vec::with_capacity(names.len());
        for src in names {
            let Some(name) = src.file_name() else {
                continue;
            };
            let dst = dir.join(name);
            std::fs::rename(&src, &dst).map_err(|e| format!("moving to {}: {e}", dst.display()))?;
            out.push(dst);
        }
        Ok(out)
    })();
    let _ = std::fs::remove_dir_all(&tmp);
    result
}

/// A 3 × 5 bitmap font for digits (rows top to bottom, 3 bits each).
const DIGITS: [[u8; 5]; 10] = [
    [7, 5, 5, 5, 7],
    [2, 6, 2, 2, 7],
    [7, 1, 7, 4, 7],
    [7, 1, 7, 1, 7],
    [5, 5, 7, 1, 1],
    [7, 4, 7, 1, 7],
    [7, 4, 7, 5, 7],
    [7, 1, 1, 1, 1],
    [7, 5, 7, 5, 7],
    [7, 5, 7, 1, 7],
];

/// Draws `text` (digits; other characters are skipped as blanks) at
/// `(x, y)` with pixel size `s`.
fn draw_digits(img: &mut Image, text: &str, x: u32, y: u32, s: u32, color: [u8; 3]) {
    for (i, ch) in text.chars().enumerate() {
        let Some(d) = ch.to_digit(10) else { continue };
        let glyph = DIGITS[d as usize];
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..3u32 {
                if bits & (4 >> col) == 0 {
                    continue;
                }
                for dy in 0..s {
                    for dx in 0..s {
                        let px = x + (i as u32 * 4 + col) * s + dx;
                        let py = y + row as u32 * s + dy;
                        if let Some(p) = img.get_mut(px, py) {
                            *p = color;
                        }
                    }
                }
            }
        }
    }
}

/// The steps heatmap with a vertical colour bar on the right, as in the
/// papers' figures: the colour of `0` at the bottom, of `max` (and above,
/// clamped) at the top, labelled `0`, `max/2` and `max`.
///
/// # Errors
/// [`ImageError`] when the widened image would be too large.
pub fn heat_legend(img: &Image, max: u32) -> Result<Image, ImageError> {
    let max = max.max(1);
    let h = img.height();
    let s = if h >= 200 { 2 } else { 1 };
    let label_w = (max.to_string().len() as u32 * 4) * s;
    let bar_w = 4 + 4 * s;
    let pad = 2 + 2 * s;
    let extra = pad + bar_w + pad + label_w + pad;
    let width = img.width().saturating_add(extra);
    let mut out = Image::new(width, h, [255, 255, 255])?;
    for y in 0..h {
        for x in 0..img.width() {
            if let (Some(p), Some(q)) = (img.get(x, y), out.get_mut(x, y)) {
                *q = p;
            }
        }
    }
    let margin = 5 * s / 2 + 1;
    let (top, bottom) = (margin, h.saturating_sub(margin + 1));
    let x0 = img.width() + pad;
    if bottom > top {
        for y in top..=bottom {
            let frac = f64::from(bottom - y) / f64::from(bottom - top);
            let c = heat((frac * f64::from(max)).round() as u32, max);
            for x in x0..x0 + bar_w {
                if let Some(p) = out.get_mut(x, y) {
                    *p = c;
                }
            }
        }
        let lx = x0 + bar_w + pad;
        let glyph_h = 5 * s;
        let place = |y: u32| y.saturating_sub(glyph_h / 2).min(h.saturating_sub(glyph_h));
        draw_digits(&mut out, &max.to_string(), lx, place(top), s, [0, 0, 0]);
        draw_digits(&mut out, "0", lx, place(bottom), s, [0, 0, 0]);
        if bottom - top > 4 * glyph_h {
            draw_digits(
                &mut out,
                &(max / 2).to_string(),
                lx,
                place((top + bottom) / 2),
                s,
                [0, 0, 0],
            );
        }
    }
    Ok(out)
}

/// Shades the first hit of every pixel (of a CPU `f64` or GPU `f32`
/// frame) with directional `lights`
/// (Lambert, two-sided: `|n · l|`, so both sides of a transparent surface
/// are lit) over the material's ambient term; a headlight when `lights` is
/// empty. Pixels without a hit get the background.
///
/// # Errors
/// [`ImageError`] for a frame too large for an image.
pub fn shade<T: Real>(
    frame: &Frame<T>,
    lights: &[LightSpec],
    material: &MaterialSpec,
) -> Result<Image, ImageError> {
    let (w, h) = (frame.width(), frame.height());
    let cam = frame.camera();
    let head;
    let lights = if lights.is_empty() {
        head = [LightSpec {
            direction: cam.forward.map(|x| -x.as_f64()),
            color: [1.0; 3],
            intensity: 1.0,
        }];
        &head[..]
    } else {
        lights
    };
    let unit: Vec<([f64; 3], [f64; 3])> = lights
        .iter()
        .map(|l| {
            let n = l.direction.iter().map(|x| x * x).sum::<f64>().sqrt();
            (l.direction.map(|x| x / n), l.color.map(|c| c * l.intensity))
        })
        .collect();
    let pixels = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| match frame.hits(x, y).first() {
            None => material.background,
            Some(hit) => {
                let n = hit.normal.map(|x| x.as_f64());
                let mut rgb = [material.ambient; 3];
                for (d, c) in &unit {
                    let lambert = (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]).abs();
                    for k in 0..3 {
                        rgb[k] += (1.0 - material.ambient) * lambert * c[k];
                    }
                }
                [0, 1, 2].map(|k| {
                    let v = f64::from(material.surface[k]) * rgb[k].clamp(0.0, 1.0);
                    v.round().clamp(0.0, 255.0) as u8
                })
            }
        })
        .collect();
    Image::from_pixels(w, h, pixels)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tempdir() -> PathBuf {
        let d = std::env::temp_dir().join(format!(
            "bt-out-{}-{}",
            std::process::id(),
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| d.as_nanos())
                .unwrap_or(0)
        ));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn atomic_write_replaces_and_leaves_no_temp() {
        let d = tempdir();
        let p = d.join("a.txt");
        std::fs::write(&p, b"old").unwrap();
        write_atomic(&p, b"new").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"new");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);
        // a missing directory fails without creating anything
        assert!(write_atomic(&d.join("no/such/x.png"), b"x").is_err());
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn dir_write_is_all_or_nothing() {
        let d = tempdir();
        let out = d.join("slices");
        let r = write_dir_atomic(&out, |t| {
            std::fs::write(t.join("0.png"), b"x").map_err(|e| e.to_string())?;
            Err("boom".into())
        });
        assert_eq!(r.unwrap_err(), "boom");
        assert!(!out.exists());
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 0, "temp dir left");
        let files = write_dir_atomic(&out, |t| {
            std::fs::write(t.join("0.png"), b"x").map_err(|e| e.to_string())
        })
        .unwrap();
        assert_eq!(files, vec![out.join("0.png")]);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn legend_runs_from_low_to_high() {
        let img = Image::new(50, 100, [9, 9, 9]).unwrap();
        let out = heat_legend(&img, 75).unwrap();
        let x = 50 + 4 + 2; // inside the bar
        let top = out.get(x, 3).unwrap(); // margin 5/2 + 1 at s = 1
        let bottom = out.get(x, 96).unwrap();
        assert_eq!(top, heat(75, 75));
        assert_eq!(bottom, heat(0, 75));
        assert_eq!(out.get(10, 10), Some([9, 9, 9]));
    }
}
