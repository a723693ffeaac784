//! pbrt-v4's `visualizestrategies` and `visualizeweights` for `Integrator "bdpt"`: one EXR
//! per connection strategy `(s, t)`, named `bdpt_dDD_sSS_tTT.exr` with depth
//! `DD = s + t - 2`, beside the output image. `visualizestrategies` writes each strategy's
//! contribution unweighted (what it estimates alone), `visualizeweights` writes it
//! MIS-weighted (its share of the final image; these images add up to it).
//!
//! pbrt fills all of them in one pass; here each image is its own render of the same
//! samples keeping only one strategy, so the cost is the number of strategies times that
//! of the main render (`(D + 1)(D + 4) / 2 - 1` strategies for max depth `D`).

use std::path::Path;

use anyhow::{Context, Result};
use mcrender_core::render::{render, RenderOptions};
use mcrender_core::scene::{IntegratorKind, Scene, SceneDescription};
use mcrender_formats::image_io::{write_image, ImageRgb};

/// The strategies `(s, t)` of paths with at most `max_depth` bounces, by depth.
#[must_use]
pub fn strategies(max_depth: u32) -> Vec<(u32, u32, u32)> {
    let mut v = Vec::new();
    for depth in 0..=max_depth {
        for t in 1..=depth + 2 {
            let s = depth + 2 - t;
            if (s, t) != (1, 1) {
                v.push((depth, s, t));
            }
        }
    }
    v
}

/// Write the per-strategy images when the scene asks for them; does nothing otherwise.
pub fn write_if_requested(desc: &SceneDescription, opts: &RenderOptions, dir: &Path, quiet: bool) -> Result<()> {
    let b = desc.integrator.bdpt;
    if desc.integrator.kind != IntegratorKind::Bdpt || !(b.visualize_strategies || b.visualize_weights) {
        return Ok(());
    }
    for (depth, s, t) in strategies(desc.integrator.max_depth) {
        let mut d = desc.clone();
        d.integrator.bdpt.strategy = Some((s, t));
        // pbrt: visualizeweights wins when both are set.
        d.integrator.bdpt.mis = b.visualize_weights;
        let scene = Scene::build(&d).context("the scene cannot be rendered")?;
        let out = render(&scene, opts, &|_, _| {})?;
        let path = dir.join(format!("bdpt_d{depth:02}_s{s:02}_t{t:02}.exr"));
        let img = ImageRgb {
            width: out.film.width(),
            height: out.film.height(),
            pixels: out.film.mean_image(),
        };
        write_image(&path, &img).with_context(|| format!("cannot write \"{}\"", path.display()))?;
        if !quiet {
            eprintln!("{}", path.display());
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strategies_cover_each_depth_once_per_split() {
        assert_eq!(strategies(1), vec![(0, 0, 2), (1, 2, 1), (1, 1, 2), (1, 0, 3)]);
        // (D + 1)(D + 4) / 2 - 1 strategies.
        assert_eq!(strategies(7).len(), 8 * 11 / 2 - 1);
    }
}
