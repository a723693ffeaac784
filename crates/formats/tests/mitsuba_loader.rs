//! The Mitsuba XML loader: directives (`default`, `$name`, `-D`, `include`, `path`,
//! `ref`), conventions (camera mirror, `max_depth`, transforms, envmap axes) and malformed
//! input, which must give `file:line:col` and never panic.

use mcrender_core::material::{
    BumpHeight, BumpMapMaterial, ConductorMaterial, DielectricMaterial, DiffuseMaterial, NormalMapMaterial,
    PlasticMaterial,
};
use std::path::{Path, PathBuf};

use mcrender_core::color::Rgb;
use mcrender_core::math::Vec3;
use mcrender_core::scene::{GeometryDesc, IntegratorKind, LightDesc, MaterialDesc, Reconstruction};
use mcrender_formats::{load, load_with, LoadOptions, LoadedScene, SceneError, SceneErrorKind};

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn scene(body: &str) -> String {
    format!("<scene version=\"3.0.0\">\n{body}\n</scene>\n")
}

fn load_text(body: &str) -> Result<LoadedScene, SceneError> {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "s.xml", &scene(body));
    load(&p)
}

fn err(body: &str) -> SceneError {
    load_text(body).expect_err("should fail")
}

const CAMERA: &str = r#"
<sensor type="perspective">
  <float name="fov" value="40"/>
  <transform name="to_world"><lookat origin="0,0,-5" target="0,0,0" up="0,1,0"/></transform>
  <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="16"/><rfilter type="box"/></film>
  <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
</sensor>"#;

#[test]
fn defaults_substitution_and_defines() {
    let body = format!(
        "<default name=\"spp\" value=\"7\"/>\n<default name=\"integrator\" value=\"path\"/>\n\
         <integrator type=\"moment\"><integrator type=\"$integrator\"><integer name=\"max_depth\" value=\"3\"/></integrator></integrator>\n{CAMERA}"
    );
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "s.xml", &scene(&body));
    let l = load(&p).unwrap();
    assert_eq!(l.description.sampler.samples_per_pixel, 7);
    assert_eq!(l.description.film.width, 32);
    // Mitsuba's max_depth 3 (camera ray, two bounces) is two scattering events.
    assert_eq!(l.description.integrator.max_depth, 2);
    assert_eq!(l.description.integrator.kind, IntegratorKind::Path);
    let opts = LoadOptions {
        defines: vec![("spp".into(), "11".into()), ("integrator".into(), "direct".into())],
        ..LoadOptions::default()
    };
    let l = load_with(&p, &opts).unwrap();
    assert_eq!(l.description.sampler.samples_per_pixel, 11);
    assert_eq!(l.description.integrator.kind, IntegratorKind::Direct);
}

#[test]
fn camera_is_mirrored_to_pbrt_convention_and_fov_is_converted() {
    let l = load_text(&format!("<default name=\"spp\" value=\"1\"/>{CAMERA}")).unwrap();
    let c = &l.description.camera;
    // Camera at (0,0,-5) looking at +z with up +y: Mitsuba's image right is world -x (the
    // "left" vector is +x); mcrender's camera +x must therefore map to world -x.
    let right = c.world_from_camera.vector(Vec3::X);
    assert!((right - Vec3::new(-1.0, 0.0, 0.0)).length() < 1e-5, "{right}");
    assert!((c.world_from_camera.point(Vec3::ZERO) - Vec3::new(0.0, 0.0, -5.0)).length() < 1e-5);
    // fov 40 along x on a 2:1 film: the shorter (y) axis spans 2 atan(tan(20) / 2).
    let expected = 2.0 * ((20f32).to_radians().tan() / 2.0).atan().to_degrees();
    assert!((c.fov_degrees - expected).abs() < 1e-3, "{}", c.fov_degrees);
}

