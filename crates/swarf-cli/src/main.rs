//! The `swarf` command line: argument parsing and printing over the swarf libraries.
//!
//! Exit status: 0 on success, 1 on bad input (the message names file, line and column), 2 on a
//! usage error (clap's own exit code).

mod cli;
mod commands;
mod output;

use clap::Parser;

fn main() {
    output::install_stop_handler();
    let cli = cli::Cli::parse();
    // The runs that poll for Ctrl-C between moves stop cleanly (no output written); the
    // others end at once, as without a handler.
    if matches!(
        cli.command,
        cli::Command::Simulate(_)
            | cli::Command::Verify(_)
            | cli::Command::Engage(_)
            | cli::Command::Forces(_)
            | cli::Command::Schedule(_)
    ) {
        output::listen_for_stop();
    }
    let result = match cli.command {
        cli::Command::Tool(args) => commands::tool::run(&args),
        cli::Command::Path(args) => commands::path::run(&args),
        cli::Command::Simulate(args) => commands::simulate::run(&args),
        cli::Command::Toolsize(args) => commands::toolsize::run(&args),
        cli::Command::Envelope(args) => commands::envelope::run(&args),
        cli::Command::Engage(args) => commands::engage::run(&args),
        cli::Command::Forces(args) => commands::forces::run(&args),
        cli::Command::Schedule(args) => commands::schedule::run(&args),
        cli::Command::Gouge(args) => commands::gouge::run(&args),
        cli::Command::Verify(args) => commands::verify::run(&args),
        cli::Command::Demo(args) => commands::demo::run(&args),
        cli::Command::Report(args) => commands::report::run(&args),
    };
    if let Err(e) = result {
        // A closed pipe (`swarf path x --json | head`) is the reader's choice, not an error.
        let broken_pipe = e.chain().any(|c| {
            let kind = c
                .downcast_ref::<std::io::Error>()
                .map(std::io::Error::kind)
                .or_else(|| c.downcast_ref::<serde_json::Error>()?.io_error_kind());
            kind == Some(std::io::ErrorKind::BrokenPipe)
        });
        if broken_pipe {
            std::process::exit(0);
        }
        // `{:#}` prints the whole context chain on one line: "reading X: X:3:7: message".
        eprintln!("swarf: error: {e:#}");
        std::process::exit(1);
    }
}
