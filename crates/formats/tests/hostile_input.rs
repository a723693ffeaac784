//! Regression tests for issue 10's loader bugs, each named after it.

use std::path::Path;
use std::time::{Duration, Instant};

use mcrender_core::color::Rgb;
use mcrender_formats::image_io::{write_images, ImageRgb};
use mcrender_formats::limits::LoadLimits;
use mcrender_formats::pbrt::{load_file, load_file_with, LoadOptions};

/// An uncompressed 24-bit TGA of `n` x `n` (a gradient, so it is not all one value).
fn write_tga(path: &Path, n: u16) {
    let mut bytes = vec![0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0];
    bytes.extend(n.to_le_bytes());
    bytes.extend(n.to_le_bytes());
    bytes.extend([24, 0]);
    let row: Vec<u8> = (0..usize::from(n) * 3).map(|i| (i * 7 % 256) as u8).collect();
    for _ in 0..n {
        bytes.extend(&row);
    }
    std::fs::write(path, bytes).unwrap();
}

/// A scene of `shapes` spheres all using an image texture from `image`.
fn write_scene(dir: &Path, image: &str, shapes: usize) -> std::path::PathBuf {
    let mut s = format!(
        "WorldBegin\nTexture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"{image}\"\nMaterial \"diffuse\" \"texture reflectance\" \"t\"\n"
    );
    for i in 0..shapes {
        s += &format!("Translate {i} 0 0 Shape \"sphere\" \"float radius\" [ 0.1 ]\n");
    }
    let path = dir.join("scene.pbrt");
    std::fs::write(&path, s).unwrap();
    path
}

#[test]
fn image_texture_key_is_not_built_over_every_texel() {
    // The material lookup key was format!("{desc:?}") over every texel, once per shape:
    // a 4096x4096 texture took 18 s and 3.6 GB to load.
    let dir = tempfile::tempdir().unwrap();
    write_tga(&dir.path().join("t.tga"), 4096);
    let path = write_scene(dir.path(), "t.tga", 50);
    let start = Instant::now();
    let scene = load_file(&path).unwrap();
    let took = start.elapsed();
    assert_eq!(
        scene.description.materials.len(),
        1,
        "one material shared by all shapes"
    );
    let debug = format!("{:?}", scene.description.materials);
    assert!(debug.len() < 10_000, "Debug of the materials is {} bytes", debug.len());
    assert!(debug.contains("4096x4096"), "{debug}");
    // About 2 s on 2 busy cores; the bug took 18 s.
    assert!(took < Duration::from_secs(12), "4096x4096 texture took {took:?}");
}

#[test]
fn image_texture_8192_is_refused_before_decoding_not_aborted() {
    let dir = tempfile::tempdir().unwrap();
    write_tga(&dir.path().join("t.tga"), 8192);
    let path = write_scene(dir.path(), "t.tga", 2);
    let options = LoadOptions {
        limits: LoadLimits { max_memory: 1 << 30 },
        ..LoadOptions::default()
    };
    let start = Instant::now();
    let err = load_file_with(&path, &options).unwrap_err().to_string();
    assert!(
        err.contains("scene.pbrt:2:") && err.contains("8192x8192") && err.contains("memory limit of 1.0 GiB"),
        "{err}"
    );
    // Refused from the header: no time spent decoding.
    assert!(start.elapsed() < Duration::from_secs(5), "{:?}", start.elapsed());
}

#[test]
fn failing_variance_output_leaves_the_main_image_behind_no_more() {
    let dir = tempfile::tempdir().unwrap();
    let main = dir.path().join("a.exr");
    let good = ImageRgb::new(2, 2);
    // The second image cannot be written (its pixel count is wrong): neither appears.
    let bad = ImageRgb {
        width: 3,
        height: 3,
        pixels: vec![Rgb::BLACK; 2],
    };
    let var = dir.path().join("v.exr");
    assert!(write_images(&[(&main, &good), (&var, &bad)]).is_err());
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().collect();
    assert!(left.is_empty(), "{left:?}");
    // A directory that vanished: the same.
    let gone = dir.path().join("gone/v.exr");
    assert!(write_images(&[(&main, &good), (&gone, &good)]).is_err());
    assert!(std::fs::read_dir(dir.path()).unwrap().next().is_none());
    // Both good: both written.
    write_images(&[(&main, &good), (&var, &good)]).unwrap();
    assert!(main.exists() && var.exists());
}

