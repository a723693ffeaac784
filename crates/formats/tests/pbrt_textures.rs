//! `Texture` and `"texture ..."` parameters: each class, the texture graph they build, the
//! errors, image decoding, and a render whose mean radiance is the texture's mean.

use mcrender_core::material::{BumpHeight, BumpMapMaterial, ConductorMaterial, DiffuseMaterial, NormalMapMaterial};
use std::path::Path;

use mcrender_core::color::{srgb_to_linear, Rgb};
use mcrender_core::math::Vec2;
use mcrender_core::render::{render, RenderOptions};
use mcrender_core::scene::{MaterialDesc, Scene};
use mcrender_core::texture::{MipFilter, RgbTexture, Texture, TextureContext, TextureMapping, WrapMode};
use mcrender_formats::pbrt::{load_str, LoadedScene};
use mcrender_formats::SceneErrorKind;

fn load(body: &str, dir: &Path) -> Result<LoadedScene, mcrender_formats::SceneError> {
    load_str(&format!("WorldBegin\n{body}\nShape \"sphere\""), "scene.pbrt", dir)
}

/// The diffuse reflectance texture of the (only) sphere.
fn reflectance(body: &str, dir: &Path) -> RgbTexture {
    let s = load(body, dir).unwrap_or_else(|e| panic!("{e}"));
    let d = s.description;
    match &d.materials[d.shapes[0].material as usize] {
        MaterialDesc::Diffuse(DiffuseMaterial { reflectance }) => reflectance.clone(),
        m => panic!("{m:?}"),
    }
}

fn error(body: &str, dir: &Path) -> (SceneErrorKind, String) {
    let e = load(body, dir).unwrap_err();
    (e.kind, e.to_string())
}

fn at(uv: (f32, f32)) -> TextureContext {
    TextureContext {
        uv: Vec2::new(uv.0, uv.1),
        ..TextureContext::default()
    }
}

/// Write a `w` x `h` 8-bit RGB PNG from `f(x, y)`.
fn write_png(path: &Path, w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 3]) {
    let img = image::RgbImage::from_fn(w, h, |x, y| image::Rgb(f(x, y)));
    img.save(path).unwrap();
}

#[test]
fn constant_scale_and_mix_textures() {
    let dir = Path::new("");
    let t = reflectance(
        "Texture \"c\" \"spectrum\" \"constant\" \"rgb value\" [0.2 0.4 0.6]\nMaterial \"diffuse\" \"texture reflectance\" \"c\"",
        dir,
    );
    assert_eq!(t, Texture::Constant(Rgb::new(0.2, 0.4, 0.6)));
    let t = reflectance(
        "Texture \"half\" \"float\" \"constant\" \"float value\" 0.5\n\
         Texture \"s\" \"spectrum\" \"scale\" \"rgb tex\" [0.2 0.4 0.6] \"texture scale\" \"half\"\n\
         Material \"diffuse\" \"texture reflectance\" \"s\"",
        dir,
    );
    assert_eq!(t, Texture::Constant(Rgb::new(0.1, 0.2, 0.3)), "constant products fold");
    let t = reflectance(
        "Texture \"board\" \"float\" \"checkerboard\" \"float uscale\" 2 \"float vscale\" 2\n\
         Texture \"m\" \"spectrum\" \"mix\" \"rgb tex1\" [0 0 0] \"rgb tex2\" [1 0.5 0.25] \"texture amount\" \"board\"\n\
         Material \"diffuse\" \"texture reflectance\" \"m\"",
        dir,
    );
    // The board is 1 (tex1 default) on even squares: the mix gives tex2 there.
    assert_eq!(t.evaluate(&at((0.1, 0.1))), Rgb::new(1.0, 0.5, 0.25));
    assert_eq!(t.evaluate(&at((0.6, 0.1))), Rgb::BLACK);
}

