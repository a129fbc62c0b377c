//! The `grime` command line.

mod cli;

use clap::Parser;

fn main() {
    let args = cli::Cli::parse();
    let result = cli::dispatch(args);
    if cli::signals::interrupted() {
        eprintln!("grime: interrupted (Ctrl-C or SIGTERM); unfinished outputs were not written");
        std::process::exit(cli::signals::EXIT_INTERRUPTED);
    }
    if let Err(err) = result {
        // One line: what was wrong and how to fix it. Library errors already
        // include their cause, so a cause repeated down the chain is skipped.
        let mut line = String::new();
        for part in err.chain().map(|e| e.to_string()) {
            if !line.contains(&part) {
                line = if line.is_empty() {
                    part
                } else {
                    format!("{line}: {part}")
                };
            }
        }
        eprintln!("grime: error: {}", line.replace('\n', " "));
        std::process::exit(1);
    }
}
