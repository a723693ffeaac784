//! Malformed, invalid and unsupported input: the exact message, with line and column.

use std::path::Path;

use mcrender_formats::pbrt::load_str;
use mcrender_formats::SceneErrorKind;

/// The error message for `src`, loaded as `scene.pbrt`.
fn error(src: &str) -> String {
    match load_str(src, "scene.pbrt", Path::new("")) {
        Ok(_) => panic!("expected an error for:\n{src}"),
        Err(e) => e.to_string(),
    }
}

fn kind(src: &str) -> SceneErrorKind {
    load_str(src, "scene.pbrt", Path::new("")).unwrap_err().kind
}

#[test]
fn bad_number() {
    assert_eq!(
        error("WorldBegin\nTranslate 1 abc 3"),
        "scene.pbrt:2:13: expected a number, found \"abc\""
    );
    assert_eq!(
        error("Translate 1 2"),
        "scene.pbrt:1:14: expected a number, found end of file"
    );
    assert_eq!(
        error("Scale 1 \"2\" 3"),
        "scene.pbrt:1:9: expected a number, found string \"2\""
    );
    assert_eq!(
        error("Rotate 1e39 0 0 1"),
        "scene.pbrt:1:8: expected a finite number, found \"1e39\""
    );
}

#[test]
fn unterminated_string() {
    assert_eq!(
        error("WorldBegin\nShape \"sphere\n\"float radius\" 1"),
        "scene.pbrt:2:7: unterminated string"
    );
    assert_eq!(kind("Film \"rgb"), SceneErrorKind::Syntax);
}

#[test]
fn unknown_directive() {
    assert_eq!(
        error("WorldBegin\n  Foo \"bar\""),
        "scene.pbrt:2:3: unknown directive \"Foo\""
    );
    assert_eq!(
        error("WorldBegin\n[ 1 ]"),
        "scene.pbrt:2:1: expected a directive, found \"[\""
    );
    assert_eq!(
        error("\"sphere\""),
        "scene.pbrt:1:1: expected a directive, found string \"sphere\""
    );
}

#[test]
fn unknown_and_unsupported_shapes() {
    assert_eq!(
        error("WorldBegin\nShape \"cube\""),
        "scene.pbrt:2:1: unknown shape \"cube\""
    );
    assert_eq!(
        error("WorldBegin\nShape \"loopsubdiv\""),
        "scene.pbrt:2:1: shape \"loopsubdiv\" is not supported yet"
    );
    assert_eq!(kind("WorldBegin\nShape \"curve\""), SceneErrorKind::Unsupported);
}

#[test]
fn malformed_disks() {
    assert_eq!(
        error("WorldBegin\nShape \"disk\" \"float radius\" -1"),
        "scene.pbrt:2:14: disk radius must be positive, found -1"
    );
    assert_eq!(
        error("WorldBegin\nShape \"disk\" \"float radius\" 1 \"float innerradius\" 2"),
        "scene.pbrt:2:31: disk innerradius must be in [0, radius = 1), found 2"
    );
    assert_eq!(
        error("WorldBegin\nShape \"disk\" \"float phimax\" 0"),
        "scene.pbrt:2:14: disk phimax must be positive"
    );
}

#[test]
fn malformed_cylinders() {
    assert_eq!(
        error("WorldBegin\nShape \"cylinder\" \"float radius\" 0"),
        "scene.pbrt:2:18: cylinder radius must be positive, found 0"
    );
    assert_eq!(
        error("WorldBegin\nShape \"cylinder\" \"float zmin\" 0.5 \"float zmax\" 0.5"),
        "scene.pbrt:2:35: cylinder zmin and zmax must be finite and differ, found 0.5 and 0.5"
    );
    assert_eq!(
        error("WorldBegin\nShape \"cylinder\" \"float zmin\" 1"),
        "scene.pbrt:2:18: cylinder zmin and zmax must be finite and differ, found 1 and 1"
    );
    assert_eq!(
        error("WorldBegin\nShape \"cylinder\" \"float phimax\" -10"),
        "scene.pbrt:2:18: cylinder phimax must be positive"
    );
    assert_eq!(
        kind("WorldBegin\nShape \"cylinder\" \"float radius\" -1"),
        SceneErrorKind::Invalid
    );
    assert_eq!(
        error("WorldBegin\nShape \"cylinder\" \"string radius\" \"big\""),
        "scene.pbrt:2:18: parameter \"string radius\" of Shape \"cylinder\" has the wrong type: expected \"float radius\""
    );
}

