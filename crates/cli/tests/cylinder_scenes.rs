//! A scene with cylinders (a diffuse post and a horizontal emitting tube over a floor) in
//! its Mitsuba 3 and pbrt-v4 descriptions renders to the same image within noise. The two
//! loaders place the cylinder differently (Mitsuba's `p0`/`p1`/`radius` frame with its
//! mirrored height axis, pbrt's `zmin`/`zmax` under the CTM), so this checks that they
//! describe the same surface, normals and emission. Differences are measured per pixel in
//! units of the standard error from both renders' own sample variances, and for the image
//! means; a 5% brightness error fails (checked in the test itself).

use mcrender_core::color::Rgb;
use mcrender_core::render::{render, RenderOptions};
use mcrender_core::scene::{SamplerKind, Scene};
use mcrender_formats::load;

mod common;

use common::agreement::agreement;

const SIZE: u32 = 48;
const SPP: u32 = 128;

const MITSUBA: &str = r#"<scene version="3.0.0">
  <integrator type="path"><integer name="max_depth" value="5"/></integrator>
  <sensor type="perspective">
    <float name="fov" value="45"/>
    <transform name="to_world"><lookat origin="0, 5, 2" target="0, 0, 0.8" up="0, 0, 1"/></transform>
    <film type="hdrfilm"><integer name="width" value="48"/><integer name="height" value="48"/><rfilter type="box"/></film>
    <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
  </sensor>
  <bsdf type="twosided" id="grey"><bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.5, 0.5"/></bsdf></bsdf>
  <bsdf type="twosided" id="warm"><bsdf type="diffuse"><rgb name="reflectance" value="0.7, 0.4, 0.2"/></bsdf></bsdf>
  <shape type="rectangle">
    <transform name="to_world"><scale value="3"/></transform>
    <ref id="grey"/>
  </shape>
  <shape type="cylinder">
    <point name="p0" x="0.6" y="0" z="0"/><point name="p1" x="0.6" y="0" z="1.2"/>
    <float name="radius" value="0.35"/>
    <ref id="warm"/>
  </shape>
  <shape type="cylinder">
    <point name="p0" x="-1.5" y="-1" z="1.6"/><point name="p1" x="1.5" y="-1" z="1.6"/>
    <float name="radius" value="0.15"/>
    <ref id="grey"/>
    <emitter type="area"><rgb name="radiance" value="5, 5, 5"/></emitter>
  </shape>
</scene>
"#;

const PBRT: &str = r#"Integrator "path" "integer maxdepth" [ 4 ]
Scale -1 1 1
LookAt 0 5 2  0 0 0.8  0 0 1
Camera "perspective" "float fov" [ 45 ]
Film "rgb" "integer xresolution" [ 48 ] "integer yresolution" [ 48 ]
PixelFilter "box"
Sampler "independent" "integer pixelsamples" [ 16 ]
WorldBegin
Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]
Shape "trianglemesh" "point3 P" [ -3 -3 0  3 -3 0  3 3 0  -3 3 0 ] "integer indices" [ 0 1 2 0 2 3 ]
AttributeBegin
  Material "diffuse" "rgb reflectance" [ 0.7 0.4 0.2 ]
  Translate 0.6 0 0
  Shape "cylinder" "float radius" 0.35 "float zmin" 0 "float zmax" 1.2
AttributeEnd
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [ 5 5 5 ]
  Translate -1.5 -1 1.6
  Rotate 90 0 1 0
  Shape "cylinder" "float radius" 0.15 "float zmin" 0 "float zmax" 3
AttributeEnd
"#;

/// Mean image and per-pixel variance of the mean of the scene file `name` holding `text`.
fn render_text(name: &str, text: &str, seed: u64) -> (Vec<Rgb>, Vec<Rgb>) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, text).unwrap();
    let mut desc = load(&path).expect("scene loads").description;
    desc.film.width = SIZE;
    desc.film.height = SIZE;
    desc.sampler.kind = SamplerKind::Independent;
    desc.sampler.samples_per_pixel = SPP;
    desc.sampler.seed = seed;
    let scene = Scene::build(&desc).expect("builds");
    let out = render(&scene, &RenderOptions::default(), &|_, _| {}).expect("renders");
    (out.film.mean_image(), out.film.variance_image())
}

#[test]
fn mitsuba_and_pbrt_cylinder_scenes_agree_within_noise() {
    let m = render_text("cylinders.xml", MITSUBA, 1);
    let p = render_text("cylinders.pbrt", PBRT, 2);
    let a = agreement(&m, &p, 1.0);
    let (fraction, mean_z, mean) = (a.within, a.max_mean_z, a.mean_a);
    eprintln!(
        "cylinders, Mitsuba vs pbrt description: {:.3}% of channels within 3.29 sigma, image-mean z {mean_z:.2}, mean {mean:.4}",
        fraction * 100.0
    );
    // Something is lit: the tube lights the floor and the post.
    assert!(mean > 0.02, "image mean {mean}");
    assert!(fraction > 0.99, "only {:.3}% of pixel channels agree", fraction * 100.0);
    assert!(mean_z < 4.0, "image means differ by {mean_z:.2} standard errors");
    let scaled_z = agreement(&m, &p, 1.05).max_mean_z;
    eprintln!("the same with the Mitsuba render 5% brighter: image-mean z {scaled_z:.2}");
    assert!(scaled_z > 4.0, "a 5% brightness error went unnoticed (z {scaled_z:.2})");
}
