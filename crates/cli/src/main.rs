//! `asperity`: generate, analyse, render and export rough surfaces.
//!
//! The binary is a thin layer over `asperity-engine` (and `asperity-gallery`
//! for `demo`): it parses arguments (clap), sets up threads, memory limits and
//! progress bars, calls a job, writes what it returns, and reports. Errors print
//! as one `error:` line with their causes and exit code 2.

/// `println!` that returns the I/O error instead of panicking (a closed pipe,
/// as in `asperity formats | head`, ends the command cleanly).
macro_rules! outln {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($t)*)?;
    }};
}

/// `print!` that returns the I/O error instead of panicking.
macro_rules! out {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        write!(std::io::stdout().lock(), $($t)*)?;
    }};
}

/// mimalloc keeps freed pages for reuse: the multi-megabyte buffers of
/// subdivision, level sets and rendering otherwise go back to the kernel and
/// fault in again (about a tenth of the time of 4-level subdivision).
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

mod analyze_cmd;
mod bench_cmd;
mod ca_cmd;
mod cli;
mod context;
mod convert;
mod demo;
mod growth_cmd;
mod ifs_cmd;
mod memory;
mod progress;
mod reconstruct_cmd;
mod render_cmd;
mod scaling_cmd;
mod stdout;
mod subdiv_cmd;
mod surfca_cmd;

use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches};

fn main() -> ExitCode {
    let matches = negative_numbers(cli::Cli::command()).get_matches();
    let mut args = cli::Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    let explicit = given_on_the_command_line(&matches);
    // `-o -`: the command writes into a private folder; the file goes to
    // stdout only once the command has succeeded.
    let stdout_dir = match stdout::redirect(&mut args.global) {
        Ok(d) => d,
        Err(err) => {
            eprintln!("error: {}", message(&err));
            return ExitCode::from(2);
        }
    };
    // Ctrl-C, SIGTERM, SIGHUP: delete the temporary files of unfinished outputs,
    // then exit as a shell expects of an interrupted program.
    let _ = ctrlc::set_handler(|| asperity_engine::io::exit_removing_temporaries(130));
    // Every output of the command is renamed into place only when the whole
    // command succeeded: a failure leaves every existing file as it was.
    // (`bench` writes only scratch files, timed with their rename.)
    let outputs = (!matches!(args.command, cli::Command::Bench(_)))
        .then(asperity_engine::io::Transaction::begin);
    let quiet = args.global.quiet;
    let result = run(args, explicit)
        .and_then(|()| match outputs {
            Some(tx) => Ok(tx.commit()?),
            None => Ok(()),
        })
        .and_then(|()| stdout_dir.as_ref().map_or(Ok(()), stdout::send));
    if !quiet {
        for p in asperity_engine::io::stale_temporaries() {
            eprintln!(
                "note: removed {}, left by a run that was killed",
                p.display()
            );
        }
    }
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            // A closed pipe (e.g. `asperity formats | head`) is not an error.
            if err.chain().any(|c| {
                c.downcast_ref::<std::io::Error>()
                    .is_some_and(|e| e.kind() == std::io::ErrorKind::BrokenPipe)
                    || c.downcast_ref::<serde_json::Error>()
                        .is_some_and(|e| e.io_error_kind() == Some(std::io::ErrorKind::BrokenPipe))
            }) {
                return ExitCode::SUCCESS;
            }
            eprintln!("error: {}", message(&err));
            ExitCode::from(2)
        }
    }
}

/// Every option that takes a value reads a negative number as its value
/// (`--k1 -0.5`, not only `--k1=-0.5`), in every subcommand.
fn negative_numbers(cmd: clap::Command) -> clap::Command {
    cmd.mut_args(|a| {
        let takes = a.get_action().takes_values();
        a.allow_negative_numbers(takes)
    })
    .mut_subcommands(negative_numbers)
}

/// The error and its causes on one line, each cause once: a cause whose text
/// the message already holds (errors that print their source) is not repeated;
/// parameters named as flags.
fn message(err: &anyhow::Error) -> String {
    let mut msg = err.to_string();
    for cause in err.chain().skip(1) {
        let c = cause.to_string();
        if !msg.contains(&c) {
            msg = format!("{msg}: {c}");
        }
    }
    asperity_engine::core::wording::spell(&msg, asperity_engine::core::wording::Spelling::Cli)
}

/// The ids (field names) of every argument given on the command line, at any
/// level of subcommands.
fn given_on_the_command_line(matches: &clap::ArgMatches) -> std::collections::BTreeSet<String> {
    let mut given = std::collections::BTreeSet::new();
    let mut level = Some(matches);
    while let Some(m) = level {
        for id in m.ids() {
            if m.value_source(id.as_str()) == Some(clap::parser::ValueSource::CommandLine) {
                given.insert(id.as_str().to_owned());
            }
        }
        level = m.subcommand().map(|(_, sub)| sub);
    }
    given
}

fn run(args: cli::Cli, explicit: std::collections::BTreeSet<String>) -> anyhow::Result<()> {
    let ctx = context::Context::new(&args.global, explicit)?;
    match args.command {
        cli::Command::Demo(a) => demo::run(&ctx, &a),
        cli::Command::Convert(a) => convert::run(&ctx, &a),
        cli::Command::Info(a) => convert::info(&ctx, &a),
        cli::Command::Render(a) => render_cmd::run(&ctx, &a),
        cli::Command::Formats => convert::formats(&ctx),
        cli::Command::Bench(a) => bench_cmd::run(&ctx, &a),
        cli::Command::Analyze(a) => analyze_cmd::analyze(&ctx, &a),
        cli::Command::Filter(a) => analyze_cmd::filter(&ctx, &a),
        cli::Command::Generate(cli::GenerateCommand::Fbm(a)) => analyze_cmd::fbm(&ctx, &a),
        cli::Command::Generate(cli::GenerateCommand::DlaTerrain(a)) => {
            reconstruct_cmd::dla_terrain(&ctx, &a)
        }
        cli::Command::Generate(cli::GenerateCommand::RdsrSphere(a)) => {
            reconstruct_cmd::rdsr_sphere(&ctx, &a)
        }
        cli::Command::Reconstruct(a) => reconstruct_cmd::run(&ctx, &a),
        cli::Command::Ifs(c) => ifs_cmd::run(&ctx, c),
        cli::Command::SurfaceCa(a) => surfca_cmd::run(&ctx, &a),
        cli::Command::Subdiv(a) => subdiv_cmd::run(&ctx, &a),
        cli::Command::Growth(c) => growth_cmd::run(&ctx, c),
        cli::Command::Ca(c) => ca_cmd::run(&ctx, c),
        cli::Command::Facet(a) => ca_cmd::facet(&ctx, &a),
        cli::Command::Interpolate(a) => ca_cmd::interpolate(&ctx, &a),
    }
}
