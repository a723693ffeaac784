//! TEMPORARY stand-in.
use anyhow::Result;
use mcrender_scene::image_io::ImageRgb;
/// Stand-in.
pub fn contact_sheet(images: &[(String, ImageRgb)], columns: usize) -> Result<ImageRgb> {
    let (w, h) = (images[0].1.width, images[0].1.height);
    let rows = images.len().div_ceil(columns) as u32;
    let mut out = ImageRgb::new(w * columns as u32, h * rows);
    for (k, (_, im)) in images.iter().enumerate() {
        let (ox, oy) = ((k % columns) as u32 * w, (k / columns) as u32 * h);
        for y in 0..h {
            for x in 0..w {
                out.pixels[((oy + y) * out.width + ox + x) as usize] = im.pixels[(y * w + x) as usize];
            }
        }
    }
    Ok(out)
}
