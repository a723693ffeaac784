//! `"float alpha"` and `"texture alpha"` on shapes: read for every shape type (also inside
//! objects), constant 1 meaning no alpha test, and errors for bad textures.

use std::path::Path;

use mcrender_core::scene::{FloatTexture, SceneDescription};
use mcrender_core::texture::Texture;
use mcrender_formats::pbrt::{load_str, LoadedScene};
use mcrender_formats::SceneErrorKind;

fn load(body: &str) -> Result<LoadedScene, mcrender_formats::SceneError> {
    load_str(&format!("WorldBegin\n{body}"), "scene.pbrt", Path::new(""))
}

fn desc(body: &str) -> SceneDescription {
    let s = load(body).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        !s.warnings.iter().any(|w| w.contains("alpha")),
        "alpha is supported: {:?}",
        s.warnings
    );
    s.description
}

const SHAPES: [&str; 4] = [
    "Shape \"sphere\"",
    "Shape \"disk\"",
    "Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 2]",
    "Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 1 1 1 0] \"integer indices\" [0 1 2 3]",
];

#[test]
fn float_alpha_on_every_shape() {
    for shape in SHAPES {
        let d = desc(&format!("{shape} \"float alpha\" 0.25"));
        assert_eq!(d.shapes[0].alpha, Some(FloatTexture::Constant(0.25)), "{shape}");
        // Opaque: no alpha test at all, whether given as 1 or not given.
        assert_eq!(
            desc(&format!("{shape} \"float alpha\" 1")).shapes[0].alpha,
            None,
            "{shape}"
        );
        assert_eq!(desc(shape).shapes[0].alpha, None, "{shape}");
    }
}

#[test]
fn texture_alpha_and_alpha_in_objects() {
    let checks = "Texture \"leaf\" \"float\" \"checkerboard\" \"float uscale\" 8 \"float tex2\" 0\n";
    for shape in SHAPES {
        let d = desc(&format!("{checks}{shape} \"texture alpha\" \"leaf\""));
        assert!(
            matches!(d.shapes[0].alpha, Some(Texture::Checkerboard(_))),
            "{shape}: {:?}",
            d.shapes[0].alpha
        );
    }
    let d = desc(&format!(
        "{checks}ObjectBegin \"o\"\nShape \"sphere\" \"texture alpha\" \"leaf\"\nShape \"disk\" \"float alpha\" 0\nObjectEnd\nObjectInstance \"o\""
    ));
    let shapes = &d.objects[0].shapes;
    assert!(matches!(shapes[0].alpha, Some(Texture::Checkerboard(_))), "{shapes:?}");
    assert_eq!(shapes[1].alpha, Some(FloatTexture::Constant(0.0)));
}

#[test]
fn alpha_errors_say_where_and_what() {
    let cases: &[(&str, SceneErrorKind, &str)] = &[
        (
            "Shape \"sphere\" \"texture alpha\" \"nope\"",
            SceneErrorKind::Invalid,
            "scene.pbrt:2:16: \"texture alpha\" of Shape \"sphere\" refers to texture \"nope\", which is not defined (define it with Texture \"nope\" \"float\" ... first)",
        ),
        (
            "Texture \"s\" \"spectrum\" \"constant\"\nShape \"sphere\" \"texture alpha\" \"s\"",
            SceneErrorKind::Invalid,
            "scene.pbrt:3:16: \"texture alpha\" of Shape \"sphere\" needs a float texture, but texture \"s\" is a spectrum texture",
        ),
        ("Shape \"disk\" \"string alpha\" \"half\"", SceneErrorKind::Syntax, "scene.pbrt:2:14: parameter \"string alpha\" of Shape \"disk\" has the wrong type: expected \"float alpha\" or \"texture alpha\""),
    ];
    for (body, kind, message) in cases {
        let e = load(body).unwrap_err();
        assert_eq!((&e.kind, e.to_string().as_str()), (kind, *message), "{body}");
    }
}
