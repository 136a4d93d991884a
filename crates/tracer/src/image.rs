//! RGB8 images, a dependency-free PNG encoder, and the colormaps of the
//! papers' figures (steps heatmap, depth, normals).
//!
//! The PNG writer stores the image data uncompressed: zlib "stored" deflate
//! blocks (RFC 1950/1951) with an Adler-32 checksum, in chunks protected by
//! CRC-32 (PNG specification, ISO/IEC 15948). The files are larger than a
//! compressing encoder's but every PNG reader accepts them, and no
//! dependency is needed.
//!
//! ```
//! use boundtrace_tracer::image::{Image, heat};
//!
//! let img = Image::from_fn(4, 2, |x, _y| heat(x, 3))?;
//! let png = img.to_png();
//! assert_eq!(&png[1..4], b"PNG");
//! assert_eq!(img.get(3, 1), Some(heat(3, 3)));
//! # Ok::<(), boundtrace_tracer::image::ImageError>(())
//! ```

use alloc::vec;
use alloc::vec::Vec;
use core::fmt;

/// The largest width or height of an [`Image`].
pub const MAX_DIMENSION: u32 = 1 << 16;
/// The largest number of pixels of an [`Image`] (`width · height`).
pub const MAX_PIXELS: u64 = 1 << 28;

/// An image of the wrong size.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ImageError {
    /// The width or the height is zero (PNG has no empty images).
    ZeroSize,
    /// The width or the height exceeds [`MAX_DIMENSION`], or the pixel
    /// count exceeds [`MAX_PIXELS`].
    TooLarge,
    /// The pixel buffer's length is not `width · height`.
    WrongPixelCount,
}

impl fmt::Display for ImageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ImageError::ZeroSize => f.write_str("image: the width and the height must be >= 1"),
            ImageError::TooLarge => write!(
                f,
                "image: at most {MAX_DIMENSION} pixels wide and high and {MAX_PIXELS} pixels in all"
            ),
            ImageError::WrongPixelCount => {
                f.write_str("image: the pixel buffer's length must be width * height")
            }
        }
    }
}

impl core::error::Error for ImageError {}

/// An RGB image, 8 bits per channel, rows from top to bottom.
///
/// Invariant: `1 ≤ width, height ≤ MAX_DIMENSION`,
/// `width · height ≤ MAX_PIXELS` and `pixels.len() == width · height`
/// (checked by every constructor).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Image {
    width: u32,
    height: u32,
    pixels: Vec<[u8; 3]>,
}

fn check_size(width: u32, height: u32) -> Result<usize, ImageError> {
    if width == 0 || height == 0 {
        return Err(ImageError::ZeroSize);
    }
    let n = u64::from(width) * u64::from(height);
    if width > MAX_DIMENSION || height > MAX_DIMENSION || n > MAX_PIXELS {
        return Err(ImageError::TooLarge);
    }
    usize::try_from(n).map_err(|_| ImageError::TooLarge)
}

impl Image {
    /// A `width × height` image filled with `fill`.
    ///
    /// # Errors
    /// [`ImageError::ZeroSize`] or [`ImageError::TooLarge`].
    pub fn new(width: u32, height: u32, fill: [u8; 3]) -> Result<Self, ImageError> {
        let n = check_size(width, height)?;
        Ok(Self {
            width,
            height,
            pixels: vec![fill; n],
        })
    }

    /// An image from its pixels, row by row from the top.
    ///
    /// # Errors
    /// [`ImageError::ZeroSize`], [`ImageError::TooLarge`] or
    /// [`ImageError::WrongPixelCount`].
    pub fn from_pixels(width: u32, height: u32, pixels: Vec<[u8; 3]>) -> Result<Self, ImageError> {
        let n = check_size(width, height)?;
        if pixels.len() != n {
            return Err(ImageError::WrongPixelCount);
        }
        Ok(Self {
            width,
            height,
            pixels,
        })
    }

