//! What a load may cost: [`LoadLimits`] caps the memory the loader allocates for image
//! textures, environment maps and meshes, checked *before* each allocation from the file's
//! header, so an 8192x8192 texture on a small machine is an error naming the figure and the
//! limit rather than an abort. The per-item estimates live here too, so the command line can
//! add the film and BVH to the same budget.

use mcrender_core::accel::WideBvh;
use mcrender_core::scene::Primitive;

/// Bytes one `Rgb` (three `f32`) takes.
const RGB_BYTES: u64 = 12;

/// Limits of one scene load.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoadLimits {
    /// Bytes the loaded images and meshes may take in total.
    pub max_memory: u64,
}

impl Default for LoadLimits {
    /// No limit beyond the machine's.
    fn default() -> Self {
        Self { max_memory: u64::MAX }
    }
}

/// Peak bytes of reading a `width` x `height` image texture and MIP-mapping it: the decoded
/// file (at most 16 bytes a pixel: 4 channels of `f32`), two linear RGB copies, and the MIP
/// pyramid (4/3 of a base level that is first resampled up to powers of two, so up to 4
/// times the pixels).
#[must_use]
pub fn image_texture_bytes(width: u64, height: u64) -> u64 {
    let pixels = width.saturating_mul(height);
    let pyramid = width
        .checked_next_power_of_two()
        .unwrap_or(u64::MAX)
        .saturating_mul(height.checked_next_power_of_two().unwrap_or(u64::MAX))
        .saturating_mul(RGB_BYTES)
        .saturating_mul(4)
        / 3;
    pixels.saturating_mul(16 + 2 * RGB_BYTES).saturating_add(pyramid)
}

/// Peak bytes of reading a `width` x `height` environment image: the decoded file, the
/// linear RGB copy, and the light's sampling distribution (a few `f32` per pixel).
#[must_use]
pub fn env_image_bytes(width: u64, height: u64) -> u64 {
    width.saturating_mul(height).saturating_mul(16 + 2 * RGB_BYTES + 8)
}

/// Bytes of a triangle mesh of `vertices` and `triangles` once built for rendering:
/// positions, normals and uvs (32 bytes a vertex), indices (12 bytes a triangle), the
/// scene's primitive for each triangle, and the BVH over them at the peak of its build
/// ([`WideBvh::estimated_peak_bytes`]). A 1M-triangle PLY mesh (0.5M vertices) rendered at
/// 16x16 peaked at 339 MB resident; this gives 290 MB (the former figure, a binary BVH's
/// 104 bytes a triangle in all, gave 120 MB).
#[must_use]
pub fn mesh_bytes(vertices: u64, triangles: u64) -> u64 {
    let primitive = 12 + size_of::<Primitive>() as u64;
    vertices
        .saturating_mul(32)
        .saturating_add(triangles.saturating_mul(primitive))
        .saturating_add(WideBvh::estimated_peak_bytes(triangles))
}

/// Count `need` more bytes of images, for `what` (e.g. `image "wood.png" (4096x4096)`),
/// on top of `counted` (the images read so far), unless the total passes the limit: then
/// the message refusing it, naming both figures and the limit. How the Mitsuba, OBJ and
/// glTF loaders check each image from its header before decoding it.
///
/// # Errors
/// The refusal, when the total would pass `limits.max_memory`.
pub fn count_image_bytes(counted: &mut u64, need: u64, what: &str, limits: &LoadLimits) -> Result<(), String> {
    let total = counted.saturating_add(need);
    if total > limits.max_memory {
        return Err(format!(
            "{what} needs about {} (images so far: {}), over the memory limit of {} (see --max-memory)",
            format_bytes(need),
            format_bytes(*counted),
            format_bytes(limits.max_memory)
        ));
    }
    *counted = total;
    Ok(())
}

/// A byte count for messages: `1.5 GiB`, `310.0 MiB`, `12.0 KiB`, `512 bytes`.
#[must_use]
pub fn format_bytes(bytes: u64) -> String {
    const UNITS: [&str; 4] = ["KiB", "MiB", "GiB", "TiB"];
    if bytes < 1024 {
        return format!("{bytes} bytes");
    }
    let mut v = bytes as f64 / 1024.0;
    let mut unit = 0;
    while v >= 1024.0 && unit + 1 < UNITS.len() {
        v /= 1024.0;
        unit += 1;
    }
    format!("{v:.1} {}", UNITS[unit])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn estimates_grow_with_size_and_never_overflow() {
        assert!(image_texture_bytes(8192, 8192) > 8192 * 8192 * 28);
        assert!(image_texture_bytes(1000, 1000) > image_texture_bytes(512, 512));
        assert_eq!(image_texture_bytes(u64::MAX, u64::MAX), u64::MAX);
        assert_eq!(mesh_bytes(u64::MAX, 1), u64::MAX);
        assert_eq!(env_image_bytes(u64::MAX, 3), u64::MAX);
    }

    #[test]
    fn byte_counts_read_naturally() {
        assert_eq!(format_bytes(512), "512 bytes");
        assert_eq!(format_bytes(1536), "1.5 KiB");
        assert_eq!(format_bytes(3 << 30), "3.0 GiB");
    }
}
