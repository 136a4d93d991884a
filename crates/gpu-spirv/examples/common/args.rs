//! The command line the timing examples share: `[SIZE] [REPEATS] [SCENES]`.

use std::error::Error;

/// `[SIZE] [REPEATS] [SCENES]` from the command line: the frame side
/// (`size` when absent), the repeats (3 when absent, at least 1), and the
/// comma-separated scene names (`scenes` when absent). A number that does
/// not parse is an error.
pub fn size_repeats_scenes(
    size: u32,
    scenes: &str,
) -> Result<(u32, u32, Vec<String>), Box<dyn Error>> {
    let mut args = std::env::args().skip(1);
    let size: u32 = args.next().map(|s| s.parse()).transpose()?.unwrap_or(size);
    let repeats: u32 = args
        .next()
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(3)
        .max(1);
    let scenes = args
        .next()
        .as_deref()
        .unwrap_or(scenes)
        .split(',')
        .map(str::to_owned)
        .collect();
    Ok((size, repeats, scenes))
}
