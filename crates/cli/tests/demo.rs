//! `asperity demo`, the main job: the quick gallery is byte-identical at any
//! thread count and its pictures are real; the full gallery (slow tier,
//! `cargo test -- --ignored`) has every card of the quick one, every output
//! it reports, and no warning.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::{Command, Output};

fn asperity(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_asperity"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run asperity")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The quick demo three times at once (the machine's cores are shared, which
/// is faster than one after another): seed 11 at one thread and at two, and
/// the default seed at the default thread count.
#[test]
fn demo_is_byte_identical_across_thread_counts_and_its_pictures_are_real() {
    let d = tempfile::tempdir().unwrap();
    let runs: Vec<(&str, Vec<&str>)> = vec![
        ("g1", vec!["--threads", "1", "--seed", "11"]),
        ("g2", vec!["--threads", "2", "--seed", "11"]),
        ("g3", vec![]),
    ];
    let children: Vec<_> = runs
        .iter()
        .map(|(out, globals)| {
            Command::new(env!("CARGO_BIN_EXE_asperity"))
                .args(globals)
                .args(["demo", "--quick", "--out", out])
                .current_dir(d.path())
                .stdout(std::process::Stdio::piped())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .expect("run asperity")
        })
        .collect();
    for child in children {
        let o = child.wait_with_output().expect("wait for asperity");
        assert!(o.status.success(), "{}", stderr(&o));
    }
    identical_across_thread_counts(d.path());
    pictures_are_real(&d.path().join("g3"));
}

/// `g1` and `g2` (seed 11 at one and two threads) are the same files, every
/// command line shown parses, and `g3` (another seed) differs.
fn identical_across_thread_counts(d: &Path) {
    let g1 = d.join("g1");
    every_command_line_shown_parses(&g1.join("index.html"), d);
    let mut names: Vec<_> = std::fs::read_dir(&g1)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    names.sort();
    assert!(names.iter().any(|n| n == "index.html"));
    assert!(names.len() >= 15, "{names:?}");
    let viewer: Vec<_> = std::fs::read_dir(g1.join("viewer"))
        .unwrap()
        .map(|e| std::path::Path::new("viewer").join(e.unwrap().file_name()))
        .collect();
    assert!(viewer.len() > 10, "the 3-D views: {viewer:?}");
    let files = names
        .iter()
        .map(std::path::PathBuf::from)
        .filter(|n| n.as_os_str() != "viewer")
        .chain(viewer);
    for n in files {
        if n.as_os_str() == "report.json" {
            continue; // holds timings and the thread count
        }
        let a = std::fs::read(g1.join(&n)).unwrap();
        let b = std::fs::read(d.join("g2").join(&n)).unwrap();
        assert!(a == b, "{n:?} differs between 1 and 2 threads");
    }
    // A different seed gives a different surface.
    assert_ne!(
        std::fs::read(g1.join("sample_height.npy")).unwrap(),
        std::fs::read(d.join("g3/sample_height.npy")).unwrap()
    );
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(g1.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["seed"], 11);
    assert_eq!(report["threads"], 1);
}

/// Every picture of the gallery `g` is on its page and is a real picture, and
/// the gallery is light.
fn pictures_are_real(g: &Path) {
    let html = std::fs::read_to_string(g.join("index.html")).unwrap();
    let mut pngs = 0;
    for e in std::fs::read_dir(g).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if p.extension().is_some_and(|x| x == "png")
            && !name.ends_with("_texture.png")
            && name != "sample_height.png"
        {
            // Every picture is shown on the page…
            assert!(
                html.contains(&format!("src=\"{name}\"")),
                "{name} is not on the page"
            );
            // …and is a real picture: PNGs read as heights are luminance in [0, 1].
            let h = asperity_io::read_height(&p).unwrap();
            let (lo, hi) = h.min_max();
            assert!(
                h.nx() >= 64 && h.ny() >= 64,
                "{name}: {}×{}",
                h.nx(),
                h.ny()
            );
            assert!(hi - lo > 0.2, "{name} is nearly uniform ({lo}..{hi})");
            let mean = h.mean();
            let sd =
                (h.data().iter().map(|v| (v - mean).powi(2)).sum::<f64>() / h.len() as f64).sqrt();
            assert!(sd > 0.02, "{name}: contrast {sd}");
            pngs += 1;
        }
    }
    assert!(pngs >= 10, "{pngs} pictures");
    assert_light(g, 25e6, asperity_gallery::downloads::TRIANGLE_BUDGETS.0);
    for section in ["Foundation", "Renderer"] {
        assert!(html.contains(section), "section {section}");
    }
    let svg = std::fs::read_to_string(g.join("plot_rock_curvature.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("<path") || svg.contains("<polyline"));
}

/// A gallery is at most `limit` bytes with everything in it (#39), and each
/// of its PLY meshes is within the triangle `budget` or reduced to it as far as
/// its seams allow, as the report lists and the page says.
fn assert_light(gallery: &Path, limit: f64, budget: usize) {
    let mut total = 0;
    let mut stack = vec![gallery.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(dir).unwrap() {
            let e = e.unwrap();
            match e.file_type().unwrap().is_dir() {
                true => stack.push(e.path()),
                false => total += e.metadata().unwrap().len(),
            }
        }
    }
    assert!(total as f64 <= limit, "{total} bytes (at most {limit})");
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(gallery.join("report.json")).unwrap()).unwrap();
    let reduced = report["measurements"]["reduced_downloads"]
        .as_object()
        .unwrap();
    assert!(reduced.len() >= 10, "{} reduced downloads", reduced.len());
    let html = std::fs::read_to_string(gallery.join("index.html")).unwrap();
    for e in std::fs::read_dir(gallery).unwrap() {
        let path = e.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if !name.ends_with(".ply") {
            continue;
        }
        let Ok(m) = asperity_io::read_mesh(&path) else {
            continue; // a point set
        };
        match reduced.get(&name) {
            Some(counts) => {
                let (kept, whole) = (counts[0].as_u64().unwrap(), counts[1].as_u64().unwrap());
                assert_eq!(m.n_faces() as u64, kept, "{name}");
                assert!(kept < whole, "{name}: {kept} of {whole}");
                let said = format!("{name} reduced to {kept} of {whole} triangles");
                assert!(html.contains(&said), "the page says {said}");
            }
            None => assert!(m.n_faces() <= budget, "{name}: {} triangles", m.n_faces()),
        }
    }
}

/// `--full-meshes` writes the downloads whole, and their cards say nothing of
/// a reduction.
#[test]
fn full_meshes_writes_the_downloads_whole() {
    let d = tempfile::tempdir().unwrap();
    for (flags, out) in [(&[][..], "reduced"), (&["--full-meshes"][..], "whole")] {
        let args = [
            &[
                "--quiet", "demo", "--quick", "--only", "subdiv", "--out", out,
            ],
            flags,
        ]
        .concat();
        let o = asperity(&args, d.path());
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let faces = |out: &str| {
        asperity_io::read_mesh(&d.path().join(out).join("subdiv_rock.ply"))
            .unwrap()
            .n_faces()
    };
    let budget = asperity_gallery::downloads::TRIANGLE_BUDGETS.0;
    assert_eq!(faces("reduced"), budget);
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.path().join("reduced/report.json")).unwrap())
            .unwrap();
    let counts = &report["measurements"]["reduced_downloads"]["subdiv_rock.ply"];
    assert_eq!(counts[0], budget);
    assert_eq!(
        counts[1],
        faces("whole"),
        "the whole mesh, as the reduced run counted it"
    );
    assert!(faces("whole") > budget);
    let html = std::fs::read_to_string(d.path().join("whole/index.html")).unwrap();
    assert!(!html.contains("reduced to"), "no card says reduced");
    let report = std::fs::read_to_string(d.path().join("whole/report.json")).unwrap();
    assert!(!report.contains("reduced_downloads"));
}

