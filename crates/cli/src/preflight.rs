//! Checks before spending (issue 10 item 4): everything that would make a render fail
//! *after* it has cost time or memory is checked before it starts. Output paths must be
//! writable, counts (threads, samples, light samples) within sane bounds, and the memory the
//! render needs (film, images, meshes, BVH) within `--max-memory`, by default a fraction of
//! the machine's physical memory read from `/proc/meminfo`.

use std::io::ErrorKind;
use std::path::{Path, PathBuf};

use anyhow::{bail, Result};
use mcrender_core::scene::{GeometryDesc, Reconstruction, SceneDescription};
use mcrender_formats::limits::{format_bytes, mesh_bytes};
use mcrender_formats::{io_error_text, quoted};

/// Most worker threads accepted (far more than any CPU has cores; each thread costs a stack
/// and start-up time, and 100,000 of them took 54 s to fail).
pub const MAX_THREADS: usize = 1024;
/// Most samples per pixel accepted (2^24: days of rendering for any image).
pub const MAX_SPP: u32 = 1 << 24;
/// Most direct-lighting samples per path vertex accepted.
pub const MAX_LIGHT_SAMPLES: u32 = 4096;
/// Most path depth accepted (Russian roulette ends paths long before).
pub const MAX_DEPTH: u32 = 100_000;
/// Bytes a film pixel costs while rendering and writing: the accumulator (64 bytes) and its
/// splat sum (48), the accumulator's copy in the finished tile (64), and the mean and
/// variance images written out (12 + 12), rounded up for the encoders' buffers. Measured
/// with 24-byte splat sums: about 125 bytes a pixel (issue 10).
pub const FILM_BYTES_PER_PIXEL: u64 = 184;
/// What filter splatting adds per pixel: its filtered sums (11 i128, 176 bytes), the wave's
/// camera samples, listed per tile and then gathered (2 x 20 bytes), and the wave's group
/// sums (4 i128, 64 bytes). (A wave of several sample indices, on images under 2^20
/// pixels, lists at most 20 MiB more: see the render session's `FILTER_WAVE_SAMPLES`.)
pub const FILTERED_BYTES_PER_PIXEL: u64 = 280;

/// Bytes a film pixel of `desc` costs while rendering and writing.
#[must_use]
pub fn film_bytes_per_pixel(desc: &SceneDescription) -> u64 {
    match desc.reconstruction {
        Reconstruction::FilterSampling => FILM_BYTES_PER_PIXEL,
        Reconstruction::FilterSplatting => FILM_BYTES_PER_PIXEL + FILTERED_BYTES_PER_PIXEL,
    }
}
/// Share of physical memory a render may use by default.
pub const DEFAULT_MEMORY_FRACTION: f64 = 0.75;

/// Check the command-line counts that do not depend on the scene.
///
/// # Errors
/// A thread count of 0 or above [`MAX_THREADS`].
pub fn check_threads(threads: Option<usize>) -> Result<()> {
    if let Some(n) = threads {
        if n == 0 || n > MAX_THREADS {
            bail!("--threads {n}: expected between 1 and {MAX_THREADS}");
        }
    }
    Ok(())
}

/// Check the counts of the description (from the file or the flags) before anything is
/// built.
///
/// # Errors
/// Samples per pixel, light samples or depth beyond their bounds.
pub fn check_counts(desc: &SceneDescription) -> Result<()> {
    let spp = desc.sampler.samples_per_pixel;
    if spp == 0 || spp > MAX_SPP {
        bail!("{spp} samples per pixel (--spp or \"integer pixelsamples\"): expected between 1 and {MAX_SPP}");
    }
    let ls = desc.integrator.light_samples;
    if ls == 0 || ls > MAX_LIGHT_SAMPLES {
        bail!("{ls} light samples (--light-samples or \"integer lightsamples\"): expected between 1 and {MAX_LIGHT_SAMPLES}");
    }
    let depth = desc.integrator.max_depth;
    if depth > MAX_DEPTH {
        bail!("maximum depth {depth} (--max-depth or \"integer maxdepth\"): expected at most {MAX_DEPTH}");
    }
    Ok(())
}

