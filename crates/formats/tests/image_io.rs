//! PNG and EXR writing and reading: values survive, sRGB encoding is right, and a failed
//! write leaves nothing behind.

use std::path::Path;

use mcrender_core::color::Rgb;
use mcrender_formats::image_io::{read_exr, write_exr_layers, write_image, ImageError, ImageRgb};

fn gradient(width: u32, height: u32) -> ImageRgb {
    let pixels = (0..width * height)
        .map(|i| {
            let (x, y) = (i % width, i / width);
            Rgb::new(x as f32 * 0.25, y as f32 * 1.5, 1e-3 + (x * y) as f32 * 100.0)
        })
        .collect();
    ImageRgb { width, height, pixels }
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn exr_round_trip_is_exact() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.exr");
    let img = gradient(7, 5);
    write_image(&path, &img).unwrap();
    assert_eq!(read_exr(&path).unwrap(), img);
    assert_eq!(files_in(dir.path()), vec!["out.exr"]);
}

#[test]
fn exr_layers_keep_the_main_image_readable() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("layers.exr");
    let img = gradient(4, 3);
    let variance: Vec<Rgb> = img.pixels.iter().map(|p| *p * 0.5).collect();
    write_exr_layers(&path, 4, 3, &[("", &img.pixels), ("variance", &variance)]).unwrap();
    assert_eq!(read_exr(&path).unwrap(), img);
    // The extra channels are there under their layer name.
    let bytes = std::fs::read(&path).unwrap();
    assert!(bytes.windows(10).any(|w| w == b"variance.R"));

    let err = write_exr_layers(&path, 4, 3, &[("", &img.pixels[..5])]).unwrap_err();
    assert!(matches!(err, ImageError::InvalidImage { .. }), "{err}");
    // The earlier file is untouched.
    assert_eq!(read_exr(&path).unwrap(), img);
}

#[test]
fn png_is_srgb_encoded() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.png");
    let img = ImageRgb {
        width: 3,
        height: 2,
        pixels: vec![
            Rgb::splat(0.5),
            Rgb::new(0.0, 1.0, 2.0),
            Rgb::new(-1.0, 0.0031308, 0.2),
            Rgb::splat(0.0),
            Rgb::splat(1.0),
            Rgb::new(f32::NAN, 0.5, 0.5),
        ],
    };
    write_image(&path, &img).unwrap();
    let read = image::open(&path).unwrap().to_rgb8();
    assert_eq!(read.dimensions(), (3, 2));
    assert_eq!(read.get_pixel(0, 0).0, [188, 188, 188]);
    assert_eq!(read.get_pixel(1, 0).0, [0, 255, 255]);
    assert_eq!(read.get_pixel(2, 0).0, [0, 10, 124]);
    assert_eq!(read.get_pixel(1, 1).0, [255, 255, 255]);
    assert_eq!(read.get_pixel(2, 1).0, [0, 188, 188]);
    assert_eq!(files_in(dir.path()), vec!["out.png"]);
}

#[test]
fn failed_writes_leave_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let img = gradient(2, 2);

    let err = write_image(&dir.path().join("missing/out.png"), &img).unwrap_err();
    assert!(matches!(err, ImageError::Io { .. }), "{err}");
    assert!(err.to_string().ends_with("No such file or directory"), "{err}");

    let err = write_image(&dir.path().join("out.jpg"), &img).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!(
            "{}: unsupported image format \"jpg\" (use .png or .exr)",
            dir.path().join("out.jpg").display()
        )
    );

    let bad = ImageRgb {
        width: 3,
        height: 3,
        pixels: img.pixels.clone(),
    };
    assert!(matches!(
        write_image(&dir.path().join("bad.exr"), &bad),
        Err(ImageError::InvalidImage { .. })
    ));
    assert!(matches!(
        write_image(&dir.path().join("bad.png"), &ImageRgb::new(0, 4)),
        Err(ImageError::InvalidImage { .. })
    ));

    assert!(files_in(dir.path()).is_empty(), "{:?}", files_in(dir.path()));
}

#[test]
fn overwriting_replaces_the_whole_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.exr");
    write_image(&path, &gradient(8, 8)).unwrap();
    let small = gradient(2, 1);
    write_image(&path, &small).unwrap();
    assert_eq!(read_exr(&path).unwrap(), small);
    assert_eq!(files_in(dir.path()), vec!["out.exr"]);
}

#[test]
fn reading_a_missing_or_bogus_exr_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    assert!(matches!(
        read_exr(&dir.path().join("none.exr")),
        Err(ImageError::Io { .. })
    ));
    std::fs::write(dir.path().join("bogus.exr"), b"not an exr").unwrap();
    assert!(read_exr(&dir.path().join("bogus.exr")).is_err());
}
