//! `mcrender`: render a pbrt-v4 scene (or, with no arguments, the built-in Cornell box).
//!
//! Exit codes: 0 success, 2 bad input (unreadable or malformed scene, absurd parameters,
//! unwritable output, a checkpoint that does not match), with a message on stderr naming
//! what is wrong; 130 / 143 a render stopped by SIGINT / SIGTERM (image so far and a
//! checkpoint written); 141 when standard output was closed by its reader (`| head`).

mod bdpt_visualize;
mod bench_rays_cmd;
mod builtin;
mod checkpoint;
mod convert_cmd;
mod diff_cmd;
mod interrupt;
mod lab;
mod mlt_render;
mod pi_cmd;
mod preflight;
mod progressive;
mod render_cmd;
mod scene_args;
mod sppm_render;
mod state_driver;
mod stdout;
mod study;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// A physically based Monte Carlo path tracer.
#[derive(Parser, Debug)]
#[command(name = "mcrender", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a pbrt-v4 scene file (the built-in Cornell box when SCENE is omitted).
    Render(render_cmd::RenderArgs),
    /// Compare direct-lighting techniques: variance, time, efficiency, contact sheet, convergence plot.
    Compare(study::compare::CompareArgs),
    /// Render the scene at several maximum depths, with a labelled contact sheet.
    Bounces(study::bounces::BouncesArgs),
    /// Compare Russian roulette settings: time, mean radiance and error against a reference.
    RrStudy(study::rr_study::RrStudyArgs),
    /// Compare an image with a reference: MSE, relative MSE, means, block-mean relative error.
    Diff(diff_cmd::DiffArgs),
    /// Re-encode an image (EXR/PFM/PNG/... to PNG or EXR), optionally downsampled and scaled.
    Convert(convert_cmd::ConvertArgs),
    /// Estimate pi from random points and show the variance falling as 1/N (the lecture's
    /// coconut).
    Pi(pi_cmd::PiArgs),
    /// Trace a fixed list of rays against a PLY mesh: BVH build time and rays per second
    /// (the interface `bench/rays.sh` also feeds to Embree).
    BenchRays(bench_rays_cmd::BenchRaysArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Render(args)) => render_cmd::run(&args),
        Some(Command::Compare(args)) => study::compare::run(&args),
        Some(Command::Bounces(args)) => study::bounces::run(&args),
        Some(Command::RrStudy(args)) => study::rr_study::run(&args),
        Some(Command::Diff(args)) => diff_cmd::run(&args),
        Some(Command::Convert(args)) => convert_cmd::run(&args),
        Some(Command::Pi(args)) => pi_cmd::run(&args),
        Some(Command::BenchRays(args)) => bench_rays_cmd::run(&args),
        None => render_cmd::run(&render_cmd::RenderArgs::builtin_default()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // The message (samples done, files written) is already on stderr.
        Err(e) if e.downcast_ref::<interrupt::Interrupted>().is_some() => {
            ExitCode::from(e.downcast_ref::<interrupt::Interrupted>().map_or(2, |i| i.code))
        }
        Err(e) if e.downcast_ref::<stdout::ReaderGone>().is_some() => ExitCode::from(stdout::READER_GONE_STATUS),
        Err(e) => {
            eprintln!("mcrender: error: {}", error_line(&e));
            ExitCode::from(2)
        }
    }
}

/// An error and its causes on one line, `outer: cause: cause`, without a cause whose text
/// the line already holds (an I/O error is often both a message and its source, which read
/// "No such file or directory: No such file or directory (os error 2)"), control characters
/// escaped and quoted input shortened.
fn error_line(e: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        let bare = match cause.downcast_ref::<std::io::Error>() {
            Some(io) => mcrender_formats::io_error_text(io),
            None => text.clone(),
        };
        if line.contains(bare.trim()) {
            continue;
        }
        if !line.is_empty() {
            line.push_str(": ");
        }
        line.push_str(&text);
    }
    mcrender_formats::tidy_message(&line)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn doubled_os_errors_are_printed_once() {
        let io = std::fs::File::open("/definitely/not/here").unwrap_err();
        let img = mcrender_formats::ImageError::Io {
            path: "/definitely/not/here".into(),
            source: io,
        };
        let e = anyhow::Error::new(img).context("cannot read \"x.png\"");
        let line = error_line(&e);
        assert_eq!(line.matches("No such file or directory").count(), 1, "{line}");
        assert!(!line.contains("os error"), "{line}");
    }
}