/// Check that `path` can be written: its directory exists and accepts a new file, and it is
/// not itself a directory. `what` names the flag in the message.
///
/// # Errors
/// When the file could not be written at the end of the render.
pub fn check_writable(path: &Path, what: &str) -> Result<()> {
    let shown = quoted(&path.display().to_string());
    if path.is_dir() {
        bail!("{what} {shown} is a directory");
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let dir_shown = quoted(&dir.display().to_string());
    match std::fs::metadata(&dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => bail!("{what} {shown}: {dir_shown} is not a directory"),
        Err(e) if e.kind() == ErrorKind::NotFound => {
            bail!("{what} {shown}: directory {dir_shown} does not exist")
        }
        Err(e) => bail!(
            "{what} {shown}: cannot use directory {dir_shown}: {}",
            io_error_text(&e)
        ),
    }
    // The only sure test: create (and remove) a file where the image will go.
    let probe = dir.join(format!(".mcrender-write-test-{}", std::process::id()));
    match std::fs::OpenOptions::new().write(true).create_new(true).open(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) if e.kind() == ErrorKind::AlreadyExists => Ok(()),
        Err(e) => bail!("{what} {shown}: cannot write in {dir_shown}: {}", io_error_text(&e)),
    }
}

/// Check that no two outputs name the same file (the second would replace the first).
///
/// # Errors
/// When two of `outputs` (flag, path) are the same path.
pub fn check_distinct(outputs: &[(&str, &Path)]) -> Result<()> {
    for (i, (a, pa)) in outputs.iter().enumerate() {
        for (b, pb) in &outputs[..i] {
            if pa == pb {
                bail!("{b} and {a} are the same file {}", quoted(&pa.display().to_string()));
            }
        }
    }
    Ok(())
}

/// Everything `mcrender render` checks once the scene is loaded and before it builds or
/// renders anything: the counts, the output files (flag name, path if given), and memory.
///
/// # Errors
/// The first check that fails.
pub fn check_before_render(
    desc: &SceneDescription,
    image_bytes: u64,
    max_memory: u64,
    outputs: &[(&str, Option<&Path>)],
) -> Result<()> {
    check_counts(desc)?;
    let outputs: Vec<(&str, &Path)> = outputs.iter().filter_map(|&(f, p)| p.map(|p| (f, p))).collect();
    check_distinct(&outputs)?;
    for (flag, path) in &outputs {
        check_writable(path, flag)?;
    }
    check_memory(desc, image_bytes, max_memory)
}

/// Physical memory in bytes (`MemTotal` of `/proc/meminfo`), when it can be read.
#[must_use]
pub fn physical_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    parse_meminfo_total(&text)
}

/// `MemTotal` of a `/proc/meminfo` text, in bytes.
fn parse_meminfo_total(text: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
    let mut fields = line.split_whitespace().skip(1);
    let value: u64 = fields.next()?.parse().ok()?;
    match fields.next() {
        Some("kB") | None => value.checked_mul(1024),
        _ => None,
    }
}

/// The default memory limit: [`DEFAULT_MEMORY_FRACTION`] of physical memory, or no limit
/// where that is unknown.
#[must_use]
pub fn default_max_memory() -> u64 {
    physical_memory().map_or(u64::MAX, |m| (m as f64 * DEFAULT_MEMORY_FRACTION) as u64)
}

/// Parse a byte count: a number with an optional unit `K`, `M`, `G`, `T` (powers of 1024;
/// `KiB`, `KB`, `k` ... are read alike) or `%` of physical memory.
///
/// # Errors
/// Anything else, or zero.
pub fn parse_bytes(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let err = || format!("expected a size such as 4G, 512M or 50%, found {}", quoted(s));
    let split = t.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(t.len());
    let (num, unit) = t.split_at(split);
    let value: f64 = num.parse().map_err(|_| err())?;
    let unit = unit.trim().to_ascii_lowercase();
    let bytes = match unit.trim_end_matches("ib").trim_end_matches('b') {
        "" => value,
        "k" => value * 1024.0,
        "m" => value * 1024.0 * 1024.0,
        "g" => value * 1024.0 * 1024.0 * 1024.0,
        "t" => value * 1024.0 * 1024.0 * 1024.0 * 1024.0,
        "%" if unit == "%" => {
            let total = physical_memory().ok_or("physical memory unknown here; give a size such as 4G")?;
            total as f64 * value / 100.0
        }
        _ => return Err(err()),
    };
    if !(1.0..1.8e19).contains(&bytes) {
        return Err(err());
    }
    Ok(bytes as u64)
}

