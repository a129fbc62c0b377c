//! The `grime` command line.

mod cli;

use clap::Parser;

fn main() {
    let args = cli::Cli::parse();
    if let Err(err) = cli::dispatch(args) {
        // One line: what was wrong and how to fix it.
        let msg: Vec<String> = err.chain().map(|e| e.to_string()).collect();
        eprintln!("grime: error: {}", msg.join(": "));
        std::process::exit(1);
    }
}