#[test]
fn malformed_bilinear_patches() {
    assert_eq!(
        error(
            "WorldBegin\nShape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 0] \"integer indices\" [0 1 2]"
        ),
        "scene.pbrt:2:62: \"integer indices\" needs a non-zero multiple of 4 values, found 3"
    );
    assert_eq!(
        error("WorldBegin\nShape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0]"),
        "scene.pbrt:2:1: Shape \"bilinearmesh\" needs \"integer indices\" (P has 3 points, not 4)"
    );
    // The same checks hold for curved patches.
    assert_eq!(
        error("WorldBegin\nShape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 1] \"integer indices\" [0 1 2 4]"),
        "scene.pbrt:2:62: vertex index 4 is out of range (P has 4 points)"
    );
    assert_eq!(
        error(
            "WorldBegin\nShape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 1] \"normal N\" [0 0 1  0 0 1  0 0 1]"
        ),
        "scene.pbrt:2:62: \"normal N\" has 3 values but P has 4 points"
    );
    assert_eq!(
        error("WorldBegin\nShape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1 1] \"point2 uv\" [0 0 1 0]"),
        "scene.pbrt:2:62: \"point2 uv\" has 2 values but P has 4 points"
    );
    assert_eq!(
        error("WorldBegin\nShape \"bilinearmesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0  1 1]"),
        "scene.pbrt:2:22: parameter \"point3 P\" needs a multiple of 3 values, found 11"
    );
}

#[test]
fn object_instancing_errors() {
    assert_eq!(
        error("WorldBegin\nObjectInstance \"nothing\""),
        "scene.pbrt:2:1: object \"nothing\" is not defined"
    );
    assert_eq!(
        error(
            "WorldBegin\nObjectBegin \"a\"\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\nShape \"sphere\"\nObjectEnd"
        ),
        "scene.pbrt:4:1: Area lights not supported with object instancing"
    );
    assert_eq!(
        error("WorldBegin\nObjectBegin \"a\"\nObjectBegin \"b\""),
        "scene.pbrt:3:1: ObjectBegin \"b\" inside the definition of object \"a\"; objects do not nest"
    );
    assert_eq!(
        error("WorldBegin\nObjectBegin \"a\"\nObjectInstance \"a\""),
        "scene.pbrt:3:1: ObjectInstance inside an object definition; objects do not nest"
    );
    assert_eq!(
        error("WorldBegin\nObjectEnd"),
        "scene.pbrt:2:1: ObjectEnd without a matching ObjectBegin"
    );
    assert_eq!(
        error("WorldBegin\nObjectBegin \"a\"\nShape \"sphere\""),
        "scene.pbrt:2:1: ObjectBegin has no matching ObjectEnd"
    );
    assert_eq!(
        error("WorldBegin\nObjectBegin \"a\"\nObjectEnd\nObjectBegin \"a\""),
        "scene.pbrt:4:1: object \"a\" is defined twice"
    );
}

#[test]
fn wrong_parameter_type_and_arity() {
    assert_eq!(
        error("WorldBegin\nShape \"sphere\" \"integer radius\" 2"),
        "scene.pbrt:2:16: parameter \"integer radius\" of Shape \"sphere\" has the wrong type: expected \"float radius\""
    );
    assert_eq!(
        error("Film \"rgb\" \"float xresolution\" 640"),
        "scene.pbrt:1:12: parameter \"float xresolution\" of Film \"rgb\" has the wrong type: expected \"integer xresolution\""
    );
    assert_eq!(
        error("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0]"),
        "scene.pbrt:2:22: parameter \"point3 P\" needs a multiple of 3 values, found 5"
    );
    assert_eq!(
        error("WorldBegin\nShape \"sphere\" \"float radius\" [1 2]"),
        "scene.pbrt:2:16: parameter \"float radius\" needs exactly one value, found 2"
    );
    assert_eq!(
        error("Film \"rgb\" \"integer xresolution\" 64.5"),
        "scene.pbrt:1:34: expected an integer, found \"64.5\""
    );
    assert_eq!(
        error("Film \"rgb\" \"integer xresolution\" [ 64"),
        "scene.pbrt:1:38: expected \"]\" closing the values of parameter \"integer xresolution\", found end of file"
    );
}

