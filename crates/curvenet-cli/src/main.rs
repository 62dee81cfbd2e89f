//! The `curvenet` command-line tool: a thin layer over the `curvenet` library.
//!
//! Exit codes: 0 success (warnings on stderr and in the output), 2 when no network can be built
//! or the usage is wrong (the message names the file and line, or the option), 1 internal
//! error, 130 cancelled (Ctrl-C or SIGTERM; what was recorded is kept).

mod args;
mod cmd;
mod exit;
mod front;
mod signals;
mod values;

use clap::Parser;

fn main() {
    signals::install();
    let cli = args::Cli::parse();
    let result = cmd::run(cli);
    std::process::exit(exit::report(result));
}
