//! `mcrender diff`: zero error for identical images, known numbers for a known offset,
//! exit code 2 with a message on a size mismatch, downsampling of the reference, and a
//! decodable error image.

mod common;

use std::path::Path;
use std::process::Output;

use common::{mcrender, stderr};

use mcrender_core::color::Rgb;
use mcrender_formats::image_io::{write_image, ImageRgb};

fn write(dir: &Path, name: &str, w: u32, h: u32, f: impl Fn(u32, u32) -> Rgb) {
    let mut img = ImageRgb::new(w, h);
    for y in 0..h {
        for x in 0..w {
            img.pixels[(y * w + x) as usize] = f(x, y);
        }
    }
    write_image(&dir.join(name), &img).unwrap();
}

fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", stderr(o));
    serde_json::from_slice(&o.stdout).expect("valid JSON")
}

fn num(v: &serde_json::Value, key: &str, c: usize) -> f64 {
    v[key][c].as_f64().unwrap()
}

#[test]
fn identical_images_give_zero_error() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "a.exr", 16, 12, |x, y| {
        Rgb::new(x as f32 * 0.1, y as f32 * 0.2, 0.5)
    });
    let v = json(&mcrender(&["diff", "a.exr", "a.exr", "--json"], dir.path()));
    assert_eq!(v["mse"].as_f64(), Some(0.0));
    assert_eq!(v["rel_mse"].as_f64(), Some(0.0));
    for c in 0..3 {
        assert_eq!(num(&v, "block_rel_max", c), 0.0);
        assert_eq!(num(&v, "mean_a", c), num(&v, "mean_b", c));
    }
    assert_eq!(v["blocks"].as_u64(), Some(4)); // 2x2 blocks of 8, the bottom row partial
                                               // The table is printed without --json.
    let o = mcrender(&["diff", "a.exr", "a.exr"], dir.path());
    assert!(o.status.success());
    let t = String::from_utf8_lossy(&o.stdout);
    assert!(t.contains("relative MSE") && t.contains("block rel err mean"), "{t}");
}

#[test]
fn known_offset_gives_known_numbers() {
    let dir = tempfile::tempdir().unwrap();
    // B = 1 everywhere, A = 1.1 (red), 1 (green), 0.5 (blue).
    write(dir.path(), "a.exr", 8, 8, |_, _| Rgb::new(1.1, 1.0, 0.5));
    write(dir.path(), "b.exr", 8, 8, |_, _| Rgb::splat(1.0));
    let v = json(&mcrender(
        &["diff", "a.exr", "b.exr", "--json", "--block", "4"],
        dir.path(),
    ));
    let tol = 1e-6;
    // Per pixel squared differences 0.01, 0, 0.25 (f32 values, hence the tolerance).
    assert!((v["mse"].as_f64().unwrap() - 0.26 / 3.0).abs() < tol, "{v}");
    assert!((v["rel_mse"].as_f64().unwrap() - 0.26 / 3.0 / 1.01).abs() < tol, "{v}");
    assert!((num(&v, "mean_a", 0) - 1.1).abs() < tol);
    assert!((num(&v, "mean_rel_diff", 2) + 0.5).abs() < tol);
    assert_eq!(v["blocks"].as_u64(), Some(4));
    for (c, want) in [(0, 0.1 / 1.01), (1, 0.0), (2, 0.5 / 1.01)] {
        assert!((num(&v, "block_rel_mean", c) - want).abs() < tol, "{v}");
        assert!((num(&v, "block_rel_max", c) - want).abs() < tol, "{v}");
    }
}

#[test]
fn size_mismatch_exits_2_with_message() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "a.exr", 8, 8, |_, _| Rgb::splat(1.0));
    write(dir.path(), "b.exr", 8, 4, |_, _| Rgb::splat(1.0));
    let o = mcrender(&["diff", "a.exr", "b.exr"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("size mismatch") && e.contains("8x8") && e.contains("8x4"),
        "{e}"
    );
    // A downsampling factor that does not divide the reference.
    let o = mcrender(&["diff", "a.exr", "b.exr", "--downsample-b", "3"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("divide"), "{e}");
}

#[test]
fn downsampled_reference_compares_with_small_render() {
    let dir = tempfile::tempdir().unwrap();
    // B 8x8: columns alternate 0 and 2, so 2x downsampling gives 1 everywhere.
    write(dir.path(), "b.exr", 8, 8, |x, _| {
        Rgb::splat(if x % 2 == 0 { 0.0 } else { 2.0 })
    });
    write(dir.path(), "a.exr", 4, 4, |_, _| Rgb::splat(1.0));
    let v = json(&mcrender(
        &["diff", "a.exr", "b.exr", "--downsample-b", "2", "--json"],
        dir.path(),
    ));
    assert_eq!(v["width"].as_u64(), Some(4));
    assert_eq!(v["mse"].as_f64(), Some(0.0));
}

#[test]
fn error_image_is_written_and_decodable() {
    let dir = tempfile::tempdir().unwrap();
    // Left half exact, right half 200% off: blue and red (the scale saturates at 100%).
    write(dir.path(), "a.exr", 8, 4, |x, _| {
        Rgb::splat(if x < 4 { 1.0 } else { 3.0 })
    });
    write(dir.path(), "b.exr", 8, 4, |_, _| Rgb::splat(1.0));
    let o = mcrender(&["diff", "a.exr", "b.exr", "--error-image", "err.png"], dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let img = image::open(dir.path().join("err.png"))
        .expect("decodable PNG")
        .to_rgb8();
    assert_eq!(img.dimensions(), (8, 4));
    assert_eq!(img.get_pixel(0, 0).0, [0, 0, 255]);
    assert_eq!(img.get_pixel(7, 3).0, [255, 0, 0]);
}
