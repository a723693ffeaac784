//! The layering of `mcrender-core` (STYLE.md, "Rooms of core"): a module refers only to
//! modules of its own layer or below. This test reads every source file and fails on any
//! `crate::<module>` path (import, expression or doc link) that points upwards.

use std::path::{Path, PathBuf};

/// Each top-level module of `crates/core/src` and its layer.
const LAYERS: &[(&str, u32)] = &[
    ("math", 0),
    ("color", 0),
    ("bytes", 0),
    ("sampling", 1),
    ("shape", 2),
    ("accel", 2),
    ("bsdf", 2),
    ("camera", 2),
    ("film", 2),
    ("texture", 2),
    ("material", 3),
    ("light", 3),
    ("scene", 4),
    ("integrator", 5),
    ("render", 6),
    ("lab", 7),
];

fn layer(module: &str) -> Option<u32> {
    LAYERS.iter().find(|(m, _)| *m == module).map(|(_, l)| *l)
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The upward references in one file of module `own` at layer `own_layer`.
fn upward_references(text: &str, own: &str, own_layer: u32) -> Vec<String> {
    let mut found = Vec::new();
    for (n, line) in text.lines().enumerate() {
        for (i, _) in line.match_indices("crate::") {
            // `mcrender_core::` paths in doc examples are not `crate::` ones.
            if line[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_') {
                continue;
            }
            let rest = &line[i + "crate::".len()..];
            let target: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            if let Some(l) = layer(&target) {
                if l > own_layer {
                    found.push(format!(
                        "line {}: {own} (layer {own_layer}) -> {target} (layer {l})",
                        n + 1
                    ));
                }
            }
        }
    }
    found
}

#[test]
fn no_module_refers_to_a_higher_layer() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut violations = Vec::new();
    let mut checked = 0;
    for file in files {
        let relative = file.strip_prefix(&src).unwrap();
        let own = relative
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy()
            .trim_end_matches(".rs")
            .to_string();
        if own == "lib" {
            continue;
        }
        let own_layer = layer(&own).unwrap_or_else(|| panic!("module {own} has no layer in LAYERS: add it"));
        let text = std::fs::read_to_string(&file).unwrap();
        checked += 1;
        for v in upward_references(&text, &own, own_layer) {
            violations.push(format!("{}: {v}", relative.display()));
        }
    }
    assert!(checked > 100, "only {checked} files found under {}", src.display());
    assert!(violations.is_empty(), "upward references:\n{}", violations.join("\n"));
}

#[test]
fn an_upward_reference_is_seen() {
    let text = "use crate::math::Vec3;\nuse crate::scene::MaterialDesc;\n/// see [`crate::integrator::X`]\n";
    let found = upward_references(text, "material", 3);
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(found[0].starts_with("line 2: material (layer 3) -> scene"));
    assert!(upward_references("mcrender_core::scene::Scene", "math", 0).is_empty());
}
