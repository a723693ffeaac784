//! `LightSource` and `AreaLightSource` parameters: pbrt-v4's names, defaults and
//! normalisations, environment images in every supported file format, and the messages for
//! malformed input.

use std::f32::consts::PI;
use std::path::Path;

use mcrender_core::color::{srgb_to_linear, Rgb};
use mcrender_core::math::{Mat4, Vec3};
use mcrender_core::scene::{EnvMapping, ImageInfiniteLightDesc, LightDesc, Scene, SpotLightDesc};
use mcrender_formats::pbrt::{load_str, LoadedScene};
use mcrender_formats::{write_image, ImageRgb};

fn load_in(src: &str, dir: &Path) -> LoadedScene {
    match load_str(src, "scene.pbrt", dir) {
        Ok(s) => s,
        Err(e) => panic!("{e}"),
    }
}

fn load(src: &str) -> LoadedScene {
    load_in(src, Path::new(""))
}

fn error_in(src: &str, dir: &Path) -> String {
    match load_str(src, "scene.pbrt", dir) {
        Ok(_) => panic!("expected an error for:\n{src}"),
        Err(e) => e.to_string(),
    }
}

fn error(src: &str) -> String {
    error_in(src, Path::new(""))
}

fn only_light(s: &LoadedScene) -> &LightDesc {
    assert_eq!(s.description.lights.len(), 1, "{:?}", s.description.lights);
    &s.description.lights[0]
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[test]
fn spot_light_parameters_and_defaults() {
    let s = load("WorldBegin\nLightSource \"spot\"");
    let LightDesc::Spot(spot) = only_light(&s) else {
        panic!()
    };
    assert_eq!(spot.intensity, Rgb::WHITE);
    assert!((spot.cos_falloff_end - 30f32.to_radians().cos()).abs() < 1e-6);
    assert!((spot.cos_falloff_start - 25f32.to_radians().cos()).abs() < 1e-6);
    assert!(close(spot.world_from_light.point(Vec3::ZERO), Vec3::ZERO));
    assert!(close(spot.world_from_light.vector(Vec3::Z), Vec3::Z));

    let s = load(
        "WorldBegin\nTranslate 0 0 5\nLightSource \"spot\" \"rgb I\" [1 2 3] \"float scale\" 2 \"point3 from\" [1 2 3] \
         \"point3 to\" [1 2 1] \"float coneangle\" 40 \"float conedeltaangle\" 10",
    );
    let LightDesc::Spot(spot) = only_light(&s) else {
        panic!()
    };
    assert_eq!(spot.intensity, Rgb::new(2.0, 4.0, 6.0));
    assert!((spot.cos_falloff_end - 40f32.to_radians().cos()).abs() < 1e-6);
    assert!((spot.cos_falloff_start - 30f32.to_radians().cos()).abs() < 1e-6);
    assert!(close(spot.world_from_light.point(Vec3::ZERO), Vec3::new(1.0, 2.0, 8.0)));
    assert!(close(spot.world_from_light.vector(Vec3::Z), -Vec3::Z));
}

/// `power` makes the spot's total power (with the falloff band counted at one half) the
/// given value: the built light's power() agrees.
#[test]
fn spot_light_power_normalisation() {
    let s = load(
        "WorldBegin\nLightSource \"spot\" \"float power\" 50 \"float coneangle\" 20 \"float conedeltaangle\" 8\n\
         Shape \"sphere\"",
    );
    let LightDesc::Spot(SpotLightDesc { intensity, .. }) = only_light(&s) else {
        panic!()
    };
    let (ce, cs) = (20f32.to_radians().cos(), 12f32.to_radians().cos());
    let expected = 50.0 / (2.0 * PI * ((1.0 - cs) + (cs - ce) / 2.0));
    assert!(
        (intensity.r - expected).abs() < 1e-3 * expected,
        "{intensity:?} vs {expected}"
    );
    let scene = Scene::build(&s.description).unwrap();
    assert!((scene.lights[0].power().g - 50.0).abs() < 1e-2);
}

#[test]
fn distant_light_direction_and_illuminance() {
    // Default: from (0 0 0) to (0 0 1), so the light shines along +z and sits towards -z.
    let s = load("WorldBegin\nLightSource \"distant\"");
    let LightDesc::Distant { direction, radiance } = only_light(&s) else {
        panic!()
    };
    assert!(close(*direction, -Vec3::Z));
    assert_eq!(*radiance, Rgb::WHITE);

    let s = load(
        "WorldBegin\nRotate 90 1 0 0\nLightSource \"distant\" \"point3 from\" [0 0 10] \"point3 to\" [0 0 0] \
         \"rgb L\" [1 0.5 0.25] \"float scale\" 2 \"float illuminance\" 3",
    );
    let LightDesc::Distant { direction, radiance } = only_light(&s) else {
        panic!()
    };
    // Rotating +z by 90 degrees about x gives -y.
    assert!(close(*direction, -Vec3::Y), "{direction}");
    assert_eq!(*radiance, Rgb::new(6.0, 3.0, 1.5));
}

#[test]
fn uniform_infinite_light_and_illuminance() {
    let s = load("WorldBegin\nLightSource \"infinite\" \"rgb L\" [0.5 1 2] \"float scale\" 3");
    assert_eq!(
        *only_light(&s),
        LightDesc::UniformInfinite {
            radiance: Rgb::new(1.5, 3.0, 6.0)
        }
    );
    // Illuminance E from a uniform upper hemisphere of L is pi L.
    let s = load("WorldBegin\nLightSource \"infinite\" \"float illuminance\" 10");
    let LightDesc::UniformInfinite { radiance } = only_light(&s) else {
        panic!()
    };
    assert!((radiance.g - 10.0 / PI).abs() < 1e-5);
    // Default: white.
    let s = load("WorldBegin\nLightSource \"infinite\"");
    assert_eq!(*only_light(&s), LightDesc::UniformInfinite { radiance: Rgb::WHITE });
}

#[test]
fn blackbody_and_sampled_emission_spectra_have_luminance_one() {
    let lum = |c: Rgb| 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
    let s = load("WorldBegin\nAreaLightSource \"diffuse\" \"blackbody L\" 3000 \"float scale\" 2\nShape \"sphere\"");
    let l = s.description.shapes[0].area_light.unwrap().radiance;
    assert!((lum(l) - 2.0).abs() < 0.02 && l.r > l.g && l.g > l.b, "{l:?}");
    let s = load("WorldBegin\nLightSource \"point\" \"spectrum I\" [ 400 1 700 1 ]");
    let LightDesc::Point { intensity, .. } = only_light(&s) else {
        panic!("{:?}", only_light(&s))
    };
    assert!((lum(*intensity) - 1.0).abs() < 0.01, "{intensity:?}");
}

#[test]
fn area_light_power_is_passed_on() {
    let s = load(
        "WorldBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"float power\" 20 \"bool twosided\" true\nShape \"sphere\"",
    );
    let a = s.description.shapes[0].area_light.unwrap();
    assert_eq!((a.power, a.two_sided), (Some(20.0), true));
    // pbrt ignores power <= 0.
    let s = load("WorldBegin\nAreaLightSource \"diffuse\" \"float power\" -1\nShape \"sphere\"");
    assert_eq!(s.description.shapes[0].area_light.unwrap().power, None);
    // The built sphere light emits 20 W.
    let s = load("WorldBegin\nAreaLightSource \"diffuse\" \"float power\" 20\nShape \"sphere\" \"float radius\" 2");
    let scene = Scene::build(&s.description).unwrap();
    assert!((scene.lights[0].power().r - 20.0).abs() < 1e-3);
}

fn write_pfm(path: &Path, w: u32, h: u32, pixel: impl Fn(u32, u32) -> Rgb) {
    let mut bytes = format!("PF\n{w} {h}\n-1.0\n").into_bytes();
    // Bottom row first.
    for y in (0..h).rev() {
        for x in 0..w {
            for c in pixel(x, y).to_array() {
                bytes.extend(c.to_le_bytes());
            }
        }
    }
    std::fs::write(path, bytes).unwrap();
}

fn env(s: &LoadedScene) -> &ImageInfiniteLightDesc {
    match only_light(s) {
        LightDesc::ImageInfinite(e) => e,
        other => panic!("{other:?}"),
    }
}

#[test]
fn environment_images_in_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let pixel = |x: u32, y: u32| Rgb::new(x as f32, y as f32, 0.25);
    write_pfm(&dir.path().join("env.pfm"), 4, 4, pixel);
    let img = ImageRgb {
        width: 4,
        height: 4,
        pixels: (0..16).map(|i| pixel(i % 4, i / 4)).collect(),
    };
    write_image(&dir.path().join("env.exr"), &img).unwrap();
    let s = load_in(
        "WorldBegin\nRotate -90 1 0 0\nLightSource \"infinite\" \"string filename\" \"env.pfm\" \"float scale\" 2",
        dir.path(),
    );
    let e = env(&s);
    assert_eq!(
        (e.image.width, e.image.height, e.mapping, e.scale),
        (4, 4, EnvMapping::EqualArea, 2.0)
    );
    assert_eq!(e.image.pixels, img.pixels, "PFM rows are stored bottom first");
    assert!(close(e.world_from_light.vector(Vec3::Z), Vec3::Y));
    let s = load_in(
        "WorldBegin\nLightSource \"infinite\" \"string filename\" \"env.exr\"",
        dir.path(),
    );
    assert_eq!(env(&s).image.pixels, img.pixels);

    // 8-bit formats are decoded from sRGB.
    let grey = ImageRgb {
        width: 2,
        height: 2,
        pixels: vec![Rgb::splat(srgb_to_linear(128.0 / 255.0)); 4],
    };
    write_image(&dir.path().join("env.png"), &grey).unwrap();
    let s = load_in(
        "WorldBegin\nLightSource \"infinite\" \"string filename\" \"env.png\"",
        dir.path(),
    );
    for p in &env(&s).image.pixels {
        assert!((p.g - srgb_to_linear(128.0 / 255.0)).abs() < 1e-6, "{p:?}");
    }
    for (ext, format) in [("jpg", image::ImageFormat::Jpeg), ("tga", image::ImageFormat::Tga)] {
        let path = dir.path().join(format!("env.{ext}"));
        image::RgbImage::from_pixel(2, 2, image::Rgb([128, 128, 128]))
            .save_with_format(&path, format)
            .unwrap();
        let s = load_in(
            &format!("WorldBegin\nLightSource \"infinite\" \"string filename\" \"env.{ext}\""),
            dir.path(),
        );
        for p in &env(&s).image.pixels {
            assert!((p.r - srgb_to_linear(128.0 / 255.0)).abs() < 0.01, "{ext}: {p:?}");
        }
    }

    // Latitude-longitude images need not be square.
    write_pfm(&dir.path().join("latlong.pfm"), 8, 4, pixel);
    let s = load_in(
        "WorldBegin\nLightSource \"infinite\" \"string filename\" \"latlong.pfm\" \"string mapping\" \"equirect\"",
        dir.path(),
    );
    assert_eq!((env(&s).mapping, env(&s).image.width), (EnvMapping::Equirect, 8));
    Scene::build(&s.description).unwrap();
}

