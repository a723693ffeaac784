//! `mcrender convert`: downsampling and exposure give the expected pixels; bad arguments
//! exit 2 with a message and write nothing.

mod common;

use common::{mcrender, stderr};

use mcrender_core::color::Rgb;
use mcrender_formats::image_io::{read_image, write_image, ImageRgb};

#[test]
fn downsamples_and_scales() {
    let dir = tempfile::tempdir().unwrap();
    let mut img = ImageRgb::new(4, 2);
    for (i, p) in img.pixels.iter_mut().enumerate() {
        *p = Rgb::new(i as f32, 1.0, 0.25);
    }
    write_image(&dir.path().join("in.exr"), &img).unwrap();
    let o = mcrender(
        &["convert", "in.exr", "out.exr", "--downsample", "2", "--exposure", "1"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = read_image(&dir.path().join("out.exr")).unwrap();
    assert_eq!((out.width, out.height), (2, 1));
    // Block 0 holds pixels 0, 1, 4, 5 (mean red 2.5); block 1 holds 2, 3, 6, 7 (mean 4.5).
    assert_eq!(out.pixels[0], Rgb::new(5.0, 2.0, 0.5));
    assert_eq!(out.pixels[1], Rgb::new(9.0, 2.0, 0.5));

    let o = mcrender(&["convert", "in.exr", "out.png"], dir.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let png = read_image(&dir.path().join("out.png")).unwrap();
    assert_eq!((png.width, png.height), (4, 2));
}

#[test]
fn a_factor_that_does_not_divide_is_an_error_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    write_image(&dir.path().join("in.exr"), &ImageRgb::new(4, 3)).unwrap();
    let o = mcrender(&["convert", "in.exr", "out.png", "--downsample", "2"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--downsample 2"), "{}", stderr(&o));
    assert!(!dir.path().join("out.png").exists());
    let o = mcrender(&["convert", "missing.exr", "out.png"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("missing.exr"), "{}", stderr(&o));
}