#[test]
fn checkerboard_with_texture_inputs_and_mappings() {
    let dir = Path::new("");
    let t = reflectance(
        "Texture \"a\" \"spectrum\" \"constant\" \"rgb value\" [0.9 0.9 0.9]\n\
         Texture \"c\" \"spectrum\" \"checkerboard\" \"texture tex1\" \"a\" \"rgb tex2\" [0.1 0.2 0.3] \"float uscale\" 4 \"float vscale\" 4 \"float udelta\" 0.5\n\
         Material \"diffuse\" \"texture reflectance\" \"c\"",
        dir,
    );
    let Texture::Checkerboard(board) = &t else {
        panic!("{t:?}")
    };
    assert_eq!(
        board.mapping,
        TextureMapping::Uv {
            su: 4.0,
            sv: 4.0,
            du: 0.5,
            dv: 0.0
        }
    );
    assert_eq!(t.evaluate(&at((0.05, 0.05))), Rgb::splat(0.9)); // (0.7, 0.2)
    assert_eq!(t.evaluate(&at((0.2, 0.05))), Rgb::new(0.1, 0.2, 0.3)); // (1.3, 0.2)
    let t = reflectance(
        "Translate 0 0 1\nTexture \"c\" \"spectrum\" \"checkerboard\" \"string mapping\" \"planar\" \"vector3 v1\" [1 0 0] \"vector3 v2\" [0 0 1]\n\
         Material \"diffuse\" \"texture reflectance\" \"c\"",
        dir,
    );
    let Texture::Checkerboard(board) = &t else {
        panic!("{t:?}")
    };
    assert!(matches!(board.mapping, TextureMapping::Planar { .. }));
    // The texture space is the CTM's: world z = 1.5 is texture z = 0.5 -> t = 0.5.
    let ctx = |x: f32, z: f32| TextureContext {
        p: mcrender_core::math::Vec3::new(x, 7.0, z),
        ..TextureContext::default()
    };
    assert_eq!(t.evaluate(&ctx(0.5, 1.5)), Rgb::WHITE);
    assert_eq!(t.evaluate(&ctx(0.5, 2.5)), Rgb::BLACK);
    for mapping in ["spherical", "cylindrical"] {
        let t = reflectance(
            &format!("Texture \"c\" \"spectrum\" \"checkerboard\" \"string mapping\" \"{mapping}\"\nMaterial \"diffuse\" \"texture reflectance\" \"c\""),
            dir,
        );
        assert!(matches!(t, Texture::Checkerboard(_)));
    }
}

