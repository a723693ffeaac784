//! `mcrender`: render a pbrt-v4 scene (or, with no arguments, the built-in Cornell box).
//!
//! Exit codes: 0 success, 2 bad input (unreadable or malformed scene, absurd parameters,
//! unwritable output), with a message on stderr naming what is wrong.

mod builtin;
mod render_cmd;

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
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Render(args)) => render_cmd::run(&args),
        None => render_cmd::run(&render_cmd::RenderArgs::builtin_default()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("mcrender: error: {e:#}");
            ExitCode::from(2)
        }
    }
}
