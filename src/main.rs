//! The `glint` command line (docs/commands.md).

mod cli;

use std::process::ExitCode;

use clap::error::ErrorKind;
use clap::{CommandFactory, FromArgMatches};

fn main() -> ExitCode {
    let code = run();
    #[cfg(feature = "gpu")]
    if glint::gpu::open_unfinished() {
        cli::console::exit_past_a_stuck_open(code);
    }
    code
}

fn run() -> ExitCode {
    // On SIGINT, SIGTERM or SIGHUP, remove the temporary file of any write in
    // progress, so that an output is whole or absent. A handler that
    // cannot be installed only loses that clean-up.
    let _ = cli::signals::set_handler(|| {
        glint::output::remove_in_progress();
        glint::output::interrupt::clean_up();
        cli::console::last_words(format_args!("error: interrupted\n"));
        cli::console::exit_interrupted();
    });
    let argv: Vec<std::ffi::OsString> = std::env::args_os().collect();
    let mut command = cli::Cli::command();
    if cli::version::asked(&argv) {
        // clap keeps a version as &'static str (without its "string"
        // feature); the text lives until the process prints it and exits.
        command = command.long_version(cli::version::long().leak() as &str);
    }
    let args = match command
        .try_get_matches_from(argv)
        .and_then(|m| cli::Cli::from_arg_matches(&m))
    {
        Ok(args) => args,
        Err(e) => return usage_error(e),
    };
    cli::console::catching(|| match cli::run(args) {
        Ok(code) => {
            cache_notices();
            code
        }
        Err(e) => {
            cache_notices();
            cli::console::last_words(format_args!("error: {e:#}\n"));
            ExitCode::from(2)
        }
    })
}

/// What the caches repaired during the command (a damaged SPIR-V entry
/// compiled again), a line each at INFO level on stderr.
fn cache_notices() {
    #[cfg(feature = "gpu")]
    for n in glint::gpu::sealed::notices() {
        cli::console::to_stderr(format_args!("info: {n}\n"));
    }
}

/// clap's own text (usage, tips, or the help where a command is missing),
/// then one closing line that says what is wrong, exit status 2; `--help`
/// and `--version` print as clap prints them, exit status 0.
fn usage_error(e: clap::Error) -> ExitCode {
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => cli::console::catching(|| {
            cli::console::to_stdout(format_args!("{}", e.render()));
            ExitCode::SUCCESS
        }),
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            cli::console::last_words(format_args!(
                "{}\nerror: a command is missing (see the usage above)\n",
                e.render().to_string().trim_end()
            ));
            ExitCode::from(2)
        }
        _ => {
            let text = e.render().to_string();
            let mut lines = text.trim().lines();
            let first = lines.next().unwrap_or("error: bad arguments");
            let rest: Vec<&str> = lines.collect();
            let rest = rest.join("\n");
            if !rest.trim().is_empty() {
                cli::console::last_words(format_args!("{}\n\n", rest.trim()));
            }
            cli::console::last_words(format_args!("{}\n", glint::printable::text(first)));
            ExitCode::from(2)
        }
    }
}