/// The files of a gallery with the level-set flow's step numbers taken out
/// (the full demo saves later steps of the same flow).
fn cards(gallery: &Path) -> BTreeSet<String> {
    std::fs::read_dir(gallery)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .map(|name| match name.find("_step") {
            Some(i) => {
                let rest = name[i + 5..].trim_start_matches(|c: char| c.is_ascii_digit());
                format!("{}_step{rest}", &name[..i])
            }
            None => name,
        })
        .collect()
}

#[test]
#[ignore = "slow tier: the full demo, ~1 min (cargo test -- --ignored)"]
fn full_demo_has_every_card_and_every_output_it_reports() {
    let d = tempfile::tempdir().unwrap();
    let o = asperity(&["--quiet", "demo", "--out", "full"], d.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let full = d.path().join("full");
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(full.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["warnings"], serde_json::json!([]), "warnings");
    let outputs = report["outputs"].as_array().unwrap();
    assert!(outputs.len() >= 140, "{} outputs", outputs.len());
    assert_light(
        &full,
        250e6,
        asperity_gallery::downloads::TRIANGLE_BUDGETS.1,
    );
    let html = std::fs::read_to_string(full.join("index.html")).unwrap();
    for out in outputs {
        // relative to where the command ran
        let path = d.path().join(out["path"].as_str().unwrap());
        let bytes = std::fs::metadata(&path)
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
            .len();
        assert!(bytes > 0, "{} is empty", path.display());
        assert_eq!(Some(bytes), out["bytes"].as_u64(), "{}", path.display());
        let name = path.file_name().unwrap().to_string_lossy();
        if name.ends_with(".png") && !name.ends_with("_texture.png") && name != "sample_height.png"
        {
            assert!(
                html.contains(&format!("src=\"{name}\"")),
                "{name} is not on the page"
            );
        }
    }
    let sections = report["measurements"]["sections"].as_array().unwrap();
    assert_eq!(sections.len(), 9, "{sections:?}");
    for key in [
        "peridier",
        "kim-machiraju-thompson §4",
        "kim-machiraju-thompson §5",
        "poull-gentil",
        "gobron-chiba",
        "velho-perlin",
    ] {
        assert!(
            sections.iter().any(|s| s.as_str().unwrap().contains(key)),
            "{key} in {sections:?}"
        );
    }
    let o = asperity(&["--quiet", "demo", "--quick", "--out", "quick"], d.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        cards(&full),
        cards(&d.path().join("quick")),
        "the same cards"
    );
}

/// The gallery shows the command line that makes each card (a "CLI" fact,
/// typed by hand in `crates/gallery`): each must be one the CLI accepts. With
/// `--help` appended clap checks every flag and value before it and prints
/// the help instead of running, so a renamed flag or a value the CLI no longer
/// takes fails here, not in a reader's terminal.
fn every_command_line_shown_parses(index: &Path, dir: &Path) {
    let page = std::fs::read_to_string(index).unwrap();
    let key = "<tr><td>CLI</td><td>";
    let lines: BTreeSet<String> = page
        .split(key)
        .skip(1)
        .map(|rest| {
            rest[..rest.find("</td>").unwrap()]
                .replace("&amp;", "&")
                .replace("&lt;", "<")
                .replace("&gt;", ">")
                .replace(" …", "")
        })
        .collect();
    assert!(lines.len() >= 20, "the CLI lines: {lines:?}");
    for line in &lines {
        assert!(
            !line.contains(['"', '\'', '&']),
            "a line to split by spaces: {line}"
        );
        let words: Vec<&str> = line.split_whitespace().collect();
        assert_eq!(words[0], "asperity", "{line}");
        let o = asperity(&[&words[1..], &["--help"]].concat(), dir);
        assert!(
            o.status.success(),
            "the gallery shows `{line}`, which the CLI refuses: {}",
            stderr(&o)
        );
    }
}
