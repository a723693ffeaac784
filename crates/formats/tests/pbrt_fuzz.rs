//! The loader never panics: every input gives `Ok` or `Err`. Fed with random bytes, token
//! soup, every truncation of the Cornell box, and random mutations of it.

use std::path::Path;

use mcrender_formats::pbrt::load_str;
use mcrender_formats::ply::read_ply_bytes;
use proptest::prelude::*;

const CORNELL: &str = include_str!("../../../scenes/cornell-box/scene-v4.pbrt");

fn load(src: &str) {
    // Ok or Err are both fine; a panic fails the test.
    let _ = load_str(src, "fuzz.pbrt", Path::new("/nonexistent-fuzz-dir"));
}

#[test]
fn every_truncation_of_the_cornell_box() {
    let boundaries: Vec<usize> = CORNELL.char_indices().map(|(i, _)| i).chain([CORNELL.len()]).collect();
    let mut ok = 0;
    for &end in &boundaries {
        if load_str(&CORNELL[..end], "fuzz.pbrt", Path::new("")).is_ok() {
            ok += 1;
        }
    }
    // Prefixes that end between complete directives after WorldBegin load fine.
    assert!(ok > 0);
}

const VOCABULARY: &[&str] = &[
    "WorldBegin",
    "AttributeBegin",
    "AttributeEnd",
    "TransformBegin",
    "TransformEnd",
    "Shape",
    "Material",
    "NamedMaterial",
    "MakeNamedMaterial",
    "LightSource",
    "AreaLightSource",
    "Camera",
    "Film",
    "Sampler",
    "Integrator",
    "PixelFilter",
    "Translate",
    "Scale",
    "Rotate",
    "LookAt",
    "Transform",
    "ConcatTransform",
    "Identity",
    "ReverseOrientation",
    "CoordinateSystem",
    "CoordSysTransform",
    "Include",
    "Import",
    "Option",
    "Attribute",
    "ColorSpace",
    "Texture",
    "ObjectBegin",
    "MediumInterface",
    "\"sphere\"",
    "\"trianglemesh\"",
    "\"plymesh\"",
    "\"diffuse\"",
    "\"perspective\"",
    "\"rgb\"",
    "\"point\"",
    "\"float radius\"",
    "\"point3 P\"",
    "\"integer indices\"",
    "\"normal N\"",
    "\"point2 uv\"",
    "\"rgb L\"",
    "\"rgb reflectance\"",
    "\"string type\"",
    "\"string filename\"",
    "\"integer xresolution\"",
    "\"bool twosided\"",
    "\"float fov\"",
    "\"shape\"",
    "\"seed\"",
    "\"camera\"",
    "[",
    "]",
    "0",
    "1",
    "-1",
    "2.5",
    "1e30",
    "-1e30",
    "3",
    "0.0001",
    "true",
    "false",
    "nan",
    "inf",
    "#c\n",
    "\n",
    "\"",
    "\\",
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, failure_persistence: None, .. ProptestConfig::default() })]

    #[test]
    fn random_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
        load(&String::from_utf8_lossy(&bytes));
        let _ = read_ply_bytes(&bytes);
    }

    #[test]
    fn token_soup(words in proptest::collection::vec(0..VOCABULARY.len(), 0..80)) {
        let src: Vec<&str> = words.iter().map(|&i| VOCABULARY[i]).collect();
        load(&src.join(" "));
    }

    #[test]
    fn mutated_cornell_box(edits in proptest::collection::vec((0..CORNELL.len(), 0..VOCABULARY.len()), 1..6)) {
        let mut src = CORNELL.to_string();
        for (at, word) in edits {
            let mut at = at.min(src.len());
            while !src.is_char_boundary(at) {
                at -= 1;
            }
            let end = (at + 3).min(src.len());
            let end = (end..=src.len()).find(|&e| src.is_char_boundary(e)).unwrap_or(src.len());
            src.replace_range(at..end, VOCABULARY[word]);
        }
        load(&src);
    }

    #[test]
    fn ply_header_soup(lines in proptest::collection::vec(0..12usize, 0..12), tail in proptest::collection::vec(any::<u8>(), 0..64)) {
        const LINES: [&str; 12] = [
            "ply", "format ascii 1.0", "format binary_little_endian 1.0", "format binary_big_endian 1.0",
            "element vertex 3", "element face 1", "property float x", "property float y", "property float z",
            "property list uchar int vertex_indices", "end_header", "element vertex 4294967296",
        ];
        let mut bytes: Vec<u8> = lines.iter().flat_map(|&i| format!("{}\n", LINES[i]).into_bytes()).collect();
        bytes.extend(tail);
        let _ = read_ply_bytes(&bytes);
    }
}