#[test]
fn imagemap_reads_decodes_and_shares_images() {
    let tmp = tempfile::tempdir().unwrap();
    // 2x2: top row (255, 0, 128), (64, 64, 64); bottom row black, white.
    write_png(&tmp.path().join("tex.png"), 2, 2, |x, y| match (x, y) {
        (0, 0) => [255, 0, 128],
        (1, 0) => [64, 64, 64],
        (0, 1) => [0, 0, 0],
        _ => [255, 255, 255],
    });
    let s = load(
        "Texture \"a\" \"spectrum\" \"imagemap\" \"string filename\" \"tex.png\" \"string filter\" \"point\"\n\
         Texture \"b\" \"spectrum\" \"imagemap\" \"string filename\" \"tex.png\" \"string encoding\" \"linear\" \"string wrap\" \"clamp\" \"float scale\" 0.5\n\
         Texture \"c\" \"spectrum\" \"imagemap\" \"string filename\" \"tex.png\" \"string encoding\" \"gamma 2\" \"bool invert\" true \"string filter\" \"ewa\"\n\
         Texture \"d\" \"spectrum\" \"imagemap\" \"string filename\" \"tex.png\" \"string filter\" \"trilinear\" \"float maxanisotropy\" 4\n\
         Texture \"f\" \"float\" \"imagemap\" \"string filename\" \"tex.png\" \"string filter\" \"point\"\n\
         Material \"conductor\" \"texture reflectance\" \"a\" \"texture roughness\" \"f\"",
        tmp.path(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(s.warnings.iter().all(|w| !w.contains("Texture")), "{:?}", s.warnings);
    let d = s.description;
    let MaterialDesc::Conductor(ConductorMaterial {
        reflectance: Some(Texture::Image(a)),
        u_roughness: Texture::Image(f),
        ..
    }) = &d.materials[d.shapes[0].material as usize]
    else {
        panic!("{:?}", d.materials)
    };
    assert_eq!(a.filter.filter, MipFilter::Point);
    assert_eq!(a.mipmap.wrap(), WrapMode::Repeat);
    // sRGB decode of 8-bit values; uv (0.25, 0.75) is the top-left texel (t is flipped).
    let top_left: Rgb = Texture::Image(a.clone()).evaluate(&at((0.25, 0.75)));
    let expected = Rgb::new(1.0, 0.0, srgb_to_linear(128.0 / 255.0));
    assert!((0..3).all(|c| (top_left[c] - expected[c]).abs() < 1e-6), "{top_left:?}");
    assert!((srgb_to_linear(128.0 / 255.0) - 0.2158605).abs() < 1e-6);
    let grey: Rgb = Texture::Image(a.clone()).evaluate(&at((0.75, 0.75)));
    assert!((grey.g - srgb_to_linear(64.0 / 255.0)).abs() < 1e-6, "{grey:?}");
    // The float texture reads the red channel, and shares the pyramid of "a".
    assert_eq!(Texture::<f32>::Image(f.clone()).evaluate(&at((0.25, 0.75))), 1.0);
    assert!(std::sync::Arc::ptr_eq(&a.mipmap, &f.mipmap));
}

#[test]
fn imagemap_encoding_scale_and_invert() {
    let tmp = tempfile::tempdir().unwrap();
    write_png(&tmp.path().join("grey.png"), 1, 1, |_, _| [128, 128, 128]);
    let v = |params: &str| {
        reflectance(
            &format!("Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"grey.png\" {params}\nMaterial \"diffuse\" \"texture reflectance\" \"t\""),
            tmp.path(),
        )
        .evaluate(&at((0.5, 0.5)))
        .r
    };
    let x = 128.0f32 / 255.0;
    let close = |a: f32, b: f32| (a - b).abs() < 1e-6;
    assert!(close(v(""), srgb_to_linear(x)));
    assert!(close(v("\"string encoding\" \"sRGB\""), srgb_to_linear(x)));
    assert!(close(v("\"string encoding\" \"linear\""), x));
    assert!(close(v("\"string encoding\" \"gamma 2.2\""), x.powf(2.2)));
    assert!(close(v("\"string encoding\" \"linear\" \"float scale\" 0.5"), 0.5 * x));
    assert!(close(v("\"string encoding\" \"linear\" \"bool invert\" true"), 1.0 - x));
}

#[test]
fn texture_errors_say_where_and_what() {
    let tmp = tempfile::tempdir().unwrap();
    write_png(&tmp.path().join("ok.png"), 1, 1, |_, _| [1, 2, 3]);
    let dir = tmp.path();
    let cases: &[(&str, SceneErrorKind, &str)] = &[
        (
            "Material \"diffuse\" \"texture reflectance\" \"nope\"",
            SceneErrorKind::Invalid,
            "scene.pbrt:2:20: \"texture reflectance\" of Material \"diffuse\" refers to texture \"nope\", which is not defined (define it with Texture \"nope\" \"spectrum\" ... first)",
        ),
        (
            "Texture \"f\" \"float\" \"constant\"\nMaterial \"diffuse\" \"texture reflectance\" \"f\"",
            SceneErrorKind::Invalid,
            "scene.pbrt:3:20: \"texture reflectance\" of Material \"diffuse\" needs a spectrum texture, but texture \"f\" is a float texture",
        ),
        (
            "Texture \"s\" \"spectrum\" \"constant\"\nMaterial \"conductor\" \"texture roughness\" \"s\"",
            SceneErrorKind::Invalid,
            "scene.pbrt:3:22: \"texture roughness\" of Material \"conductor\" needs a float texture, but texture \"s\" is a spectrum texture",
        ),
        (
            "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"missing.png\"",
            SceneErrorKind::Io,
            "scene.pbrt:2:35: cannot open image \"missing.png\": No such file or directory",
        ),
        (
            "Texture \"t\" \"spectrum\" \"imagemap\"",
            SceneErrorKind::Syntax,
            "scene.pbrt:2:24: Texture \"t\" (\"imagemap\") needs a \"string filename\" parameter",
        ),
        (
            "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"ok.png\" \"string filter\" \"gaussian\"",
            SceneErrorKind::Syntax,
            "scene.pbrt:2:62: unknown filter \"gaussian\" of Texture \"t\" (\"imagemap\") (expected point, bilinear, trilinear or ewa)",
        ),
        (
            "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"ok.png\" \"string wrap\" \"mirror\"",
            SceneErrorKind::Syntax,
            "scene.pbrt:2:62: unknown wrap mode \"mirror\" of Texture \"t\" (\"imagemap\") (expected repeat, black, clamp or octahedralsphere)",
        ),
        (
            "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"ok.png\" \"string encoding\" \"gamma x\"",
            SceneErrorKind::Syntax,
            "scene.pbrt:2:62: unknown encoding \"gamma x\" of Texture \"t\" (\"imagemap\") (expected sRGB, linear or \"gamma <value>\")",
        ),
        (
            "Texture \"t\" \"color\" \"constant\"",
            SceneErrorKind::Syntax,
            "scene.pbrt:2:13: texture type \"color\" of Texture \"t\": expected \"float\" or \"spectrum\"",
        ),
        (
            "Texture \"t\" \"float\" \"wood\"",
            SceneErrorKind::Syntax,
            "scene.pbrt:2:21: unknown texture class \"wood\" of Texture \"t\" (expected constant, scale, mix, checkerboard or imagemap)",
        ),
        (
            "Texture \"t\" \"float\" \"checkerboard\" \"string mapping\" \"cubic\"",
            SceneErrorKind::Syntax,
            "scene.pbrt:2:36: unknown texture mapping \"cubic\" of Texture \"t\" (\"checkerboard\") (expected uv, spherical, cylindrical or planar)",
        ),
        (
            "Texture \"t\" \"float\" \"checkerboard\" \"integer dimension\" 3",
            SceneErrorKind::Unsupported,
            "scene.pbrt:2:36: 3-D checkerboard textures (\"dimension\" 3) are not supported yet",
        ),
        (
            "Texture \"t\" \"float\" \"constant\"\nTexture \"t\" \"float\" \"constant\"",
            SceneErrorKind::Invalid,
            "scene.pbrt:3:21: float texture \"t\" is already defined at scene.pbrt:2:21",
        ),
        (
            "Texture \"t\" \"float\" \"constant\"\nMaterial \"dielectric\" \"texture eta\" \"t\"",
            SceneErrorKind::Unsupported,
            "scene.pbrt:3:23: \"texture eta\" of Material \"dielectric\": a dielectric's index of refraction cannot be a texture (as in pbrt-v4); give a float or a named glass",
        ),
    ];
    for (body, kind, message) in cases {
        let (k, m) = error(body, dir);
        let m = m.replace(&format!("{}/", dir.display()), "");
        assert_eq!((&k, m.as_str()), (kind, *message), "{body}");
    }
    // A texture may be defined before the world block? No: pbrt only allows it inside.
    let e = load_str("Texture \"t\" \"float\" \"constant\"\nWorldBegin", "scene.pbrt", dir).unwrap_err();
    assert!(e.to_string().starts_with("scene.pbrt:1:"), "{e}");
}

#[test]
fn displacement_becomes_a_bump_map_and_normalmap_a_normal_map() {
    let s = load(
        "Texture \"b\" \"float\" \"constant\" \"float value\" 0.25\nMaterial \"diffuse\" \"texture displacement\" \"b\"",
        Path::new(""),
    )
    .unwrap();
    assert!(!s.warnings.iter().any(|w| w.contains("ignored")), "{:?}", s.warnings);
    let d = &s.description;
    let MaterialDesc::BumpMap(BumpMapMaterial {
        material,
        height: BumpHeight::Pbrt { displacement },
    }) = &d.materials[d.shapes[0].material as usize]
    else {
        panic!("{:?}", d.materials)
    };
    assert_eq!(displacement, &Texture::Constant(0.25));
    assert!(matches!(d.materials[*material as usize], MaterialDesc::Diffuse(_)));

    // The normal map is read linearly (128 -> 128/255, no sRGB curve), row 0 at v = 1.
    let tmp = tempfile::tempdir().unwrap();
    write_png(&tmp.path().join("n.png"), 2, 2, |_, y| {
        if y == 0 {
            [128, 128, 255]
        } else {
            [255, 128, 128]
        }
    });
    let s = load("Material \"conductor\" \"string normalmap\" \"n.png\"", tmp.path()).unwrap();
    assert!(!s.warnings.iter().any(|w| w.contains("ignored")), "{:?}", s.warnings);
    let d = &s.description;
    let MaterialDesc::NormalMap(NormalMapMaterial { material, normal_map }) =
        &d.materials[d.shapes[0].material as usize]
    else {
        panic!("{:?}", d.materials)
    };
    assert!(matches!(d.materials[*material as usize], MaterialDesc::Conductor(_)));
    let c = 128.0 / 255.0;
    let texel = normal_map.evaluate(&at((0.25, 0.75)));
    assert!((texel - Rgb::new(c, c, 1.0)).max_component().abs() < 1e-6, "{texel:?}");
    let texel = normal_map.evaluate(&at((0.25, 0.25)));
    assert!((texel - Rgb::new(1.0, c, c)).max_component().abs() < 1e-6, "{texel:?}");

    // Both: the displacement wins, the normal map is warned about.
    let s = load(
        "Material \"diffuse\" \"float displacement\" 0.1 \"string normalmap\" \"n.png\"",
        tmp.path(),
    )
    .unwrap();
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("normalmap") && w.contains("ignored")),
        "{:?}",
        s.warnings
    );
    let d = &s.description;
    assert!(matches!(
        d.materials[d.shapes[0].material as usize],
        MaterialDesc::BumpMap(_)
    ));
    // A missing image is an error with its position.
    let (_, e) = error("Material \"diffuse\" \"string normalmap\" \"missing.png\"", tmp.path());
    assert!(e.starts_with("scene.pbrt:2:") && e.contains("missing.png"), "{e}");
}