#[test]
fn include_path_ref_and_shapes() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    write(
        &dir.path().join("sub"),
        "tri.obj",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n",
    );
    write(
        dir.path(),
        "part.xml",
        &scene(
            r#"<bsdf type="twosided" id="red"><bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.1, 0.1"/></bsdf></bsdf>"#,
        ),
    );
    let main = write(
        dir.path(),
        "main.xml",
        &scene(
            r#"<path value="sub"/>
<include filename="part.xml"/>
<shape type="obj"><string name="filename" value="tri.obj"/><ref id="red"/>
  <transform name="to_world"><translate x="1"/></transform></shape>
<shape type="rectangle"><emitter type="area"><rgb name="radiance" value="2"/></emitter></shape>
<shape type="sphere"><float name="radius" value="0.5"/><point name="center" x="0" y="1" z="0"/></shape>
<emitter type="point"><point name="position" value="1, 2, 3"/><rgb name="intensity" value="5"/></emitter>
<emitter type="directional"><vector name="direction" value="0, 0, -1"/></emitter>"#,
        ),
    );
    let l = load(&main).unwrap();
    let d = &l.description;
    assert_eq!(d.shapes.len(), 3);
    assert!(matches!(&d.materials[d.shapes[0].material as usize],
        MaterialDesc::Diffuse(DiffuseMaterial { reflectance }) if reflectance.constant() == Some(Rgb::new(0.8, 0.1, 0.1))));
    let GeometryDesc::TriangleMesh(m) = &d.shapes[0].geometry else {
        panic!()
    };
    assert_eq!(m.positions[1], Vec3::new(2.0, 0.0, 0.0));
    assert_eq!(d.shapes[1].area_light.unwrap().radiance, Rgb::splat(2.0));
    assert!(matches!(d.lights[0], LightDesc::Point { position, .. } if position == Vec3::new(1.0, 2.0, 3.0)));
    // Mitsuba's direction is the light's travel; mcrender's points towards the light.
    assert!(matches!(d.lights[1], LightDesc::Distant { direction, .. } if direction == Vec3::Z));
}

#[test]
fn malformed_xml_has_file_line_col() {
    let e = err("<shape type=\"sphere\">\n<float name=\"radius\" value=\"1\">\n</shape>");
    assert_eq!(e.kind, SceneErrorKind::Syntax);
    assert!(e.location.file.ends_with("s.xml"));
    assert!(e.location.line >= 2, "{e}");
    assert!(e.to_string().contains("s.xml:"), "{e}");
}

#[test]
fn unknown_plugin_names_element_and_position() {
    let e = err("<bsdf type=\"glitter\" id=\"x\"/>");
    assert_eq!(e.kind, SceneErrorKind::Unsupported);
    assert_eq!((e.location.line, e.location.column), (2, 1), "{e}");
    assert!(e.message.contains("glitter"), "{e}");
    let e = err("<shape type=\"sphere\">\n  <bsdf type=\"hair\"/>\n</shape>");
    assert_eq!(e.kind, SceneErrorKind::Unsupported);
    assert!(e.message.contains("hair"), "{e}");
    assert_eq!(e.location.line, 3, "{e}");
    let e = err("<bsdf type=\"roughconductor\">\n<string name=\"distribution\" value=\"phong\"/></bsdf>");
    assert_eq!(e.kind, SceneErrorKind::Syntax);
    assert!(e.message.contains("phong"), "{e}");
    let e = err("<bsdf type=\"roughplastic\"><float name=\"alpha_u\" value=\"0.1\"/><float name=\"alpha_v\" value=\"0.2\"/></bsdf>");
    assert!(e.message.contains("anisotropic"), "{e}");
}

/// The materials of a scene made of `bsdfs`, one sphere each.
fn materials(bsdfs: &[&str]) -> Vec<MaterialDesc> {
    let dir = tempfile::tempdir().unwrap();
    let body: String = bsdfs
        .iter()
        .map(|b| format!("<shape type=\"sphere\">{b}</shape>\n"))
        .collect();
    write(dir.path(), "m.xml", &scene(&body));
    let l = load(&dir.path().join("m.xml")).unwrap_or_else(|e| panic!("{e}"));
    let d = &l.description;
    d.shapes
        .iter()
        .map(|s| d.materials[s.material as usize].clone())
        .collect()
}

#[test]
fn microfacet_plugins_default_to_beckmann_with_separable_masking() {
    use mcrender_core::bsdf::{Masking, MicrofacetModel};
    let m = materials(&[
        "<bsdf type=\"roughconductor\"/>",
        "<bsdf type=\"roughdielectric\"><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha\" value=\"0.3\"/></bsdf>",
    ]);
    let MaterialDesc::Conductor(ConductorMaterial {
        u_roughness,
        microfacet,
        ..
    }) = &m[0]
    else {
        panic!("{m:?}")
    };
    assert_eq!(
        (u_roughness.constant(), microfacet.model, microfacet.masking),
        (Some(0.1), MicrofacetModel::Beckmann, Masking::Separable)
    );
    let MaterialDesc::Dielectric(DielectricMaterial {
        v_roughness,
        microfacet,
        ..
    }) = &m[1]
    else {
        panic!("{m:?}")
    };
    assert_eq!(
        (v_roughness.constant(), microfacet.model),
        (Some(0.3), MicrofacetModel::TrowbridgeReitz)
    );
}

