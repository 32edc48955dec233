//! Outputs committed together, their folders, symlinks and special files (#20). One test
//! binary of its own: a transaction is process-wide.

use std::path::Path;

use asperity_io::{Transaction, write_text};

fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn outputs_are_committed_together_links_followed_and_fifos_kept() {
    let d = tempfile::tempdir().unwrap();
    let (a, b) = (d.path().join("a.txt"), d.path().join("b.txt"));
    std::fs::write(&a, "old a").unwrap();

    // Uncommitted: nothing changes, nothing is left behind.
    let tx = Transaction::begin();
    write_text(&a, "new a").unwrap();
    write_text(&b, "new b").unwrap();
    assert_eq!(std::fs::read_to_string(&a).unwrap(), "old a");
    assert!(!b.exists());
    assert_eq!(
        asperity_io::staging::written_len(&a),
        Some(5),
        "the staged size, not the old file's"
    );
    let anonymous = asperity_io::staging::stages_anonymously(d.path());
    if anonymous {
        // Staged anonymously: nothing in the folder has a name yet.
        assert_eq!(names(d.path()), vec!["a.txt"]);
    } else {
        eprintln!("skipped: anonymous staging (no O_TMPFILE here); named staging tested");
        assert_eq!(names(d.path()).len(), 3, "{:?}", names(d.path()));
    }
    drop(tx);
    assert_eq!(names(d.path()), vec!["a.txt"]);
    assert_eq!(std::fs::read_to_string(&a).unwrap(), "old a");

    // Committed: both in place.
    let tx = Transaction::begin();
    write_text(&a, "new a").unwrap();
    write_text(&b, "new b").unwrap();
    tx.commit().unwrap();
    assert_eq!(std::fs::read_to_string(&a).unwrap(), "new a");
    assert_eq!(std::fs::read_to_string(&b).unwrap(), "new b");
    assert_eq!(names(d.path()), vec!["a.txt", "b.txt"]);

    // Without a transaction a write lands at once.
    write_text(&b, "b again").unwrap();
    assert_eq!(std::fs::read_to_string(&b).unwrap(), "b again");

    #[cfg(unix)]
    {
        // A symlink's target is written; the link stays a link.
        let link = d.path().join("link.txt");
        std::os::unix::fs::symlink("a.txt", &link).unwrap();
        write_text(&link, "through the link").unwrap();
        assert!(
            std::fs::symlink_metadata(&link)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        assert_eq!(std::fs::read_to_string(&a).unwrap(), "through the link");

        // A FIFO is written in place, not replaced by a regular file.
        let fifo = d.path().join("pipe");
        let ok = std::process::Command::new("mkfifo").arg(&fifo).status();
        if ok.is_ok_and(|s| s.success()) {
            let reader = {
                let fifo = fifo.clone();
                std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
            };
            write_text(&fifo, "streamed").unwrap();
            assert_eq!(reader.join().unwrap(), "streamed");
            use std::os::unix::fs::FileTypeExt;
            assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
        }
    }

    // Folders made for the outputs of a failed command are removed; a
    // committed one keeps them.
    let plots = d.path().join("plots/deep");
    let tx = Transaction::begin();
    asperity_io::create_output_dir(&plots).unwrap();
    assert!(plots.is_dir());
    drop(tx);
    assert!(!d.path().join("plots").exists(), "an empty folder was left");
    let tx = Transaction::begin();
    asperity_io::create_output_dir(&plots).unwrap();
    write_text(&plots.join("p.svg"), "<svg/>").unwrap();
    tx.commit().unwrap();
    assert_eq!(names(&plots), vec!["p.svg"]);

    an_output_that_is_an_input_is_refused(d.path());
    if anonymous {
        more_outputs_than_open_files(&d.path().join("frames"));
    }
}

/// Beyond [`asperity_io::staging::ANONYMOUS_STAGED`] anonymous files a
/// transaction names the later ones at once (a long turntable would run out
/// of file handles), and commits every one.
fn more_outputs_than_open_files(dir: &Path) {
    use asperity_io::staging::ANONYMOUS_STAGED;
    std::fs::create_dir(dir).unwrap();
    let path = |i: usize| dir.join(format!("f{i:04}.txt"));
    let tx = Transaction::begin();
    for i in 0..ANONYMOUS_STAGED + 3 {
        write_text(&path(i), &format!("frame {i}")).unwrap();
    }
    let staged = names(dir);
    assert_eq!(staged.len(), 3, "{staged:?}");
    assert!(
        staged
            .iter()
            .all(|n| n.starts_with(".f02") && n.ends_with(".tmp"))
    );
    // The written size is known either way.
    assert_eq!(asperity_io::staging::written_len(&path(0)), Some(7));
    assert_eq!(
        asperity_io::staging::written_len(&path(ANONYMOUS_STAGED + 2)),
        Some(9)
    );
    tx.commit().unwrap();
    let all = names(dir);
    assert_eq!(all.len(), ANONYMOUS_STAGED + 3, "{:?}", &all[..5]);
    for i in [
        0,
        1,
        ANONYMOUS_STAGED - 1,
        ANONYMOUS_STAGED,
        ANONYMOUS_STAGED + 2,
    ] {
        assert_eq!(
            std::fs::read_to_string(path(i)).unwrap(),
            format!("frame {i}")
        );
    }
}

/// Inside a transaction (a command), an output that is a file the command
/// read — by its name, a symlink to it or a hard link — is refused naming
/// both, and the input is left byte for byte; outside one (a library call)
/// nothing is noted. Run from the test above: a transaction is process-wide.
fn an_output_that_is_an_input_is_refused(dir: &Path) {
    let input = dir.join("in.xyz");
    std::fs::write(&input, "0 0 0\n1 0 0\n0 1 1\n").unwrap();
    let before = std::fs::read(&input).unwrap();
    let refused = |out: &Path| {
        let s = asperity_io::read(&input).unwrap();
        let asperity_io::Surface::Points(p) = s else {
            panic!("points")
        };
        let e = asperity_io::write_points(out, &p, &Default::default()).unwrap_err();
        let m = e.to_string();
        assert!(m.contains("is the input") && m.contains("in.xyz"), "{m}");
        assert_eq!(std::fs::read(&input).unwrap(), before);
    };
    let tx = Transaction::begin();
    refused(&input);
    #[cfg(unix)]
    {
        let link = dir.join("link.xyz");
        std::os::unix::fs::symlink("in.xyz", &link).unwrap();
        refused(&link);
        let hard = dir.join("hard.xyz");
        std::fs::hard_link(&input, &hard).unwrap();
        refused(&hard);
    }
    // Another file is written as usual.
    let other = dir.join("other.xyz");
    let s = asperity_io::read(&input).unwrap();
    let asperity_io::Surface::Points(p) = s else {
        panic!("points")
    };
    asperity_io::write_points(&other, &p, &Default::default()).unwrap();
    tx.commit().unwrap();
    assert!(other.exists());
    // Outside a transaction the caller decides.
    asperity_io::read(&input).unwrap();
    asperity_io::write_points(&input, &p, &Default::default()).unwrap();
}