#[test]
fn a_textured_plane_under_a_uniform_sky_has_the_mean_of_its_texture() {
    let tmp = tempfile::tempdir().unwrap();
    let value = |x: u32, y: u32| [(x * 37 + y * 11) as u8 % 255, (x * y * 5) as u8, 200 - (y * 23) as u8];
    write_png(&tmp.path().join("tex.png"), 8, 8, value);
    let mut mean = [0.0f64; 3];
    for y in 0..8 {
        for x in 0..8 {
            for (c, v) in value(x, y).iter().enumerate() {
                mean[c] += f64::from(srgb_to_linear(f32::from(*v) / 255.0)) / 64.0;
            }
        }
    }
    // A unit-radiance sky over a diffuse plane gives radiance = reflectance. The 90 degree
    // view of the plane at distance 1 spans exactly its uv square; the box pixel filter
    // keeps samples inside the image, so the image mean is the mean of the bilinearly
    // interpolated, repeating texture: the mean of its texels.
    let src = "LookAt 0 0 0  0 0 1  0 1 0\n\
        Camera \"perspective\" \"float fov\" 90\n\
        Film \"rgb\" \"integer xresolution\" 32 \"integer yresolution\" 32\n\
        PixelFilter \"box\"\n\
        Sampler \"independent\" \"integer pixelsamples\" 64\n\
        Integrator \"path\" \"integer maxdepth\" 1\n\
        WorldBegin\n\
        LightSource \"infinite\" \"rgb L\" [1 1 1]\n\
        Texture \"img\" \"spectrum\" \"imagemap\" \"string filename\" \"tex.png\"\n\
        Material \"diffuse\" \"texture reflectance\" \"img\"\n\
        Shape \"trianglemesh\" \"point3 P\" [-1 -1 1  1 -1 1  1 1 1  -1 1 1] \"integer indices\" [0 1 2 0 2 3] \"point2 uv\" [1 0  0 0  0 1  1 1]\n";
    let s = load_str(src, "scene.pbrt", tmp.path()).unwrap_or_else(|e| panic!("{e}"));
    let scene = Scene::build(&s.description).unwrap();
    let out = render(&scene, &RenderOptions::default(), &|_, _| {}).unwrap();
    let pixels = out.film.pixels();
    let n = pixels.len() as f64;
    for (c, texture_mean) in mean.iter().enumerate() {
        let m = pixels.iter().map(|p| f64::from(p.mean()[c])).sum::<f64>() / n;
        let var = pixels.iter().map(|p| f64::from(p.variance_of_mean()[c])).sum::<f64>() / (n * n);
        let se = var.sqrt();
        eprintln!("channel {c}: mean {m:.5}, texture mean {texture_mean:.5}, standard error {se:.1e}");
        assert!(
            (m - texture_mean).abs() < 4.0 * se + 1e-4,
            "channel {c}: {m} vs {texture_mean}"
        );
    }
}