    /// An image with the colour `f(x, y)` at each pixel.
    ///
    /// # Errors
    /// [`ImageError::ZeroSize`] or [`ImageError::TooLarge`].
    pub fn from_fn(
        width: u32,
        height: u32,
        mut f: impl FnMut(u32, u32) -> [u8; 3],
    ) -> Result<Self, ImageError> {
        let n = check_size(width, height)?;
        let mut pixels = Vec::with_capacity(n);
        for y in 0..height {
            for x in 0..width {
                pixels.push(f(x, y));
            }
        }
        Ok(Self {
            width,
            height,
            pixels,
        })
    }

    /// The width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// The height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The pixels, row by row from the top.
    pub fn pixels(&self) -> &[[u8; 3]] {
        &self.pixels
    }

    /// The pixels, mutably (the size is fixed).
    pub fn pixels_mut(&mut self) -> &mut [[u8; 3]] {
        &mut self.pixels
    }

    /// The pixel at `(x, y)` (`y = 0` is the top row), if inside.
    pub fn get(&self, x: u32, y: u32) -> Option<[u8; 3]> {
        self.index(x, y).map(|i| self.pixels[i])
    }

    /// The pixel at `(x, y)`, mutably, if inside.
    pub fn get_mut(&mut self, x: u32, y: u32) -> Option<&mut [u8; 3]> {
        self.index(x, y).map(|i| &mut self.pixels[i])
    }

    fn index(&self, x: u32, y: u32) -> Option<usize> {
        (x < self.width && y < self.height).then(|| y as usize * self.width as usize + x as usize)
    }

    /// The image as a PNG file (8-bit RGB, no interlacing, filter type 0
    /// on every row, uncompressed zlib stream).
    pub fn to_png(&self) -> Vec<u8> {
        let row = 1 + 3 * self.width as usize;
        let mut raw = Vec::with_capacity(row * self.height as usize);
        for line in self.pixels.chunks_exact(self.width as usize) {
            raw.push(0); // filter type 0: None
            for p in line {
                raw.extend_from_slice(p);
            }
        }
        let idat = zlib_stored(&raw);
        let mut out = Vec::with_capacity(idat.len() + 64);
        out.extend_from_slice(&PNG_SIGNATURE);
        let mut ihdr = [0u8; 13];
        ihdr[0..4].copy_from_slice(&self.width.to_be_bytes());
        ihdr[4..8].copy_from_slice(&self.height.to_be_bytes());
        // bit depth 8, colour type 2 (RGB), compression 0, filter 0, no interlace
        ihdr[8..13].copy_from_slice(&[8, 2, 0, 0, 0]);
        push_chunk(&mut out, b"IHDR", &ihdr);
        push_chunk(&mut out, b"IDAT", &idat);
        push_chunk(&mut out, b"IEND", &[]);
        out
    }

    /// Writes the image as a PNG file ([`Image::to_png`]).
    ///
    /// # Errors
    /// The I/O error of creating or writing the file.
    #[cfg(feature = "std")]
    pub fn write_png(&self, path: impl AsRef<std::path::Path>) -> std::io::Result<()> {
        std::fs::write(path, self.to_png())
    }
}

/// The eight bytes every PNG file starts with.
pub const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];

/// Appends a PNG chunk: length, type, data, CRC-32 of type and data.
fn push_chunk(out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    // Chunks are at most 2³¹ − 1 bytes; an image of MAX_PIXELS RGB pixels
    // plus filter bytes and zlib framing stays below that.
    out.extend_from_slice(&(data.len() as u32).to_be_bytes());
    let start = out.len();
    out.extend_from_slice(kind);
    out.extend_from_slice(data);
    let crc = crc32(&out[start..]);
    out.extend_from_slice(&crc.to_be_bytes());
}

/// The largest payload of one stored deflate block (RFC 1951 §3.2.4).
const STORED_BLOCK: usize = 65_535;

