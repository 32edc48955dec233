//! The registry is the one place that lists the formats: a format's module
//! and its line in the registry (`src/lib.rs`) are all that name it, the
//! README's table and `asperity formats` show every one, and the fuzz seeds
//! and the malformed-file corpus are filed by its key (see
//! `fuzz_regressions.rs` and `malformed.rs`).

use std::path::{Path, PathBuf};

use asperity_io::Format;

/// The registry's lines in `src/lib.rs`: variant and module.
fn registry_lines(lib: &str) -> Vec<(String, String)> {
    let block = &lib[lib.find("format::registry! {").unwrap()..];
    let block = &block[..block.find("\n}\n").unwrap()];
    block
        .lines()
        .filter_map(|l| l.trim().strip_suffix(','))
        .filter_map(|l| l.split_once(" => "))
        .map(|(v, m)| (v.to_string(), m.split("::").next().unwrap().to_string()))
        .collect()
}

/// Every Rust source of the workspace's crates and of the fuzz binary, with
/// its text up to its `#[cfg(test)]` module: the code a new format could
/// have to be added to (tests of a format are new code, not edits).
fn sources(root: &Path) -> Vec<(PathBuf, String)> {
    fn walk(dir: &Path, out: &mut Vec<(PathBuf, String)>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push((path.clone(), std::fs::read_to_string(&path).unwrap()));
            }
        }
    }
    let mut out = Vec::new();
    for krate in std::fs::read_dir(root.join("crates")).unwrap() {
        let src = krate.unwrap().path().join("src");
        if src.is_dir() {
            walk(&src, &mut out);
        }
    }
    walk(&root.join("fuzz/fuzz_targets"), &mut out);
    for (_, text) in &mut out {
        if let Some(tests) = text.find("#[cfg(test)]") {
            text.truncate(tests);
        }
    }
    out
}

/// The extensions no earlier format lists (a `.csv` is a CSV grid's; the
/// Dektak export claims some by content).
fn own_extensions(format: Format) -> impl Iterator<Item = &'static str> {
    let earlier = &Format::ALL[..format as usize];
    format
        .info()
        .extensions
        .iter()
        .copied()
        .filter(|e| !earlier.iter().any(|f| f.info().extensions.contains(e)))
}

/// Whether `text` names `word` as a whole word after `prefix`.
fn names(text: &str, prefix: &str, word: &str) -> bool {
    let pattern = format!("{prefix}{word}");
    text.match_indices(&pattern).any(|(at, _)| {
        let after = text[at + pattern.len()..].chars().next();
        let before = text[..at].chars().next_back();
        !after.is_some_and(|c| c.is_alphanumeric() || c == '_')
            && !before.is_some_and(|c| c.is_alphanumeric() || c == '_')
    })
}

/// Per format, the files outside its module that name its variant
/// (`Format::Vk`), its module (`vk::`) or one of its extensions (`"vk4"` in
/// the readers' crate, a name ending `.vk4"` anywhere): none for a format that is only read (adding one touches its
/// module and its registry line); for the formats asperity writes, the
/// writers' dispatch and the commands that pick what to write by the output's
/// format (listed here, so that a new place shows up in review).
#[test]
fn only_its_module_and_its_registry_line_name_a_read_only_format() {
    let root = asperity_fixtures::workspace();
    let lib_path = root.join("crates/io/src/lib.rs");
    let lib = std::fs::read_to_string(&lib_path).unwrap();
    let lines = registry_lines(&lib);
    assert_eq!(
        lines.len(),
        Format::ALL.len(),
        "one registry line per format"
    );
    let sources = sources(&root);
    let mut report = String::new();
    for ((variant, module), &format) in lines.iter().zip(Format::ALL) {
        assert_eq!(variant, &format!("{format:?}"), "registry order");
        let own = [
            root.join(format!("crates/io/src/{module}.rs")),
            root.join(format!("crates/io/src/{module}")),
        ];
        let mut named_in: Vec<String> = Vec::new();
        for (path, text) in &sources {
            if own.iter().any(|o| path.starts_with(o)) {
                continue;
            }
            // The registry line itself, and lib.rs's module docs, are allowed.
            let text = if path == &lib_path {
                let end = lib.find("format::registry! {").unwrap();
                let registry_end = end + lib[end..].find("\n}\n").unwrap();
                format!(
                    "{}{}",
                    &lib[..end].replace("//!", "  "),
                    &lib[registry_end..]
                )
            } else {
                text.clone()
            };
            // An extension as a string in the readers' crate (`"vk4"`), or
            // ending a file name anywhere (`".vk4"`, `"scan.vk4"`; not a
            // member name made with `format!`, such as NMM's `"{stem}.dat"`).
            let in_io = path.starts_with(root.join("crates/io"));
            let ext = own_extensions(format).any(|e| {
                (in_io && names(&text, "\"", &format!("{e}\"")))
                    || text
                        .match_indices(&format!(".{e}\""))
                        .any(|(at, _)| !text[..at].ends_with('}'))
            });
            if names(&text, "Format::", variant) || names(&text, "", &format!("{module}::")) || ext
            {
                named_in.push(path.strip_prefix(&root).unwrap().display().to_string());
            }
        }
        let info = format.info();
        let written = info.mesh.can_write() || info.points.can_write() || info.height.can_write();
        report += &format!("{variant}: {named_in:?}\n");
        if !written {
            assert!(
                named_in.is_empty(),
                "{variant} (read only) is named outside its module ({module}) and its registry line: {named_in:?}"
            );
        }
    }
    println!("{report}");
}

/// The README's table of formats (its "File formats" section) has a row for
/// every registered format: one whose extension cell names each of its
/// extensions (`` `.vk4` ``).
#[test]
fn the_readme_s_table_shows_every_format() {
    let readme = std::fs::read_to_string(asperity_fixtures::workspace().join("README.md")).unwrap();
    let section = &readme[readme.find("## File formats").unwrap()..];
    let section = &section[..section[3..].find("\n## ").map_or(section.len(), |e| e + 3)];
    let cells: Vec<&str> = section
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| ---") && !l.starts_with("| Format"))
        .filter_map(|l| l.split(" | ").nth(1))
        .collect();
    assert!(cells.len() >= 40, "{} rows", cells.len());
    for &format in Format::ALL {
        let info = format.info();
        assert!(
            cells.iter().any(|cell| info
                .extensions
                .iter()
                .all(|e| cell.contains(&format!("`.{e}`")))),
            "no row of the README's table lists {} ({:?})",
            info.name,
            info.extensions
        );
    }
}
