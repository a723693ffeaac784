//! The orthographic camera in both loaders: pbrt-v4 `Camera "orthographic"` (parameters,
//! defaults, errors with `file:line:col`) and Mitsuba 3's `orthographic` sensor (window from
//! `to_world`'s scale, `near_clip`, the mirrored image x, errors).

use std::path::Path;

use mcrender_core::math::{Vec2, Vec3};
use mcrender_core::scene::{Projection, Scene};
use mcrender_formats::{load, pbrt::load_str, LoadedScene, SceneError};

const PBRT_TAIL: &str = "Film \"rgb\" \"integer xresolution\" 40 \"integer yresolution\" 20\nWorldBegin\n";

fn pbrt(camera: &str) -> Result<LoadedScene, SceneError> {
    load_str(&format!("{camera}\n{PBRT_TAIL}"), "scene.pbrt", Path::new(""))
}

fn mitsuba(sensor_body: &str) -> Result<LoadedScene, SceneError> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.xml");
    let text = format!(
        "<scene version=\"3.0.0\">\n<sensor type=\"orthographic\">\n{sensor_body}\n<film type=\"hdrfilm\">\
         <integer name=\"width\" value=\"40\"/><integer name=\"height\" value=\"20\"/></film>\n</sensor>\n</scene>\n"
    );
    std::fs::write(&path, text).unwrap();
    load(&path)
}

/// The message of a load that must fail.
fn fails(r: Result<LoadedScene, SceneError>) -> String {
    match r {
        Ok(_) => panic!("loaded"),
        Err(e) => e.to_string(),
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

#[test]
fn pbrt_orthographic_defaults() {
    let s = pbrt("Camera \"orthographic\"").unwrap();
    let c = &s.description.camera;
    assert_eq!(c.projection, Projection::Orthographic);
    assert_eq!(c.screen_window, None);
    assert_eq!(c.lens_radius, 0.0);
    assert_eq!(c.focal_distance, 1e6);
    // pbrt's default window for a 2:1 film is [-2, 2] x [-1, 1]: raster (0, 0) starts at
    // camera (-2, 1, 0); the camera looks down +z.
    let cam = Scene::build(&s.description).unwrap().camera;
    let r = cam.generate_ray(Vec2::ZERO, Vec2::ZERO);
    assert!(close(r.o, Vec3::new(-2.0, 1.0, 0.0)) && close(r.d, Vec3::Z), "{r:?}");
}

#[test]
fn pbrt_orthographic_parameters() {
    let s = pbrt(
        "Camera \"orthographic\" \"float screenwindow\" [-1 3 -0.5 0.5] \"float lensradius\" 0.1 \
         \"float focaldistance\" 3",
    )
    .unwrap();
    let c = &s.description.camera;
    assert_eq!(c.screen_window, Some([-1.0, 3.0, -0.5, 0.5]));
    assert_eq!((c.lens_radius, c.focal_distance), (0.1, 3.0));
    let s = pbrt("Camera \"orthographic\" \"float frameaspectratio\" 0.5").unwrap();
    assert_eq!(s.description.camera.screen_window, Some([-1.0, 1.0, -2.0, 2.0]));
    // An orthographic camera has no field of view: "fov" is reported unused.
    let s = pbrt("Camera \"orthographic\" \"float fov\" 30").unwrap();
    assert!(s.warnings.iter().any(|w| w.contains("fov")), "{:?}", s.warnings);
    // The CTM places the camera.
    let s = pbrt("LookAt 0 0 5  0 0 0  0 1 0\nCamera \"orthographic\"").unwrap();
    let cam = Scene::build(&s.description).unwrap().camera;
    let r = cam.generate_ray(Vec2::new(20.0, 10.0), Vec2::ZERO);
    assert!(close(r.o, Vec3::new(0.0, 0.0, 5.0)) && close(r.d, -Vec3::Z), "{r:?}");
}

#[test]
fn pbrt_orthographic_errors_name_the_place() {
    let err = |camera: &str| fails(pbrt(camera));
    let e = err("Camera \"orthographic\" \"float lensradius\" -1");
    assert!(e.starts_with("scene.pbrt:1:") && e.contains("lensradius"), "{e}");
    let e = err("Camera \"orthographic\" \"float screenwindow\" [1 -1 0 1]");
    assert!(e.starts_with("scene.pbrt:1:") && e.contains("screenwindow"), "{e}");
    let e = err("Camera \"orthographic\" \"float focaldistance\" 0");
    assert!(e.starts_with("scene.pbrt:1:") && e.contains("focaldistance"), "{e}");
    let e = err("\nCamera \"spherical\"");
    assert!(e.starts_with("scene.pbrt:2:1:") && e.contains("orthographic"), "{e}");
}

#[test]
fn mitsuba_orthographic_defaults_mirror_x_and_clip_near() {
    let s = mitsuba("").unwrap();
    let c = &s.description.camera;
    assert_eq!(c.projection, Projection::Orthographic);
    // The window [-1, 1] x [-1/aspect, 1/aspect] on the plane z = near_clip = 0.01.
    assert_eq!(c.screen_window, Some([-1.0, 1.0, -0.5, 0.5]));
    let cam = Scene::build(&s.description).unwrap().camera;
    let r = cam.generate_ray(Vec2::ZERO, Vec2::ZERO);
    // Mitsuba's image x runs along local -x: raster (0, 0) is at local (+1, 0.5).
    assert!(close(r.o, Vec3::new(1.0, 0.5, 0.01)) && close(r.d, Vec3::Z), "{r:?}");
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn mitsuba_orthographic_window_from_to_world_scale() {
    let s = mitsuba(
        "<float name=\"near_clip\" value=\"0\"/>\n<transform name=\"to_world\"><scale x=\"10\" y=\"10\"/>\
         <lookat origin=\"1, 1, 1\" target=\"1, 2, 1\" up=\"0, 0, 1\"/></transform>",
    )
    .unwrap();
    let cam = Scene::build(&s.description).unwrap().camera;
    // Looking along +y from (1, 1, 1), "up" +z in the image, the window 20 x 10.
    let centre = cam.generate_ray(Vec2::new(20.0, 10.0), Vec2::ZERO);
    assert!(close(centre.o, Vec3::ONE) && close(centre.d, Vec3::Y), "{centre:?}");
    let corner = cam.generate_ray(Vec2::ZERO, Vec2::ZERO);
    // Top-left: up is +z, and with Mitsuba's left-handed lookat the image's left is
    // local +x = up x dir = z x y = -x.
    assert!(close(corner.o, Vec3::new(1.0 - 10.0, 1.0, 1.0 + 5.0)), "{corner:?}");
}

#[test]
fn mitsuba_orthographic_errors_and_warnings() {
    let e = fails(mitsuba(
        "<float name=\"near_clip\" value=\"2\"/><float name=\"far_clip\" value=\"1\"/>",
    ));
    assert!(e.contains(":2:1:") && e.contains("near_clip"), "{e}");
    let e = fails(mitsuba(
        "<transform name=\"to_world\"><scale x=\"3\"/><rotate z=\"1\" angle=\"30\"/><scale y=\"2\"/></transform>",
    ));
    assert!(e.contains(":2:1:") && e.contains("shear"), "{e}");
    let s = mitsuba("<float name=\"far_clip\" value=\"100\"/>").unwrap();
    assert!(s.warnings.iter().any(|w| w.contains("far_clip")), "{:?}", s.warnings);
}