/// A Mitsuba scene (`scene.xml` in `dir`) with a bitmap texture from `texture` and an
/// envmap from `envmap`.
fn write_mitsuba_scene(dir: &Path, texture: &str, envmap: &str) -> std::path::PathBuf {
    let s = format!(
        r#"<scene version="3.0.0">
<emitter type="envmap"><string name="filename" value="{envmap}"/></emitter>
<shape type="sphere">
  <bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="{texture}"/></texture></bsdf>
</shape>
</scene>
"#
    );
    let path = dir.join("scene.xml");
    std::fs::write(&path, s).unwrap();
    path
}

/// The Mitsuba loader reported `image_bytes: 0` to the memory check: its bitmaps and
/// envmaps now count as the pbrt loader's do.
#[test]
fn mitsuba_images_are_counted_not_reported_as_zero_bytes() {
    use mcrender_formats::limits::{env_image_bytes, image_texture_bytes};
    let dir = tempfile::tempdir().unwrap();
    write_tga(&dir.path().join("t.tga"), 64);
    write_tga(&dir.path().join("e.tga"), 32);
    let path = write_mitsuba_scene(dir.path(), "t.tga", "e.tga");
    let loaded = mcrender_formats::load(&path).unwrap();
    assert_eq!(
        loaded.image_bytes,
        image_texture_bytes(64, 64) + env_image_bytes(32, 32)
    );
}

/// An 8192x8192 bitmap in a Mitsuba scene is refused from its header under the limit,
/// before it is decoded (the file here is only the header: decoding it would fail).
#[test]
fn mitsuba_texture_8192_is_refused_before_decoding() {
    let dir = tempfile::tempdir().unwrap();
    let mut header = vec![0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0];
    header.extend(8192u16.to_le_bytes());
    header.extend(8192u16.to_le_bytes());
    header.extend([24, 0]);
    std::fs::write(dir.path().join("big.tga"), header).unwrap();
    write_tga(&dir.path().join("e.tga"), 8);
    let path = write_mitsuba_scene(dir.path(), "big.tga", "e.tga");
    let options = mcrender_formats::LoadOptions {
        limits: LoadLimits { max_memory: 1 << 30 },
        ..mcrender_formats::LoadOptions::default()
    };
    let err = mcrender_formats::load_with(&path, &options).unwrap_err().to_string();
    assert!(
        err.contains("scene.xml:4:")
            && err.contains("\"big.tga\" (8192x8192)")
            && err.contains("memory limit of 1.0 GiB"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    // Without the limit it is read, and fails as the truncated file it is (not an abort).
    let err = mcrender_formats::load(&path).unwrap_err().to_string();
    assert!(err.contains("cannot read image \"big.tga\""), "{err}");
}

/// An OBJ scene whose material `m` has the diffuse texture `image`.
fn write_obj_scene(dir: &Path, image: &str) -> std::path::PathBuf {
    std::fs::write(dir.join("m.mtl"), format!("newmtl m\nKd 1 1 1\nmap_Kd {image}\n")).unwrap();
    let path = dir.join("scene.obj");
    std::fs::write(
        &path,
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n",
    )
    .unwrap();
    path
}

/// Regression: OBJ textures (`map_Kd`) were decoded without a look at the memory limit and
/// reported as 0 bytes to the command line's memory check. A 16384x16384 one is now
/// refused from its header (the file holds only that), with the figure and the limit; a
/// small one is counted.
#[test]
fn obj_texture_16384_is_refused_before_decoding_and_textures_are_counted() {
    let dir = tempfile::tempdir().unwrap();
    let mut header = vec![0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0];
    header.extend(16384u16.to_le_bytes());
    header.extend(16384u16.to_le_bytes());
    header.extend([24, 0]);
    std::fs::write(dir.path().join("big.tga"), header).unwrap();
    let path = write_obj_scene(dir.path(), "big.tga");
    let options = mcrender_formats::LoadOptions {
        limits: LoadLimits { max_memory: 1 << 30 },
        ..mcrender_formats::LoadOptions::default()
    };
    let start = Instant::now();
    let err = mcrender_formats::load_with(&path, &options).unwrap_err().to_string();
    assert!(
        err.contains("big.tga\" (16384x16384)") && err.contains("memory limit of 1.0 GiB"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(start.elapsed() < Duration::from_secs(5), "{:?}", start.elapsed());
    // Without the limit it is read, and fails as the truncated file it is (not an abort).
    let err = mcrender_formats::load(&path).unwrap_err().to_string();
    assert!(err.contains("cannot read texture"), "{err}");

    write_tga(&dir.path().join("small.tga"), 16);
    let path = write_obj_scene(dir.path(), "small.tga");
    let loaded = mcrender_formats::load_with(&path, &options).unwrap();
    assert_eq!(
        loaded.image_bytes,
        mcrender_formats::limits::image_texture_bytes(16, 16)
    );
}