/// Mean over pixels of the variance of the red pixel estimate.
fn mean_pixel_variance(src: &str) -> f64 {
    let s = load_str(src, "scene.pbrt", Path::new("")).unwrap_or_else(|e| panic!("{e}"));
    let scene = Scene::build(&s.description).unwrap();
    let out = render(&scene, &RenderOptions::default(), &|_, _| {}).unwrap();
    let pixels = out.film.pixels();
    pixels.iter().map(|p| f64::from(p.variance_of_mean().r)).sum::<f64>() / pixels.len() as f64
}

#[test]
fn pixel_footprints_filter_a_checkerboard_finer_than_the_pixels() {
    // 16 x 16 pixels over a plane with 256 x 256 checks: 16 per pixel. Filtered over the
    // pixel footprint, every sample sees about the mean reflectance 0.5, so pixels are
    // as quiet as on a constant grey plane; point sampling would make each sample 0 or 1.
    let scene = |material: &str| {
        format!(
            "LookAt 0 0 0  0 0 1  0 1 0\nCamera \"perspective\" \"float fov\" 90\n\
             Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\n\
             Sampler \"independent\" \"integer pixelsamples\" 16\nIntegrator \"path\" \"integer maxdepth\" 1\n\
             WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n\
             Texture \"cb\" \"spectrum\" \"checkerboard\" \"float uscale\" 256 \"float vscale\" 256 \"rgb tex2\" [0 0 0]\n\
             {material}\n\
             Shape \"trianglemesh\" \"point3 P\" [-1 -1 1  1 -1 1  1 1 1  -1 1 1] \"integer indices\" [0 1 2 0 2 3] \"point2 uv\" [1 0  0 0  0 1  1 1]\n"
        )
    };
    let grey = mean_pixel_variance(&scene("Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]"));
    let checks = mean_pixel_variance(&scene("Material \"diffuse\" \"texture reflectance\" \"cb\""));
    eprintln!("mean pixel variance: grey {grey:.3e}, filtered checks {checks:.3e}");
    assert!(checks < 1.5 * grey + 1e-6, "grey {grey:.3e}, checks {checks:.3e}");
}

