//! `mcrender bounces`: the same scene with increasing maximum depth (the lecture's 1, 2, 4,
//! 8, 16 bounces), one image per depth and a labelled contact sheet.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use clap::Args;
use mcrender_core::render::{RenderOptions, RenderSession};
use mcrender_core::scene::Scene;

use super::{film_image, write_into};
use crate::lab::sheet::contact_sheet;
use crate::scene_args::SceneArgs;
use crate::stdout::say;

/// Options of `mcrender bounces`.
#[derive(Args, Debug)]
pub struct BouncesArgs {
    /// The scene and overrides.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Maximum depths to render, comma-separated (0 = emission only, 1 = direct lighting).
    #[arg(long, value_delimiter = ',', default_value = "1,2,4,8,16")]
    pub depths: Vec<u32>,
    /// Directory for the images and the contact sheet.
    #[arg(short, long, default_value = "bounces")]
    pub out_dir: PathBuf,
}

/// Run the command.
pub fn run(args: &BouncesArgs) -> Result<()> {
    if args.depths.is_empty() {
        bail!("--depths: expected at least one depth");
    }
    let (loaded, stem) = args.scene.load()?;
    let mut base = loaded.description;
    args.scene.apply(&mut base)?;
    let mut images = Vec::new();
    for &depth in &args.depths {
        let mut desc = base.clone();
        desc.integrator.max_depth = depth;
        let scene = Scene::build(&desc).context("the scene cannot be rendered")?;
        let opts = RenderOptions {
            threads: args.scene.threads,
            ..Default::default()
        };
        let out = RenderSession::new(&scene, &opts)?.render_samples(0..desc.sampler.samples_per_pixel, &())?;
        let img = film_image(&out.film);
        let path = write_into(&args.out_dir, &format!("{stem}-depth-{depth}.png"), &img)?;
        say!(
            "depth {depth:>3}: {:.2} s, mean radiance {:.5} -> {}",
            out.stats.elapsed.as_secs_f64(),
            mean_luminance(&img.pixels),
            path.display()
        );
        let label = match depth {
            0 => "depth 0: emission".to_string(),
            1 => "depth 1: direct".to_string(),
            d => format!("depth {d}"),
        };
        images.push((label, img));
    }
    let sheet = contact_sheet(&images, images.len().min(5))?;
    let path = write_into(&args.out_dir, &format!("{stem}-bounces.png"), &sheet)?;
    say!("contact sheet -> {}", path.display());
    Ok(())
}

fn mean_luminance(p: &[mcrender_core::color::Rgb]) -> f64 {
    p.iter().map(|c| f64::from(c.luminance())).sum::<f64>() / p.len().max(1) as f64
}