#[test]
fn missing_ply_file() {
    let src = "WorldBegin\nShape \"plymesh\" \"string filename\" \"models/foo.ply\"";
    let err = load_str(src, "scene.pbrt", Path::new("")).unwrap_err();
    assert_eq!(err.kind, SceneErrorKind::Io);
    assert_eq!(
        err.to_string(),
        "scene.pbrt:2:1: cannot open PLY file \"models/foo.ply\": No such file or directory"
    );
}

#[test]
fn absurd_resolution() {
    assert_eq!(
        error("Film \"rgb\" \"integer xresolution\" 0\nWorldBegin"),
        "scene.pbrt:1:12: parameter \"integer xresolution\" of Film \"rgb\" must be between 1 and 32768, found 0"
    );
    assert_eq!(
        error("Film \"rgb\" \"integer yresolution\" -5\nWorldBegin"),
        "scene.pbrt:1:12: parameter \"integer yresolution\" of Film \"rgb\" must be between 1 and 32768, found -5"
    );
    assert_eq!(
        error("Film \"rgb\" \"integer xresolution\" 32768 \"integer yresolution\" 32768"),
        "scene.pbrt:1:1: film resolution 32768x32768 is too large (at most 268435456 pixels)"
    );
    assert_eq!(
        error("Film \"rgb\" \"integer xresolution\" 99999999999"),
        "scene.pbrt:1:34: integer \"99999999999\" is out of range"
    );
}

#[test]
fn nan_and_negative_values() {
    assert_eq!(
        error("WorldBegin\nShape \"sphere\" \"float radius\" nan"),
        "scene.pbrt:2:31: expected a number, found \"nan\""
    );
    assert_eq!(
        error("WorldBegin\nShape \"sphere\" \"float radius\" -1"),
        "scene.pbrt:2:16: sphere radius must be positive, found -1"
    );
    assert_eq!(
        error("Sampler \"independent\" \"integer pixelsamples\" 0"),
        "scene.pbrt:1:23: parameter \"integer pixelsamples\" of Sampler \"independent\" must be at least 1"
    );
    assert_eq!(
        error("Integrator \"path\" \"integer maxdepth\" -1"),
        "scene.pbrt:1:19: parameter \"integer maxdepth\" of Integrator \"path\" must not be negative"
    );
    assert_eq!(
        error("WorldBegin\nMaterial \"diffuse\" \"rgb reflectance\" [1.5 0 0]"),
        "scene.pbrt:2:20: reflectance (1.5 0 0) of Material \"diffuse\" must be between 0 and 1"
    );
    assert_eq!(
        error("Camera \"perspective\" \"float fov\" 180"),
        "scene.pbrt:1:22: parameter \"float fov\" of Camera \"perspective\" must be between 0 and 180 degrees"
    );
}

#[test]
fn unbalanced_attributes() {
    assert_eq!(
        error("WorldBegin\nAttributeEnd"),
        "scene.pbrt:2:1: AttributeEnd without a matching AttributeBegin"
    );
    assert_eq!(
        error("WorldBegin\nAttributeBegin\n  AttributeBegin\n  AttributeEnd\n"),
        "scene.pbrt:2:1: AttributeBegin has no matching AttributeEnd"
    );
}

#[test]
fn block_structure() {
    assert_eq!(
        error("Camera \"perspective\"\n"),
        "scene.pbrt:2:1: end of file before \"WorldBegin\""
    );
    assert_eq!(
        error("Shape \"sphere\""),
        "scene.pbrt:1:1: \"Shape\" is only allowed inside the world block, after WorldBegin"
    );
    assert_eq!(
        error("WorldBegin\nFilm \"rgb\""),
        "scene.pbrt:2:1: options cannot be set inside the world block; \"Film\" must come before WorldBegin"
    );
    assert_eq!(
        error("WorldBegin\nWorldBegin"),
        "scene.pbrt:2:1: WorldBegin appears twice"
    );
}

