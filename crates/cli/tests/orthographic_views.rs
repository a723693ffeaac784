//! One orthographic view described twice, as a Mitsuba 3 `orthographic` sensor (window
//! sized by `to_world`'s scale, `near_clip`) and as a pbrt-v4 `Camera "orthographic"`
//! (`screenwindow`, with pbrt's `Scale -1 1 1` for Mitsuba's mirrored image x): the two
//! cameras trace the same rays, and the scenes render to the same image within noise
//! (every pixel's difference in units of its standard error from both renders' sample
//! variances, and the image means). A mirrored or 5% brighter image fails (checked here).

use std::path::Path;

mod common;

use mcrender_core::color::Rgb;
use mcrender_core::math::Vec2;
use mcrender_core::render::{render, RenderOptions};
use mcrender_core::scene::{SamplerKind, Scene, SceneDescription};
use mcrender_formats::load;

use common::agreement::agreement;

const W: u32 = 48;
const H: u32 = 32;

const MITSUBA: &str = r#"<scene version="3.0.0">
  <integrator type="path"><integer name="max_depth" value="3"/></integrator>
  <sensor type="orthographic">
    <float name="near_clip" value="0.5"/>
    <transform name="to_world">
      <scale x="2" y="2"/>
      <lookat origin="1, -3, 4" target="0, 0, 0" up="0, 0, 1"/>
    </transform>
    <film type="hdrfilm">
      <integer name="width" value="48"/><integer name="height" value="32"/>
      <rfilter type="box"/>
    </film>
    <sampler type="independent"><integer name="sample_count" value="64"/></sampler>
  </sensor>
  <shape type="rectangle">
    <transform name="to_world"><scale value="3"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.6, 0.6"/></bsdf>
  </shape>
  <shape type="sphere">
    <point name="center" x="1" y="0.5" z="0.7"/>
    <float name="radius" value="0.7"/>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.2, 0.1"/></bsdf>
  </shape>
  <emitter type="point">
    <point name="position" x="-1.5" y="-1" z="3"/>
    <rgb name="intensity" value="20, 18, 15"/>
  </emitter>
</scene>
"#;

// Mitsuba's window [-1, 1] x [-1/aspect, 1/aspect] scaled by 2 (aspect 3/2); its
// max_depth 3 (up to 3 segments, the last reaching a light) is pbrt's maxdepth 2.
const PBRT: &str = r#"Scale -1 1 1
LookAt 1 -3 4  0 0 0  0 0 1
Camera "orthographic" "float screenwindow" [-2 2 -1.3333333 1.3333333]
Film "rgb" "integer xresolution" 48 "integer yresolution" 32
PixelFilter "box"
Sampler "independent" "integer pixelsamples" 64
Integrator "volpath" "integer maxdepth" 2
WorldBegin
LightSource "point" "point3 from" [-1.5 -1 3] "rgb I" [20 18 15]
AttributeBegin
  Material "diffuse" "rgb reflectance" [0.6 0.6 0.6]
  Shape "bilinearmesh" "point3 P" [-3 -3 0  3 -3 0  -3 3 0  3 3 0]
AttributeEnd
AttributeBegin
  Material "diffuse" "rgb reflectance" [0.8 0.2 0.1]
  Translate 1 0.5 0.7
  Shape "sphere" "float radius" 0.7
AttributeEnd
"#;

fn load_text(dir: &Path, name: &str, text: &str) -> SceneDescription {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    match load(&path) {
        Ok(s) => s.description,
        Err(e) => panic!("{e}"),
    }
}

/// Mean image and per-pixel variance of the mean.
fn render_desc(mut desc: SceneDescription, seed: u64) -> (Vec<Rgb>, Vec<Rgb>) {
    desc.sampler.kind = SamplerKind::Independent;
    desc.sampler.seed = seed;
    let scene = Scene::build(&desc).expect("builds");
    let out = render(&scene, &RenderOptions::default(), &|_, _| {}).expect("renders");
    assert_eq!(out.stats.nonfinite_samples, 0);
    (out.film.mean_image(), out.film.variance_image())
}

#[test]
fn mitsuba_and_pbrt_orthographic_views_agree() {
    let dir = tempfile::tempdir().unwrap();
    let m = load_text(dir.path(), "view.xml", MITSUBA);
    let p = load_text(dir.path(), "view.pbrt", PBRT);

    // The same rays, Mitsuba's starting 0.5 further along (its near clip).
    let (cm, cp) = (
        Scene::build(&m).expect("builds").camera,
        Scene::build(&p).expect("builds").camera,
    );
    for (x, y) in [(0.0, 0.0), (48.0, 0.0), (12.5, 30.0), (24.0, 16.0)] {
        let (rm, rp) = (
            cm.generate_ray(Vec2::new(x, y), Vec2::ZERO),
            cp.generate_ray(Vec2::new(x, y), Vec2::ZERO),
        );
        assert!((rm.d - rp.d).length() < 1e-5, "({x}, {y}): {} vs {}", rm.d, rp.d);
        assert!(
            (rm.o - (rp.o + rp.d * 0.5)).length() < 1e-4,
            "({x}, {y}): {} vs {}",
            rm.o,
            rp.o
        );
    }

    let (im, ip) = (render_desc(m, 1), render_desc(p, 2));
    let a = agreement(&im, &ip, 1.0);
    let (fraction, mean_z) = (a.within, a.max_mean_z);
    eprintln!(
        "orthographic view, Mitsuba vs pbrt: {:.2}% of channels within 3.29 sigma, image-mean z {mean_z:.2}",
        fraction * 100.0
    );
    assert!(fraction > 0.99, "only {:.2}% of pixel channels agree", fraction * 100.0);
    assert!(mean_z < 4.0, "image means differ by {mean_z:.2} standard errors");
    // The comparison can fail: 5% brighter, or mirrored left to right.
    let scaled_z = agreement(&im, &ip, 1.05).max_mean_z;
    assert!(scaled_z > 4.0, "a 5% brightness error went unnoticed (z {scaled_z:.2})");
    let mirror = |v: &Vec<Rgb>| -> Vec<Rgb> {
        (0..(W * H) as usize)
            .map(|i| v[i - i % W as usize + (W as usize - 1 - i % W as usize)])
            .collect()
    };
    let mirrored = agreement(&(mirror(&im.0), mirror(&im.1)), &ip, 1.0).within;
    eprintln!("mirrored: {:.2}% of channels agree", mirrored * 100.0);
    assert!(
        mirrored < 0.9,
        "a mirrored image went unnoticed ({:.2}% agree)",
        mirrored * 100.0
    );
}
