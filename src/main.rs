//! The `glint` command line (README, Command line).

mod cli;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    // On SIGINT or SIGTERM, remove the temporary file of any write in
    // progress, so that an output is whole or absent. A handler that
    // cannot be installed only loses that clean-up.
    let _ = ctrlc::set_handler(|| {
        glint::raster::partial::remove_in_progress();
        eprintln!("error: interrupted");
        std::process::exit(130);
    });
    let args = cli::Cli::parse();
    match cli::run(args) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}