/// pbrt-v4's environment-map `illuminance`: the map is scaled so that its upper hemisphere,
/// summed with pbrt's 2 pi / N per pixel, gives the value. For a constant map of luminance
/// Y that sum is pi Y / 2 (the exact irradiance is pi Y), so the scale is 2 E / (pi Y).
#[test]
fn environment_map_illuminance_follows_pbrt() {
    let dir = tempfile::tempdir().unwrap();
    let c = Rgb::new(0.2, 0.4, 0.8);
    write_pfm(&dir.path().join("c.pfm"), 64, 64, |_, _| c);
    write_pfm(&dir.path().join("c-ll.pfm"), 64, 32, |_, _| c);
    for (file, mapping) in [("c.pfm", ""), ("c-ll.pfm", "\"string mapping\" \"equirect\"")] {
        let s = load_in(
            &format!(
                "WorldBegin\nLightSource \"infinite\" \"string filename\" \"{file}\" \"float illuminance\" 5 {mapping}"
            ),
            dir.path(),
        );
        let expected = 2.0 * 5.0 / (PI * c.luminance());
        let got = env(&s).scale;
        assert!(
            (got - expected).abs() < 0.01 * expected,
            "{file}: scale {got}, expected {expected}"
        );
    }
}

#[test]
fn malformed_light_parameters() {
    assert_eq!(
        error("WorldBegin\nLightSource \"spot\" \"float coneangle\" 10 \"float conedeltaangle\" 20"),
        "scene.pbrt:2:41: LightSource \"spot\" needs 0 <= \"conedeltaangle\" <= \"coneangle\" <= 180, found 20 and 10"
    );
    assert_eq!(
        error("WorldBegin\nLightSource \"spot\" \"point3 from\" [1 1 1] \"point3 to\" [1 1 1]"),
        "scene.pbrt:2:42: \"from\" and \"to\" of LightSource \"spot\" must be different points"
    );
    assert_eq!(
        error("WorldBegin\nLightSource \"distant\" \"point3 to\" [0 0 0]"),
        "scene.pbrt:2:23: \"from\" and \"to\" of LightSource \"distant\" must be different points"
    );
    assert_eq!(
        error("WorldBegin\nLightSource \"spot\" \"rgb coneangle\" [1 2 3]"),
        "scene.pbrt:2:20: parameter \"rgb coneangle\" of LightSource \"spot\" has the wrong type: expected \"float coneangle\""
    );
    assert_eq!(
        error("WorldBegin\nLightSource \"distant\" \"float scale\" -2"),
        "scene.pbrt:2:23: \"scale\" of LightSource \"distant\" must not be negative"
    );
    assert_eq!(
        error("WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 -1 1]"),
        "scene.pbrt:2:24: emission \"L\" of LightSource \"infinite\" must not be negative"
    );
    assert_eq!(
        error("WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1] \"string filename\" \"sky.exr\""),
        "scene.pbrt:2:24: LightSource \"infinite\" cannot have both \"L\" and \"filename\""
    );
    assert_eq!(
        error("WorldBegin\nLightSource \"infinite\" \"string mapping\" \"equirect\""),
        "scene.pbrt:2:24: \"mapping\" of LightSource \"infinite\" needs a \"filename\""
    );
    assert_eq!(
        error("WorldBegin\nLightSource \"infinite\" \"point3 portal\" [0 0 0 1 0 0 1 1 0 0 1 0]"),
        "scene.pbrt:2:24: parameter \"point3 portal\" of LightSource \"infinite\" is not supported yet"
    );
    assert_eq!(
        error("WorldBegin\nLightSource \"projection\""),
        "scene.pbrt:2:1: light type \"projection\" is not supported yet"
    );
    assert_eq!(
        error("WorldBegin\nLightSource \"laser\""),
        "scene.pbrt:2:1: unknown light type \"laser\""
    );
}