#[test]
fn unsupported_features_are_named() {
    assert_eq!(
        error("WorldBegin\nMaterial \"hair\""),
        "scene.pbrt:2:1: material type \"hair\" is not supported yet"
    );
    assert_eq!(
        error("WorldBegin\nMakeNamedMaterial \"m\" \"string type\" \"subsurface\""),
        "scene.pbrt:2:23: material type \"subsurface\" is not supported yet (in MakeNamedMaterial \"m\")"
    );
    assert_eq!(
        error("WorldBegin\nMaterial \"shiny\""),
        "scene.pbrt:2:1: unknown material type \"shiny\""
    );
    assert_eq!(
        error("WorldBegin\nMaterial \"diffuse\" \"spectrum reflectance\" \"metal-Cu-eta\""),
        "scene.pbrt:2:20: \"spectrum reflectance\" of Material \"diffuse\" (a named spectrum) is not supported yet; give \"rgb reflectance\", \"spectrum reflectance\" as (wavelength, value) pairs or \"texture reflectance\""
    );
    assert_eq!(
        error("WorldBegin\nTexture \"n\" \"float\" \"fbm\""),
        "scene.pbrt:2:21: texture class \"fbm\" (Texture \"n\") is not supported yet"
    );
    assert_eq!(
        error("WorldBegin\nLightSource \"goniometric\""),
        "scene.pbrt:2:1: light type \"goniometric\" is not supported yet"
    );
    assert_eq!(
        error("Camera \"realistic\""),
        "scene.pbrt:1:1: camera type \"realistic\" is not supported yet (cameras: perspective, orthographic)"
    );
    assert_eq!(
        error("MakeNamedMedium \"fog\" \"string type\" \"homogeneous\""),
        "scene.pbrt:1:1: MakeNamedMedium \"fog\": participating media are not supported yet"
    );
    assert_eq!(
        error("ColorSpace \"rec2020\""),
        "scene.pbrt:1:1: color space \"rec2020\" is not supported yet (only \"srgb\")"
    );
    assert_eq!(
        error("WorldBegin\nMaterial \"diffuse\" \"blackbody reflectance\" 5500"),
        "scene.pbrt:2:20: \"blackbody reflectance\" of Material \"diffuse\": a blackbody is only accepted as an emission (L or I)"
    );
    assert_eq!(kind("Sampler \"bogus\""), SceneErrorKind::Syntax);
    assert_eq!(kind("WorldBegin\nMaterial \"measured\""), SceneErrorKind::Unsupported);
}

#[test]
fn undefined_named_material() {
    assert_eq!(
        error("WorldBegin\nNamedMaterial \"nope\"\nShape \"sphere\""),
        "scene.pbrt:2:1: named material \"nope\" is not defined"
    );
    assert_eq!(
        error("WorldBegin\nMakeNamedMaterial \"a\" \"string type\" \"diffuse\"\nMakeNamedMaterial \"a\" \"string type\" \"diffuse\""),
        "scene.pbrt:3:1: named material \"a\" is already defined at scene.pbrt:2:1"
    );
}

#[test]
fn bad_meshes() {
    assert_eq!(
        error("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"integer indices\" [0 1 3]"),
        "scene.pbrt:2:53: vertex index 3 is out of range (P has 3 points)"
    );
    assert_eq!(
        error("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 1]"),
        "scene.pbrt:2:1: Shape \"trianglemesh\" needs \"integer indices\" (P has 4 points, not 3)"
    );
    assert_eq!(
        error("WorldBegin\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0] \"normal N\" [0 0 1]"),
        "scene.pbrt:2:53: \"normal N\" has 1 values but P has 3 points"
    );
    assert_eq!(
        error("WorldBegin\nScale 0 1 1\nShape \"sphere\""),
        "scene.pbrt:3:1: the current transformation of Shape \"sphere\" is singular or not finite"
    );
    assert_eq!(
        error("WorldBegin\nRotate 30 0 0 0"),
        "scene.pbrt:2:1: Rotate: the rotation axis has zero length"
    );
    assert_eq!(
        error("LookAt 0 0 0  0 0 0  0 1 0"),
        "scene.pbrt:1:1: LookAt: the eye point and the look-at point are the same"
    );
}

#[test]
fn bad_utf8_reports_its_position() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.pbrt");
    std::fs::write(&path, b"WorldBegin\n  Shape \xff").unwrap();
    let err = mcrender_formats::pbrt::load_file(&path).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!("{}:2:9: the file is not valid UTF-8", path.display())
    );
}