#[test]
fn plastics_are_mitsubas_model_with_its_defaults() {
    use mcrender_core::bsdf::MicrofacetModel;
    let m = materials(&[
        "<bsdf type=\"plastic\"/>",
        "<bsdf type=\"plastic\"><rgb name=\"diffuse_reflectance\" value=\"0.1, 0.27, 0.36\"/><float name=\"int_ior\" value=\"1.9\"/><boolean name=\"nonlinear\" value=\"true\"/></bsdf>",
        "<bsdf type=\"roughplastic\"><string name=\"distribution\" value=\"ggx\"/><float name=\"alpha\" value=\"0.4\"/><string name=\"int_ior\" value=\"bk7\"/></bsdf>",
        "<bsdf type=\"roughplastic\"/>",
    ]);
    let MaterialDesc::Plastic(PlasticMaterial {
        diffuse_reflectance,
        specular_reflectance,
        nonlinear,
        specular_sampling_weight,
        coat,
    }) = &m[0]
    else {
        panic!("{m:?}")
    };
    assert_eq!(diffuse_reflectance.constant(), Some(Rgb::splat(0.5)));
    assert_eq!(specular_reflectance.constant(), Some(Rgb::splat(1.0)));
    assert!(!nonlinear && coat.distribution().is_none());
    assert!((specular_sampling_weight - 1.0 / 1.5).abs() < 1e-6);
    // Polypropylene in air.
    assert!((coat.eta() - 1.49 / 1.000_277).abs() < 1e-6, "{}", coat.eta());
    let MaterialDesc::Plastic(PlasticMaterial {
        nonlinear,
        specular_sampling_weight,
        coat,
        ..
    }) = &m[1]
    else {
        panic!()
    };
    assert!(*nonlinear && (coat.eta() - 1.9 / 1.000_277).abs() < 1e-6);
    let mean = (0.1 + 0.27 + 0.36) / 3.0;
    assert!((specular_sampling_weight - 1.0 / (1.0 + mean)).abs() < 1e-6);
    let MaterialDesc::Plastic(PlasticMaterial { coat, .. }) = &m[2] else {
        panic!()
    };
    let d = coat.distribution().unwrap();
    assert_eq!((d.model, d.alpha_x), (MicrofacetModel::TrowbridgeReitz, 0.4));
    assert!((coat.eta() - 1.5046 / 1.000_277).abs() < 1e-5);
    let MaterialDesc::Plastic(PlasticMaterial { coat, .. }) = &m[3] else {
        panic!()
    };
    let d = coat.distribution().unwrap();
    assert_eq!((d.model, d.alpha_x), (MicrofacetModel::Beckmann, 0.1));
}

#[test]
fn missing_ref_and_undefined_parameter() {
    let e = err("<shape type=\"sphere\">\n  <ref id=\"nowhere\"/>\n</shape>");
    assert_eq!(e.kind, SceneErrorKind::Invalid);
    assert_eq!((e.location.line, e.location.column), (3, 3), "{e}");
    assert!(e.message.contains("nowhere"), "{e}");
    let e = err("<sensor type=\"perspective\"><float name=\"fov\" value=\"$fov\"/></sensor>");
    assert!(e.message.contains("$fov"), "{e}");
    assert_eq!(e.location.line, 2, "{e}");
}

#[test]
fn cyclic_include_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "a.xml", &scene("<include filename=\"b.xml\"/>"));
    write(dir.path(), "b.xml", &scene("\n<include filename=\"a.xml\"/>"));
    let e = load(&dir.path().join("a.xml")).unwrap_err();
    assert_eq!(e.kind, SceneErrorKind::Invalid);
    assert!(e.message.contains("cyclic"), "{e}");
    assert!(e.location.file.ends_with("b.xml") && e.location.line == 3, "{e}");
}

