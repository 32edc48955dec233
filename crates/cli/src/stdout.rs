//! `-o -`: one output file sent to stdout.
//!
//! The command writes as usual, into a private temporary folder under a name
//! with the `--format` extension, so every writer, the all-or-nothing commit
//! and the format checks stay the same; once the command has succeeded the
//! file is copied to stdout. A failure sends nothing. Commands that write more
//! than one file (numbered frames, textures beside an OBJ) are refused after
//! the fact, before anything reaches stdout.

use std::io::Write as _;
use std::path::PathBuf;

use anyhow::{Context as _, bail, ensure};

use crate::cli::Global;

/// Where a `-o -` command writes: the folder to send from.
pub struct StdoutDir(tempfile::TempDir);

/// Points `-o -` at a file in a fresh temporary folder; `None` for other outputs.
pub fn redirect(g: &mut Global) -> anyhow::Result<Option<StdoutDir>> {
    let to_stdout = g.output.as_deref() == Some(std::path::Path::new("-"));
    let Some(ext) = g.format.clone() else {
        ensure!(
            !to_stdout,
            "-o - writes to stdout and needs the format: add --format npy (or ply, stl, csv, …)"
        );
        return Ok(None);
    };
    ensure!(
        to_stdout,
        "--format names the format of -o - (stdout); a file's extension names its own"
    );
    ensure!(
        !g.json,
        "--json prints its report on stdout, where -o - sends the data; drop one of them"
    );
    let ext = ext.trim_start_matches('.').to_ascii_lowercase();
    ensure!(
        !ext.is_empty() && ext.chars().all(|c| c.is_ascii_alphanumeric()),
        "--format takes an extension such as npy, ply or csv, got {ext:?}"
    );
    let path = PathBuf::from(format!("stdout.{ext}"));
    asperity_engine::io::Format::from_path(&path)
        .with_context(|| format!("--format {ext}: run `asperity formats`"))?;
    let dir = tempfile::Builder::new()
        .prefix(".asperity-stdout.")
        .tempdir()
        .context("cannot create a temporary folder for -o -")?;
    g.output = Some(dir.path().join(path));
    Ok(Some(StdoutDir(dir)))
}

/// Copies the command's one file to stdout.
pub fn send(dir: &StdoutDir) -> anyhow::Result<()> {
    let files: Vec<PathBuf> = std::fs::read_dir(dir.0.path())
        .context("reading the -o - folder")?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    match files.as_slice() {
        [one] => {
            let bytes = std::fs::read(one).context("reading the -o - output")?;
            let mut out = std::io::stdout().lock();
            out.write_all(&bytes)?;
            out.flush()?;
            Ok(())
        }
        [] => bail!("the command wrote no file for -o -"),
        many => bail!(
            "-o - sends one file to stdout, but this command wrote {} (frames, textures or \
             companions); give a file name instead",
            many.len()
        ),
    }
}
