//! Export the scene description mcrender loads from a pbrt-v4 file in a form that
//! `bench/mitsuba_scene.py` turns into a Mitsuba 3 scene: OBJ meshes in world space, sphere
//! and mesh emitters, diffuse and conductor materials, the camera. This lets an independent
//! renderer render exactly what our loader understood, separating loader questions from
//! light-transport questions.
//!
//! Usage: `cargo run --release --example export_mitsuba -- SCENE.pbrt OUT_DIR`
#![allow(missing_docs)]

use mcrender_core::material::{ConductorMaterial, DiffuseMaterial};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use mcrender_core::math::Vec3;
use mcrender_core::scene::{FloatTexture, GeometryDesc, MaterialDesc, RgbTexture};

fn material_json(m: &MaterialDesc) -> Result<String> {
    let rgb = |t: &RgbTexture| match t.constant() {
        Some(c) => Ok(c.to_array()),
        None => bail!("no Mitsuba export for textures yet"),
    };
    let float = |t: &FloatTexture| match t.constant() {
        Some(c) => Ok(c),
        None => bail!("no Mitsuba export for textures yet"),
    };
    Ok(match m {
        MaterialDesc::Diffuse(DiffuseMaterial { reflectance }) => {
            format!(r#"{{"type":"diffuse","reflectance":{:?}}}"#, rgb(reflectance)?)
        }
        MaterialDesc::Conductor(ConductorMaterial {
            eta,
            k,
            reflectance: None,
            u_roughness,
            v_roughness,
            remap_roughness,
            ..
        }) => {
            let alpha = |r: f32| if *remap_roughness { r.max(0.0).sqrt() } else { r };
            format!(
                r#"{{"type":"conductor","eta":{:?},"k":{:?},"alpha_u":{},"alpha_v":{}}}"#,
                rgb(eta)?,
                rgb(k)?,
                alpha(float(u_roughness)?),
                alpha(float(v_roughness)?)
            )
        }
        other => bail!("no Mitsuba export for {other:?} yet"),
    })
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let [_, scene, out] = &args[..] else {
        bail!("usage: export_mitsuba SCENE.pbrt OUT_DIR")
    };
    let loaded = mcrender_formats::pbrt::load_file(&PathBuf::from(scene)).map_err(anyhow::Error::new)?;
    let d = &loaded.description;
    let out = PathBuf::from(out);
    std::fs::create_dir_all(&out)?;
    let mut shapes = Vec::new();
    if !d.instances.is_empty() {
        bail!("object instances are not exported yet");
    }
    for (i, s) in d.shapes.iter().enumerate() {
        let material = material_json(&d.materials[s.material as usize])?;
        let emitter = s.area_light.map_or("null".to_string(), |a| {
            format!(
                r#"{{"radiance":{:?},"two_sided":{}}}"#,
                a.radiance.to_array(),
                a.two_sided
            )
        });
        let geometry = match &s.geometry {
            GeometryDesc::TriangleMesh(m) => {
                let path = out.join(format!("mesh{i}.obj"));
                let mut f = std::io::BufWriter::new(std::fs::File::create(&path)?);
                for p in &m.positions {
                    writeln!(f, "v {} {} {}", p.x, p.y, p.z)?;
                }
                for t in m.indices.chunks(3) {
                    writeln!(f, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1)?;
                }
                format!(r#""kind":"mesh","file":{:?}"#, path.display().to_string())
            }
            GeometryDesc::Sphere {
                radius,
                world_from_object,
                z_min,
                z_max,
                phi_max,
            } => {
                if *z_min > -radius || *z_max < *radius || *phi_max < 360.0 {
                    bail!("shape {i}: partial spheres are not exported yet");
                }
                let c = world_from_object.point(Vec3::ZERO);
                let scale = world_from_object.vector(Vec3::X).length();
                format!(
                    r#""kind":"sphere","center":{:?},"radius":{}"#,
                    c.to_array(),
                    scale * radius
                )
            }
            GeometryDesc::Disk { .. } => bail!("shape {i}: disks are not exported yet"),
            GeometryDesc::Cylinder { .. } => bail!("shape {i}: cylinders are not exported yet"),
            GeometryDesc::BilinearMesh(_) => bail!("shape {i}: bilinear patches are not exported yet"),
        };
        shapes.push(format!(r#"{{{geometry},"material":{material},"emitter":{emitter}}}"#));
    }
    let mut json = String::new();
    write!(
        json,
        r#"{{"width":{},"height":{},"fov":{},"max_depth":{},"world_from_camera":{:?},"shapes":[{}]}}"#,
        d.film.width,
        d.film.height,
        d.camera.fov_degrees,
        d.integrator.max_depth,
        d.camera.world_from_camera.m.to_cols_array(),
        shapes.join(",")
    )?;
    std::fs::write(out.join("scene.json"), json).context("cannot write scene.json")?;
    eprintln!("wrote {} shapes to {}", shapes.len(), out.display());
    Ok(())
}