#[test]
fn bad_values_are_errors_not_panics() {
    for body in [
        "<shape type=\"sphere\"><float name=\"radius\" value=\"abc\"/></shape>",
        "<shape type=\"sphere\"><float name=\"radius\" value=\"-1\"/></shape>",
        "<shape type=\"obj\"><string name=\"filename\" value=\"missing.obj\"/></shape>",
        "<shape type=\"rectangle\"><transform name=\"to_world\"><scale value=\"0\"/></transform></shape>",
        "<sensor type=\"perspective\"><film type=\"hdrfilm\"><integer name=\"width\" value=\"0\"/></film></sensor>",
        "<integrator type=\"path\"><integer name=\"max_depth\" value=\"1.5\"/></integrator>",
        "<emitter type=\"envmap\"><string name=\"filename\" value=\"nope.exr\"/></emitter>",
        "<integrator type=\"moment\"/>",
        "<unknown/>",
    ] {
        let e = err(body);
        assert!(e.location.line >= 1, "{body}: {e}");
    }
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "v.xml", "<scene version=\"0.6.0\"></scene>");
    assert_eq!(load(&p).unwrap_err().kind, SceneErrorKind::Unsupported);
    let p = write(dir.path(), "r.xml", "<notascene/>");
    assert_eq!(load(&p).unwrap_err().kind, SceneErrorKind::Syntax);
}

#[test]
fn unused_parameters_are_warnings_with_location() {
    let l = load_text("<bsdf type=\"diffuse\" id=\"d\">\n  <float name=\"sparkle\" value=\"1\"/>\n</bsdf>").unwrap();
    let w: Vec<_> = l.warnings.iter().filter(|w| w.contains("sparkle")).collect();
    assert_eq!(w.len(), 1, "{:?}", l.warnings);
    assert!(w[0].contains("s.xml:3:3"), "{w:?}");
}