/// A zlib stream (RFC 1950) of stored (uncompressed) deflate blocks.
fn zlib_stored(data: &[u8]) -> Vec<u8> {
    let blocks = data.len().div_ceil(STORED_BLOCK).max(1);
    let mut out = Vec::with_capacity(data.len() + 5 * blocks + 6);
    // CMF: deflate, 32 KiB window; FLG: no dictionary, check bits so that
    // (CMF·256 + FLG) % 31 == 0 (0x7801 = 30721 = 31 · 991).
    out.extend_from_slice(&[0x78, 0x01]);
    let mut chunks = data.chunks(STORED_BLOCK).peekable();
    if chunks.peek().is_none() {
        out.extend_from_slice(&[1, 0, 0, 0xff, 0xff]); // one final empty block
    }
    while let Some(chunk) = chunks.next() {
        let last = chunks.peek().is_none();
        // BFINAL bit, BTYPE = 00 (stored), padded to the byte boundary.
        out.push(u8::from(last));
        let len = chunk.len() as u16; // ≤ STORED_BLOCK
        out.extend_from_slice(&len.to_le_bytes());
        out.extend_from_slice(&(!len).to_le_bytes());
        out.extend_from_slice(chunk);
    }
    out.extend_from_slice(&adler32(data).to_be_bytes());
    out
}