/// What rendering `desc` needs beyond what loading it took (`loaded_bytes`: images and PLY
/// meshes, already counted by the loader): the film, and the meshes given inline with
/// their BVH.
#[must_use]
pub fn render_memory(desc: &SceneDescription, loaded_bytes: u64) -> u64 {
    let pixels = u64::from(desc.film.width) * u64::from(desc.film.height);
    let geometry = |shapes: &mut dyn Iterator<Item = &GeometryDesc>| {
        shapes.fold(0u64, |acc, g| {
            acc.saturating_add(match g {
                GeometryDesc::TriangleMesh(m) => mesh_bytes(m.positions.len() as u64, m.indices.len() as u64 / 3)
                    .saturating_add(m.tangents.as_ref().map_or(0, |t| 16 * t.len() as u64)),
                GeometryDesc::BilinearMesh(m) => mesh_bytes(m.positions.len() as u64, m.indices.len() as u64 / 4),
                _ => mesh_bytes(0, 1),
            })
        })
    };
    let world = geometry(&mut desc.shapes.iter().map(|s| &s.geometry));
    let objects = geometry(&mut desc.objects.iter().flat_map(|o| o.shapes.iter().map(|s| &s.geometry)));
    pixels
        .saturating_mul(film_bytes_per_pixel(desc))
        .saturating_add(loaded_bytes)
        .saturating_add(world)
        .saturating_add(objects)
}

/// Refuse a render whose estimated memory passes the limit, naming both.
///
/// # Errors
/// When `need > limit`.
pub fn check_memory(desc: &SceneDescription, loaded_bytes: u64, limit: u64) -> Result<()> {
    let need = render_memory(desc, loaded_bytes);
    if need > limit {
        let (w, h) = (desc.film.width, desc.film.height);
        let per_pixel = film_bytes_per_pixel(desc);
        bail!(
            "the render needs about {} ({w}x{h} film at {per_pixel} bytes a pixel, images and meshes {}), over the memory limit of {} (--max-memory; default {:.0}% of physical memory)",
            format_bytes(need),
            format_bytes(need.saturating_sub(u64::from(w) * u64::from(h) * per_pixel)),
            format_bytes(limit),
            DEFAULT_MEMORY_FRACTION * 100.0
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meminfo_total_is_read_in_bytes() {
        let text = "MemTotal:       24567808 kB\nMemFree:  100 kB\n";
        assert_eq!(parse_meminfo_total(text), Some(24_567_808 * 1024));
        assert_eq!(parse_meminfo_total("nothing"), None);
        assert!(physical_memory().is_some_and(|m| m > 1 << 20));
    }

    #[test]
    fn byte_sizes_parse_with_units() {
        assert_eq!(parse_bytes("512"), Ok(512));
        assert_eq!(parse_bytes("4G"), Ok(4 << 30));
        assert_eq!(parse_bytes("1.5GiB"), Ok(3 << 29));
        assert_eq!(parse_bytes("300mb"), Ok(300 << 20));
        assert!(parse_bytes("50%").unwrap() > 0);
        for bad in ["", "x", "0", "-1G", "4Q", "1e400"] {
            assert!(parse_bytes(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn thread_counts_are_bounded() {
        assert!(check_threads(Some(4)).is_ok());
        assert!(check_threads(None).is_ok());
        let e = check_threads(Some(100_000)).unwrap_err().to_string();
        assert!(e.contains("--threads 100000") && e.contains("1024"), "{e}");
        assert!(check_threads(Some(0)).is_err());
    }

    #[test]
    fn missing_and_unwritable_directories_are_found_before_rendering() {
        let dir = tempfile::tempdir().unwrap();
        assert!(check_writable(&dir.path().join("a.png"), "-o").is_ok());
        let e = check_writable(&dir.path().join("missing/a.png"), "-o")
            .unwrap_err()
            .to_string();
        assert!(e.contains("does not exist"), "{e}");
        let e = check_writable(dir.path(), "-o").unwrap_err().to_string();
        assert!(e.contains("is a directory"), "{e}");
        // /sys refuses new files even to root.
        let e = check_writable(Path::new("/sys/a.png"), "-o").unwrap_err().to_string();
        assert!(e.contains("cannot write in"), "{e}");
        assert!(
            std::fs::read_dir(dir.path()).unwrap().next().is_none(),
            "probe file left behind"
        );
    }
}