/// Issue 10 item 7 for the Mitsuba loader: every error and warning is one line, quotes the
/// scene's text at most ~80 characters, and escapes control characters (XML allows C1
/// controls such as U+009B, the terminal's CSI, as character references).
#[test]
fn messages_are_one_short_line_without_control_characters() {
    let long = "B".repeat(5000);
    let errors = [
        format!("<{long}/>"),
        format!(r#"<shape type="sphere"><float name="radius" value="${long}"/></shape>"#),
        format!(r#"<shape type="ply"><string name="filename" value="{long}.ply"/></shape>"#),
        format!(r#"<shape type="obj"><string name="filename" value="{long}.obj"/></shape>"#),
        format!(r#"<include filename="{long}.xml"/>"#),
        format!(r#"<shape type="{long}"/>"#),
        r#"<shape type="ply"><string name="filename" value="a&#x9b;31m.ply"/></shape>"#.to_string(),
        r#"<include filename="a&#x9b;31m&#10;.xml"/>"#.to_string(),
        r#"<shape type="sph&#x9b;ere&#127;"/>"#.to_string(),
    ];
    let check = |what: &str, text: &str| {
        assert_eq!(text.lines().count(), 1, "{what}: {text}");
        assert!(text.chars().count() < 400, "{what}: {} characters: {text}", text.len());
        assert!(!text.chars().any(char::is_control), "{what}: {text:?}");
    };
    for body in &errors {
        let e = err(body).to_string();
        check(&body[..body.len().min(60)], &e);
    }
    // The PLY error is the OS's reason once, not "...: No such file or directory (os error 2)".
    let e = err(r#"<shape type="ply"><string name="filename" value="gone.ply"/></shape>"#).to_string();
    assert!(
        e.contains("cannot read PLY \"gone.ply\"") && !e.contains("os error"),
        "{e}"
    );
    let warned = [
        format!(r#"<shape type="sphere"><float name="{long}" value="1"/></shape>"#),
        format!(r#"<shape type="sphere"><{long} name="x" value="1"/></shape>"#),
        r#"<shape type="sphere"><float name="r&#x9b;2J" value="1"/></shape>"#.to_string(),
    ];
    for body in &warned {
        let l = load_text(body).unwrap();
        assert!(!l.warnings.is_empty(), "{body}");
        for w in &l.warnings {
            check(&body[..body.len().min(60)], w);
        }
    }
}

/// Regression: an `obj` shape whose `mtllib` has a one-value colour (`Ks 0.5`, valid MTL)
/// panicked inside tobj 4.0.5 through the Mitsuba loader (the OBJ front door already
/// rewrote such lines; both now go through `obj::parse_obj`).
#[test]
fn mitsuba_obj_with_a_one_value_mtl_colour_does_not_panic() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "m.obj",
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl glossy\nf 1 2 3\n",
    );
    for mtl in ["newmtl glossy\nKs 0.5\n", "newmtl glossy\nKd\nKa 1\nTf 0.2 0.3\n"] {
        write(dir.path(), "m.mtl", mtl);
        let main = write(
            dir.path(),
            "main.xml",
            &scene(r#"<shape type="obj"><string name="filename" value="m.obj"/></shape>"#),
        );
        let l = load(&main).unwrap_or_else(|e| panic!("{mtl:?}: {e}"));
        assert_eq!(l.description.shapes.len(), 1, "{mtl:?}");
    }
}

#[test]
fn normalmap_wraps_its_bsdf_with_a_raw_texture() {
    let m = materials(&[
        "<bsdf type=\"normalmap\"><texture name=\"normalmap\" type=\"rawconstant\"><vector name=\"value\" value=\"0.5, 0.5, 1.0\"/></texture><bsdf type=\"diffuse\"/></bsdf>",
    ]);
    let MaterialDesc::NormalMap(NormalMapMaterial { normal_map, .. }) = &m[0] else {
        panic!("{m:?}")
    };
    assert_eq!(normal_map.constant(), Some(Rgb::new(0.5, 0.5, 1.0)));
    let e = err("<bsdf type=\"normalmap\"><bsdf type=\"diffuse\"/></bsdf>");
    assert!(e.message.contains("normalmap"), "{e}");
    let e = err("<bsdf type=\"normalmap\"><texture name=\"normalmap\" type=\"rawconstant\"><vector name=\"value\" value=\"0.5, 0.5, 1.0\"/></texture></bsdf>");
    assert!(e.message.contains("nested bsdf"), "{e}");
}

#[test]
fn bumpmap_wraps_its_bsdf_with_a_texture_of_any_name_and_a_scale() {
    let m = materials(&[
        "<bsdf type=\"bumpmap\"><float name=\"scale\" value=\"0.02\"/><texture name=\"heights\" type=\"rawconstant\"><float name=\"value\" value=\"0.3\"/></texture><bsdf type=\"diffuse\"/></bsdf>",
    ]);
    let MaterialDesc::BumpMap(BumpMapMaterial {
        height: BumpHeight::Mitsuba { texture, scale },
        ..
    }) = &m[0]
    else {
        panic!("{m:?}")
    };
    assert_eq!(*scale, 0.02);
    assert_eq!(texture.constant(), Some(Rgb::splat(0.3)));
    let e = err("<bsdf type=\"bumpmap\"><bsdf type=\"diffuse\"/></bsdf>");
    assert!(e.message.contains("one nested texture"), "{e}");
    let e = err(
        "<bsdf type=\"bumpmap\"><texture type=\"rawconstant\"><float name=\"value\" value=\"0.3\"/></texture></bsdf>",
    );
    assert!(e.message.contains("one nested bsdf"), "{e}");
}

#[test]
fn serialized_meshes_load_by_shape_index_and_bad_ones_are_errors() {
    use mcrender_core::math::{Vec2, Vec3};
    use mcrender_core::scene::{GeometryDesc, TriangleMeshDesc};
    use mcrender_formats::serialized::write_serialized;
    let tri = |x: f32| TriangleMeshDesc {
        positions: vec![
            Vec3::new(x, 0.0, 0.0),
            Vec3::new(x + 1.0, 0.0, 0.0),
            Vec3::new(x, 1.0, 0.0),
        ],
        indices: vec![0, 1, 2],
        normals: None,
        uvs: Some(vec![Vec2::ZERO, Vec2::X, Vec2::Y]),
        tangents: None,
    };
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("m.serialized"),
        write_serialized(&[("a", &tri(0.0)), ("b", &tri(5.0))]),
    )
    .unwrap();
    let body = r#"<shape type="serialized"><string name="filename" value="m.serialized"/><integer name="shape_index" value="1"/>
        <transform name="to_world"><translate x="0" y="0" z="2"/></transform></shape>"#;
    let xml = write(dir.path(), "s.xml", &scene(body));
    let s = load(&xml).unwrap_or_else(|e| panic!("{e}"));
    let GeometryDesc::TriangleMesh(m) = &s.description.shapes[0].geometry else {
        panic!()
    };
    // The second mesh, moved to z = 2, with v flipped to mcrender's convention.
    assert_eq!(m.positions[0], Vec3::new(5.0, 0.0, 2.0));
    assert_eq!(m.uvs.as_ref().unwrap()[2], Vec2::new(0.0, 0.0));
    let bad = |index: &str, file: &str| {
        let body = format!(
            r#"<shape type="serialized"><string name="filename" value="{file}"/><integer name="shape_index" value="{index}"/></shape>"#
        );
        load(&write(dir.path(), "bad.xml", &scene(&body)))
            .expect_err("should fail")
            .to_string()
    };
    let e = bad("7", "m.serialized");
    assert!(
        e.contains("bad.xml:2:") && e.contains("shape_index 7, but the file holds 2 meshes"),
        "{e}"
    );
    std::fs::write(dir.path().join("junk.serialized"), b"not a mesh at all").unwrap();
    let e = bad("0", "junk.serialized");
    assert!(e.contains("expected the serialized format tag"), "{e}");
    assert!(bad("0", "missing.serialized").contains("cannot read"));
}

/// `spot`: Mitsuba's falloff, its angles in degrees (beam width 3/4 of the cutoff by
/// default), uniform light selection for Mitsuba scenes, and bad angles as errors.
#[test]
fn spot_is_mitsubas_linear_falloff() {
    use mcrender_core::scene::{LightSelection, SpotFalloff};
    let s = load_text(
        "<emitter type=\"spot\"><rgb name=\"intensity\" value=\"2, 3, 4\"/>\
         <float name=\"cutoff_angle\" value=\"40\"/></emitter>",
    )
    .unwrap();
    let LightDesc::Spot(spot) = &s.description.lights[0] else {
        panic!("{:?}", s.description.lights)
    };
    assert_eq!(spot.falloff, SpotFalloff::LinearAngle);
    assert_eq!(spot.intensity, Rgb::new(2.0, 3.0, 4.0));
    assert!((spot.cos_falloff_end - 40f32.to_radians().cos()).abs() < 1e-6);
    assert!((spot.cos_falloff_start - 30f32.to_radians().cos()).abs() < 1e-6);
    assert!(spot.projection.is_none());
    assert_eq!(s.description.integrator.light_selection, LightSelection::Uniform);
    let e = err("<emitter type=\"spot\"><float name=\"cutoff_angle\" value=\"10\"/>\
         <float name=\"beam_width\" value=\"20\"/></emitter>");
    assert_eq!(e.kind, SceneErrorKind::Invalid, "{e}");
    assert!(e.message.contains("beam_width"), "{e}");
}

/// A PLY with a vertex colour and a face weight, two triangles.
const ATTRIBUTE_PLY: &str =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
property float color_0\nproperty float color_1\nproperty float color_2\nelement face 2\n\
property list uchar int vertex_indices\nproperty float weight_0\nend_header\n\
0 0 0 1 0 0\n1 0 0 0 1 0\n1 1 0 0 0 1\n0 1 0 1 1 1\n3 0 1 2 0.25\n3 0 2 3 0.75\n";

/// `mesh_attribute`: a BSDF declared once is built per PLY shape with that shape's data
/// (vertex values with the mesh's indices, face values per triangle); a `blendbsdf` of two
/// diffuse BSDFs is a diffuse with the blended reflectance; misuse is an error naming the
/// attribute.
#[test]
fn mesh_attributes_bind_to_each_ply_shape() {
    use mcrender_core::scene::DiffuseMaterial;
    use mcrender_core::texture::{AttributeRate, Texture};
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "m.ply", ATTRIBUTE_PLY);
    let body = r#"<texture type="mesh_attribute" id="w"><string name="name" value="face_weight"/></texture>
<bsdf type="diffuse" id="vc"><texture type="mesh_attribute" name="reflectance"><string name="name" value="vertex_color"/>
  <float name="scale" value="0.5"/></texture></bsdf>
<bsdf type="blendbsdf" id="blend"><ref name="weight" id="w"/>
  <bsdf type="diffuse"><rgb name="reflectance" value="0.2"/></bsdf><bsdf type="diffuse"><rgb name="reflectance" value="0.6"/></bsdf></bsdf>
<shape type="ply"><string name="filename" value="m.ply"/><ref id="vc"/></shape>
<shape type="ply"><string name="filename" value="m.ply"/><ref id="blend"/></shape>"#;
    let p = write(dir.path(), "s.xml", &scene(body));
    let s = load(&p).unwrap();
    let d = &s.description;
    let material = |i: usize| &d.materials[d.shapes[i].material as usize];
    let MaterialDesc::Diffuse(DiffuseMaterial {
        reflectance: Texture::MeshAttribute(t),
    }) = material(0)
    else {
        panic!("{:?}", material(0))
    };
    assert_eq!(t.scale, 0.5);
    assert_eq!(t.values[1], Rgb::new(0.0, 1.0, 0.0));
    assert!(matches!(&t.rate, AttributeRate::Vertex { indices } if indices[..] == [0, 1, 2, 0, 2, 3]));
    let MaterialDesc::Diffuse(DiffuseMaterial {
        reflectance: Texture::Mix(mix),
    }) = material(1)
    else {
        panic!("{:?}", material(1))
    };
    let Texture::MeshAttribute(w) = &mix.amount else {
        panic!("{:?}", mix.amount)
    };
    assert_eq!((w.values[0], w.values[1]), (Rgb::splat(0.25), Rgb::splat(0.75)));
    assert_eq!(w.rate, AttributeRate::Face);
    assert_eq!(
        (mix.tex1.constant(), mix.tex2.constant()),
        (Some(Rgb::splat(0.2)), Some(Rgb::splat(0.6)))
    );

    // An attribute the file lacks, and one on a shape without attributes.
    let bad = write(
        dir.path(),
        "bad.xml",
        &scene(
            r#"<bsdf type="diffuse" id="x"><texture type="mesh_attribute" name="reflectance"><string name="name" value="vertex_normal"/></texture></bsdf>
<shape type="ply"><string name="filename" value="m.ply"/><ref id="x"/></shape>"#,
        ),
    );
    let e = load(&bad).unwrap_err();
    assert!(
        e.message.contains("vertex_normal") && e.message.contains("vertex_color"),
        "{e}"
    );
    let e = err(
        r#"<bsdf type="diffuse" id="x"><texture type="mesh_attribute" name="reflectance"><string name="name" value="face_color"/></texture></bsdf>
<shape type="sphere"><ref id="x"/></shape>"#,
    );
    assert_eq!(e.kind, SceneErrorKind::Unsupported, "{e}");
    let e = err(
        r#"<texture type="mesh_attribute" id="t"><string name="name" value="color"/></texture>
<bsdf type="diffuse"><ref name="reflectance" id="t"/></bsdf>"#,
    );
    assert!(e.message.contains("vertex_"), "{e}");
}

/// `null`: no surface at all, rays pass through (mcrender's interface material).
#[test]
fn null_bsdf_is_an_interface() {
    let m = materials(&[r#"<bsdf type="null"/>"#, r#"<bsdf type="diffuse"/>"#]);
    assert_eq!(m[0], MaterialDesc::Interface);
    assert_ne!(m[1], MaterialDesc::Interface);
}

#[test]
fn films_splat_through_filters_wider_than_the_pixel_box() {
    let with = |filter: &str| {
        let camera = CAMERA.replace("<rfilter type=\"box\"/>", filter);
        load_text(&format!("<default name=\"spp\" value=\"1\"/>{camera}"))
            .unwrap()
            .description
            .reconstruction
    };
    // The box of radius one half: the same samples as filter sampling, kept.
    assert_eq!(with("<rfilter type=\"box\"/>"), Reconstruction::FilterSampling);
    assert_eq!(with("<rfilter type=\"tent\"/>"), Reconstruction::FilterSplatting);
    // hdrfilm's default filter is the Gaussian.
    assert_eq!(with(""), Reconstruction::FilterSplatting);
}

/// The cylinder of the first shape of `body`, built as the renderer will build it.
fn first_cylinder(body: &str) -> (mcrender_core::shape::Cylinder, bool) {
    let l = load_text(body).unwrap();
    let s = &l.description.shapes[0];
    let GeometryDesc::Cylinder {
        radius,
        z_min,
        z_max,
        phi_max,
        world_from_object,
    } = s.geometry
    else {
        panic!("not a cylinder: {:?}", s.geometry)
    };
    let c = mcrender_core::shape::Cylinder::new(radius, z_min, z_max, phi_max, world_from_object, s.flip_normals);
    (c, s.flip_normals)
}

/// Where a ray from `o` along `d` meets the cylinder: point, normal and uv.
fn cylinder_hit(c: &mcrender_core::shape::Cylinder, o: Vec3, d: Vec3) -> (Vec3, Vec3, [f32; 2]) {
    let ray = mcrender_core::math::Ray::new(o, d);
    let hit = c.intersect(&ray, f32::INFINITY).expect("a hit");
    let si = c.interaction(&ray, &hit);
    (si.p(), si.n(), si.uv.to_array())
}

/// Mitsuba's cylinder: the segment p0..p1 (default (0,0,0)..(0,0,1)), radius (1), placed
/// by to_world, open, normals outwards unless flipped; uv = (phi / 2 pi, 1 - h / |p1 - p0|)
/// (Mitsuba's v flipped, as for every Mitsuba shape here).
#[test]
fn cylinder_parameters_defaults_and_uv() {
    let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-5;
    // Defaults: unit radius around +z from 0 to 1.
    let (c, flip) = first_cylinder("<shape type=\"cylinder\"/>");
    assert!(!flip);
    assert!((c.area() - std::f32::consts::TAU).abs() < 1e-5);
    let (p, n, uv) = cylinder_hit(&c, Vec3::new(5.0, 0.0, 0.25), -Vec3::X);
    assert!(close(p, Vec3::new(1.0, 0.0, 0.25)) && close(n, Vec3::X), "{p} {n}");
    assert!((uv[0] - 0.0).abs() < 1e-5 && (uv[1] - 0.75).abs() < 1e-5, "{uv:?}");
    // Nothing above p1 or below p0.
    assert!(c
        .intersect(
            &mcrender_core::math::Ray::new(Vec3::new(5.0, 0.0, 1.1), -Vec3::X),
            f32::INFINITY
        )
        .is_none());
    // p0, p1, radius and to_world; flipped normals.
    let (c, flip) = first_cylinder(
        r#"<shape type="cylinder">
             <point name="p0" x="1" y="0" z="0"/><point name="p1" x="1" y="0" z="2"/>
             <float name="radius" value="0.5"/><boolean name="flip_normals" value="true"/>
             <transform name="to_world"><translate y="3"/></transform>
           </shape>"#,
    );
    assert!(flip);
    assert!((c.area() - 2.0 * std::f32::consts::PI).abs() < 1e-5, "{}", c.area());
    // Frame of +z: s = +x, t = +y, so phi = 90 degrees is +y: u = 1/4; h = 0.5 of 2.
    let (p, n, uv) = cylinder_hit(&c, Vec3::new(1.0, 10.0, 0.5), -Vec3::Y);
    assert!(close(p, Vec3::new(1.0, 3.5, 0.5)) && close(n, -Vec3::Y), "{p} {n}");
    assert!((uv[0] - 0.25).abs() < 1e-5 && (uv[1] - 0.75).abs() < 1e-5, "{uv:?}");
    // A slanted axis: the surface is at distance radius from the segment.
    let (c, _) = first_cylinder(
        r#"<shape type="cylinder"><point name="p0" x="0" y="0" z="0"/><point name="p1" x="1" y="1" z="0"/>
           <float name="radius" value="0.25"/></shape>"#,
    );
    let (p, n, _) = cylinder_hit(&c, Vec3::new(0.5, 0.5, 3.0), -Vec3::Z);
    assert!(close(p, Vec3::new(0.5, 0.5, 0.25)) && close(n, Vec3::Z), "{p} {n}");
}

#[test]
fn malformed_cylinders_have_file_line_col() {
    let e = err("<shape type=\"cylinder\">\n  <float name=\"radius\" value=\"0\"/>\n</shape>");
    assert_eq!(e.kind, SceneErrorKind::Invalid);
    assert!(
        e.to_string().contains("s.xml:3:3: cylinder radius 0 must be positive"),
        "{e}"
    );
    let e = err("<shape type=\"cylinder\">\n  <point name=\"p0\" x=\"1\" y=\"2\" z=\"3\"/>\n  <point name=\"p1\" x=\"1\" y=\"2\" z=\"3\"/>\n</shape>");
    assert_eq!(e.kind, SceneErrorKind::Invalid);
    assert!(e.to_string().contains("s.xml:4:3: cylinder p0"), "{e}");
    assert!(e.to_string().contains("must be distinct finite points"), "{e}");
    let e = err("<shape type=\"cylinder\">\n  <float name=\"radius\" value=\"wide\"/>\n</shape>");
    assert!(e.location.line == 3, "{e}");
    // An unknown parameter is a warning with its location.
    let l = load_text("<shape type=\"cylinder\">\n  <float name=\"height\" value=\"2\"/>\n</shape>").unwrap();
    assert!(
        l.warnings
            .iter()
            .any(|w| w.contains("height") && w.contains("s.xml:3:3")),
        "{:?}",
        l.warnings
    );
}