/// The CRC-32 lookup table (polynomial 0xEDB88320, reflected).
const CRC_TABLE: [u32; 256] = {
    let mut table = [0u32; 256];
    let mut n = 0;
    while n < 256 {
        let mut c = n as u32;
        let mut k = 0;
        while k < 8 {
            c = if c & 1 != 0 {
                0xedb8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
            k += 1;
        }
        table[n] = c;
        n += 1;
    }
    table
};

/// CRC-32 as used by PNG chunks (ISO 3309, PNG specification Annex D).
pub(crate) fn crc32(bytes: &[u8]) -> u32 {
    let mut c = 0xffff_ffffu32;
    for &b in bytes {
        c = CRC_TABLE[((c ^ u32::from(b)) & 0xff) as usize] ^ (c >> 8);
    }
    c ^ 0xffff_ffff
}

/// The Adler-32 checksum of a zlib stream (RFC 1950 §8.2).
pub(crate) fn adler32(bytes: &[u8]) -> u32 {
    const MOD: u32 = 65_521;
    // 5552 bytes keep the sums below 2³² before reduction (zlib's NMAX).
    let (mut a, mut b) = (1u32, 0u32);
    for chunk in bytes.chunks(5552) {
        for &x in chunk {
            a += u32::from(x);
            b += a;
        }
        a %= MOD;
        b %= MOD;
    }
    (b << 16) | a
}

/// `x ∈ [0, 1]` to a channel value, rounding to nearest; NaN gives 0.
fn channel(x: f64) -> u8 {
    if x >= 1.0 {
        255
    } else if x > 0.0 {
        (x * 255.0 + 0.5) as u8
    } else {
        0
    }
}

/// Viridis at nine equally spaced points (van der Walt and Smith's
/// perceptually uniform colormap, as in matplotlib); its lightness
/// increases monotonically.
const VIRIDIS: [[u8; 3]; 9] = [
    [0x44, 0x01, 0x54],
    [0x48, 0x28, 0x78],
    [0x3e, 0x4a, 0x89],
    [0x31, 0x68, 0x8e],
    [0x26, 0x82, 0x8e],
    [0x1f, 0x9e, 0x89],
    [0x35, 0xb7, 0x79],
    [0x6e, 0xce, 0x58],
    [0xfd, 0xe7, 0x25],
];

/// The perceptual colormap (viridis, piecewise linear through nine
/// samples) at `x ∈ [0, 1]`: dark blue at 0, yellow at 1; `x` is clamped,
/// NaN gives the colour of 0. Its luminance increases with `x`.
pub fn viridis(x: f64) -> [u8; 3] {
    let x = if x > 0.0 { x.min(1.0) } else { 0.0 };
    let s = x * (VIRIDIS.len() - 1) as f64;
    let i = (s as usize).min(VIRIDIS.len() - 2);
    let f = s - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let mix =
        |k: usize| channel((f64::from(a[k]) + f * (f64::from(b[k]) - f64::from(a[k]))) / 255.0);
    [mix(0), mix(1), mix(2)]
}

/// The steps heatmap colour of a count: [`viridis`] of
/// `min(value, max) / max` (the papers clamp step counts to 75 for display,
/// forward-inclusion paper Fig. 12); `max = 0` is taken as 1.
pub fn heat(value: u32, max: u32) -> [u8; 3] {
    let max = max.max(1);
    viridis(f64::from(value.min(max)) / f64::from(max))
}

/// Depth as gray: white at `near`, dark gray (40) at `far`, linear in
/// between (clamped); `far ≤ near` gives white, NaN the far colour.
pub fn depth_gray(t: f64, near: f64, far: f64) -> [u8; 3] {
    const FAR: f64 = 40.0 / 255.0;
    let s = if far > near {
        (t - near) / (far - near)
    } else {
        0.0
    };
    let s = if s >= 0.0 {
        s.min(1.0)
    } else if s < 0.0 {
        0.0
    } else {
        1.0
    };
    let g = channel(1.0 - s * (1.0 - FAR));
    [g, g, g]
}

/// A unit normal as a colour: `(n + 1) / 2` per channel (clamped), the
/// usual normal-map encoding.
pub fn normal_rgb(n: [f64; 3]) -> [u8; 3] {
    n.map(|c| channel((c + 1.0) * 0.5))
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::string::ToString;

    fn luminance(c: [u8; 3]) -> f64 {
        0.2126 * f64::from(c[0]) + 0.7152 * f64::from(c[1]) + 0.0722 * f64::from(c[2])
    }

    #[test]
    fn checksums_match_reference_values() {
        assert_eq!(crc32(b"123456789"), 0xcbf4_3926);
        assert_eq!(crc32(b""), 0);
        assert_eq!(crc32(b"IEND"), 0xae42_6082); // every PNG ends with it
        assert_eq!(adler32(b"Wikipedia"), 0x11e6_0398);
        assert_eq!(adler32(b""), 1);
        // long input: the chunked reduction equals the direct definition
        let data: Vec<u8> = (0..70_000u32).map(|i| (i * 7 + i / 251) as u8).collect();
        let (mut a, mut b) = (1u64, 0u64);
        for &x in &data {
            a = (a + u64::from(x)) % 65_521;
            b = (b + a) % 65_521;
        }
        assert_eq!(adler32(&data), ((b << 16) | a) as u32);
    }

    /// Inflates a zlib stream of stored blocks (and nothing else).
    fn inflate_stored(z: &[u8]) -> Vec<u8> {
        assert_eq!((u32::from(z[0]) * 256 + u32::from(z[1])) % 31, 0);
        assert_eq!(z[0] & 0x0f, 8, "deflate");
        let mut out = Vec::new();
        let mut i = 2;
        loop {
            let header = z[i];
            assert_eq!(header >> 1, 0, "stored block");
            let len = u16::from_le_bytes([z[i + 1], z[i + 2]]);
            let nlen = u16::from_le_bytes([z[i + 3], z[i + 4]]);
            assert_eq!(len, !nlen);
            out.extend_from_slice(&z[i + 5..i + 5 + len as usize]);
            i += 5 + len as usize;
            if header & 1 == 1 {
                break;
            }
        }
        assert_eq!(z.len(), i + 4);
        assert_eq!(
            u32::from_be_bytes([z[i], z[i + 1], z[i + 2], z[i + 3]]),
            adler32(&out)
        );
        out
    }

    #[test]
    fn zlib_stored_round_trips() {
        for n in [0usize, 1, 65_534, 65_535, 65_536, 200_000] {
            let data: Vec<u8> = (0..n).map(|i| (i % 253) as u8).collect();
            let z = zlib_stored(&data);
            assert_eq!(inflate_stored(&z), data, "{n} bytes");
        }
    }

    #[test]
    fn png_structure() {
        let img = Image::from_fn(300, 90, |x, y| [x as u8, y as u8, (x ^ y) as u8]).unwrap();
        let png = img.to_png();
        assert_eq!(png[..8], PNG_SIGNATURE);
        let mut i = 8;
        let mut kinds = Vec::new();
        let mut idat = Vec::new();
        while i < png.len() {
            let len = u32::from_be_bytes(png[i..i + 4].try_into().unwrap()) as usize;
            let kind = &png[i + 4..i + 8];
            let data = &png[i + 8..i + 8 + len];
            let crc = u32::from_be_bytes(png[i + 8 + len..i + 12 + len].try_into().unwrap());
            assert_eq!(crc, crc32(&png[i + 4..i + 8 + len]));
            if kind == b"IHDR" {
                assert_eq!(data, [0, 0, 1, 44, 0, 0, 0, 90, 8, 2, 0, 0, 0]);
            }
            if kind == b"IDAT" {
                idat.extend_from_slice(data);
            }
            kinds.push(kind.to_vec());
            i += 12 + len;
        }
        assert_eq!(
            kinds,
            [b"IHDR".to_vec(), b"IDAT".to_vec(), b"IEND".to_vec()]
        );
        let raw = inflate_stored(&idat);
        assert_eq!(raw.len(), 90 * (1 + 300 * 3));
        for (y, line) in raw.chunks_exact(1 + 900).enumerate() {
            assert_eq!(line[0], 0);
            for x in 0..300 {
                assert_eq!(
                    line[1 + 3 * x..4 + 3 * x],
                    img.get(x as u32, y as u32).unwrap()
                );
            }
        }
    }

    #[test]
    fn sizes_and_access() {
        assert_eq!(Image::new(0, 3, [0; 3]), Err(ImageError::ZeroSize));
        assert_eq!(
            Image::new(MAX_DIMENSION + 1, 1, [0; 3]),
            Err(ImageError::TooLarge)
        );
        assert_eq!(
            Image::new(MAX_DIMENSION, MAX_DIMENSION, [0; 3]),
            Err(ImageError::TooLarge)
        );
        assert_eq!(
            Image::from_pixels(2, 2, vec![[0; 3]; 3]),
            Err(ImageError::WrongPixelCount)
        );
        let mut img = Image::new(3, 2, [1, 2, 3]).unwrap();
        *img.get_mut(2, 1).unwrap() = [9, 9, 9];
        assert_eq!(img.pixels()[5], [9, 9, 9]);
        assert_eq!(img.get(3, 0), None);
        assert_eq!(img.get(0, 2), None);
        assert!(img.get_mut(0, 2).is_none());
        assert!(ImageError::TooLarge.to_string().contains("at most"));
    }

    #[test]
    fn colormaps() {
        // luminance increases strictly with the step count up to the clamp
        let mut last = -1.0;
        for s in 0..=75 {
            let l = luminance(heat(s, 75));
            assert!(l > last, "step {s}");
            last = l;
        }
        assert_eq!(heat(200, 75), heat(75, 75));
        assert_eq!(heat(0, 0), heat(0, 1));
        assert_eq!(viridis(f64::NAN), viridis(0.0));
        assert_eq!(viridis(0.0), VIRIDIS[0]);
        assert_eq!(viridis(1.0), VIRIDIS[8]);
        assert_eq!(viridis(0.5), VIRIDIS[4]);
        assert_eq!(depth_gray(1.0, 1.0, 3.0), [255; 3]);
        assert_eq!(depth_gray(3.0, 1.0, 3.0), [40; 3]);
        assert!(depth_gray(2.0, 1.0, 3.0)[0] < 255 && depth_gray(2.0, 1.0, 3.0)[0] > 40);
        assert_eq!(depth_gray(9.0, 1.0, 1.0), [255; 3]);
        assert_eq!(normal_rgb([1.0, -1.0, 0.0]), [255, 0, 128]);
    }
}