#[test]
fn malformed_environment_images() {
    let dir = tempfile::tempdir().unwrap();
    write_pfm(&dir.path().join("wide.pfm"), 4, 2, |_, _| Rgb::WHITE);
    write_pfm(&dir.path().join("nan.pfm"), 2, 2, |x, _| {
        Rgb::splat(if x == 0 { f32::NAN } else { 1.0 })
    });
    std::fs::write(dir.path().join("bad.pfm"), b"PF\n2 2\n-1\n").unwrap();
    let src =
        |file: &str, extra: &str| format!("WorldBegin\nLightSource \"infinite\" \"string filename\" \"{file}\"{extra}");
    assert_eq!(
        error_in(&src("wide.pfm", ""), dir.path()),
        "scene.pbrt:2:24: image \"wide.pfm\" is 4x2, not square, so it is not an equal-area environment map (for a latitude-longitude map add \"string mapping\" \"equirect\")"
    );
    assert_eq!(
        error_in(&src("nan.pfm", ""), dir.path()),
        "scene.pbrt:2:24: image \"nan.pfm\" has infinite or not-a-number pixels and so is not suitable as a light"
    );
    assert_eq!(
        error_in(&src("bad.pfm", ""), dir.path()),
        "scene.pbrt:2:24: cannot read image \"bad.pfm\": not a valid PFM file: 0 bytes of data for a 2x2 image of 3 channel(s)"
    );
    assert_eq!(
        error_in(&src("missing.exr", ""), dir.path()),
        "scene.pbrt:2:24: cannot open image \"missing.exr\": No such file or directory"
    );
    assert!(error_in(&src("sky.hdr", ""), dir.path()).starts_with(
        "scene.pbrt:2:24: cannot read image \"sky.hdr\": unsupported image format \"hdr\" (use .exr, .pfm, .png, .jpg, .jpeg or .tga)"
    ));
    assert_eq!(
        error_in(&src("wide.pfm", " \"string mapping\" \"cube\""), dir.path()),
        "scene.pbrt:2:53: unknown \"mapping\" \"cube\" of LightSource \"infinite\" (expected \"equalarea\" or \"equirect\")"
    );
}

/// The CTM at the light rotates environment maps: pbrt scenes commonly turn +z up into +y
/// up with `Rotate -90 1 0 0`.
#[test]
fn environment_map_transform_is_the_ctm() {
    let dir = tempfile::tempdir().unwrap();
    write_pfm(&dir.path().join("e.pfm"), 2, 2, |_, _| Rgb::WHITE);
    let s = load_in(
        "WorldBegin\nAttributeBegin\nRotate -90 1 0 0\nLightSource \"infinite\" \"string filename\" \"e.pfm\"\nAttributeEnd",
        dir.path(),
    );
    let m = env(&s).world_from_light.m;
    let expected = Mat4::from_rotation_x(-PI / 2.0);
    assert!(m.abs_diff_eq(expected, 1e-6), "{m:?}");
}
