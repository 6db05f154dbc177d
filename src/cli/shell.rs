//! What a shell and `man` read: `glint completions SHELL` and `glint man`,
//! both generated from the command line's own definition so that they
//! cannot drift from it.

use std::process::ExitCode;

use anyhow::Context;
use clap::{Args, CommandFactory};
use clap_complete::Shell;

#[derive(Args)]
pub struct CompletionsArgs {
    /// The shell: bash, zsh, fish, elvish or powershell.
    shell: Shell,
}

/// Prints the completion script for `a.shell` on stdout.
pub fn completions(a: &CompletionsArgs) -> anyhow::Result<ExitCode> {
    let mut command = super::Cli::command();
    let mut out = Vec::new();
    clap_complete::generate(a.shell, &mut command, "glint", &mut out);
    write_stdout(&out)
}

/// Prints glint's man page (roff) on stdout: `glint man > glint.1`.
pub fn man() -> anyhow::Result<ExitCode> {
    let mut out = Vec::new();
    clap_mangen::Man::new(super::Cli::command())
        .render(&mut out)
        .context("cannot write the man page")?;
    write_stdout(&out)
}

fn write_stdout(bytes: &[u8]) -> anyhow::Result<ExitCode> {
    super::console::out_bytes(bytes);
    Ok(ExitCode::SUCCESS)
}