#[test]
fn a_normal_map_tilts_the_cosine_of_a_diffuse_plane_under_a_distant_light() {
    // The light arrives along the view axis, perpendicular to the plane; a constant
    // normal map tilts the shading normal by theta, so every pixel is (R / pi) L cos theta
    // with cos theta the normalised map's z (a direct light on a diffuse: no noise).
    let tmp = tempfile::tempdir().unwrap();
    let rgb = [210u8, 128, 225];
    write_png(&tmp.path().join("n.png"), 2, 2, |_, _| rgb);
    let n = rgb.map(|v| 2.0 * f64::from(v) / 255.0 - 1.0);
    let cos = n[2] / (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    assert!(cos < 0.8, "a real tilt: {cos}");
    let scene = |normalmap: &str| {
        format!(
            "LookAt 0 0 0  0 0 1  0 1 0\n\
             Camera \"perspective\" \"float fov\" 60\n\
             Film \"rgb\" \"integer xresolution\" 16 \"integer yresolution\" 16\n\
             Sampler \"independent\" \"integer pixelsamples\" 4\n\
             Integrator \"path\" \"integer maxdepth\" 1\n\
             WorldBegin\n\
             LightSource \"distant\" \"point3 from\" [0 0 0] \"point3 to\" [0 0 1] \"rgb L\" [1 1 1]\n\
             Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5] {normalmap}\n\
             Shape \"trianglemesh\" \"point3 P\" [-3 -3 1  3 -3 1  3 3 1  -3 3 1] \"integer indices\" [0 1 2 0 2 3] \"point2 uv\" [1 0  0 0  0 1  1 1]\n"
        )
    };
    let mean = |src: &str| {
        let s = load_str(src, "scene.pbrt", tmp.path()).unwrap_or_else(|e| panic!("{e}"));
        let out = render(
            &Scene::build(&s.description).unwrap(),
            &RenderOptions::default(),
            &|_, _| {},
        )
        .unwrap();
        let pixels = out.film.pixels();
        pixels.iter().map(|p| f64::from(p.mean().g)).sum::<f64>() / pixels.len() as f64
    };
    let flat = mean(&scene(""));
    let expected = 0.5 / std::f64::consts::PI;
    assert!((flat - expected).abs() < 1e-3 * expected, "{flat} vs {expected}");
    let tilted = mean(&scene("\"string normalmap\" \"n.png\""));
    assert!(
        (tilted - expected * cos).abs() < 1e-3 * expected,
        "{tilted} vs {}",
        expected * cos
    );
}
