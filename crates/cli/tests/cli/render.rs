//! `render` and `bench`.

use super::*;

#[test]
fn render_command() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(
        d.path().join("h.csv"),
        "0,1,2,3\n1,2,3,4\n2,3,4,5.5\n3,4,5,6\n",
    )
    .unwrap();
    let o = asperity(
        &[
            "render", "h.csv", "-o", "v.png", "--size", "160x120", "--view", "top", "--shader",
            "height",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let img = asperity_io::read_height(&d.path().join("v.png")).unwrap();
    assert_eq!(img.dims(), [160, 120]);
    let o = asperity(
        &["render", "h.csv", "-o", "m.png", "--view", "map"],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = asperity(
        &[
            "render",
            "h.csv",
            "-o",
            "t.png",
            "--size",
            "64x48",
            "--turntable",
            "3",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    for k in 0..3 {
        assert!(d.path().join(format!("t_{k:03}.png")).exists());
    }
    fails(
        d.path(),
        &["render", "h.csv", "-o", "v.png", "--size", "0x10"],
        "--size must be in [1, 1048576], got 0",
    );
    fails(
        d.path(),
        &["render", "h.csv", "-o", "v.png", "--size", "big"],
        "WIDTHxHEIGHT",
    );
    fails(d.path(), &["render", "h.csv", "-o", "v.jpg"], "PNG");
    fails(
        d.path(),
        &["render", "h.csv", "-o", "v.png", "--shader", "texture"],
        "UVs and a texture",
    );
    std::fs::write(d.path().join("p.xyz"), "0 0 0\n1 0 0\n0 1 1\n").unwrap();
    fails(
        d.path(),
        &["render", "p.xyz", "-o", "v.png", "--view", "map"],
        "need a height field",
    );
    let o = asperity(
        &["render", "p.xyz", "-o", "p.png", "--size", "100x80"],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn bench_runs_every_workload() {
    let d = tempfile::tempdir().unwrap();
    let o = asperity(&["--json", "bench", "--quick", "--repeat", "1"], d.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let w = v["measurements"]["workloads"].as_array().unwrap();
    assert_eq!(w.len(), 28);
    assert!(v["measurements"]["ca_bits_over_bytes"].as_f64().unwrap() > 1.0);
    assert!(
        w.iter()
            .all(|x| x["median_s"].as_f64().unwrap() > 0.0
                && x["per_second"].as_f64().unwrap() > 0.0)
    );
    fails(
        d.path(),
        &["bench", "--quick", "nothing-matches"],
        "no workload matches",
    );
    // --scaling: every method's doubling series, each point in its own process
    let o = asperity(
        &["--json", "bench", "--scaling", "all", "--quick"],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let table = v["measurements"]["scaling"].as_array().unwrap();
    assert_eq!(table.len(), 9, "every method");
    for m in table {
        let points = m["points"].as_array().unwrap();
        assert!(points.len() >= 5, "{m}");
        let elements: Vec<f64> = points
            .iter()
            .map(|p| p["elements"].as_f64().unwrap())
            .collect();
        assert!(elements.windows(2).all(|w| w[1] > w[0]), "{m}");
        assert!(
            points
                .iter()
                .all(|p| p["seconds"].as_f64().unwrap() > 0.0
                    && p["peak_bytes"].as_f64().unwrap() > 1e6),
            "{m}"
        );
        assert!(m["time_slope"].as_f64().is_some(), "{m}");
    }
    fails(d.path(), &["bench", "--scaling", "nope"], "no such method");
    // --background-load: DLA's walkers timed at 1 and 2 threads on a busy
    // machine; the loops are gone when the bench ends.
    #[cfg(unix)]
    {
        let loops = || {
            let ps = std::process::Command::new("ps")
                .args(["-eo", "args"])
                .output();
            ps.map_or(0, |o| {
                String::from_utf8_lossy(&o.stdout)
                    .lines()
                    .filter(|l| l.starts_with("sh -c while :; do :; done"))
                    .count()
            })
        };
        let before = loops();
        let o = asperity(
            &[
                "--json",
                "--threads",
                "2",
                "bench",
                "--threads-scaling",
                "--background-load",
                "--quick",
                "--repeat",
                "1",
                "growth/dla-point",
            ],
            d.path(),
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        assert_eq!(v["measurements"]["background_load"]["loops"], cores);
        let w = v["measurements"]["workloads"].as_array().unwrap();
        assert!(
            !w.is_empty()
                && w.iter()
                    .all(|w| w["threads_scaling"].as_array().unwrap().len() == 2)
        );
        assert_eq!(loops(), before, "the background loops were left running");
    }
    // --threads-scaling: 1, 2, 4 threads up to --threads, the speed-up over one.
    let o = asperity(
        &[
            "--json",
            "--threads",
            "5",
            "bench",
            "--threads-scaling",
            "--quick",
            "--repeat",
            "1",
            "core/fourier",
        ],
        d.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for w in v["measurements"]["workloads"].as_array().unwrap() {
        let rows = w["threads_scaling"].as_array().unwrap();
        let threads: Vec<u64> = rows
            .iter()
            .map(|r| r["threads"].as_u64().unwrap())
            .collect();
        assert_eq!(threads, [1, 2, 4, 5], "{w}");
        assert_eq!(rows[0]["speedup"], 1.0);
        for r in rows {
            let (s, e) = (
                r["speedup"].as_f64().unwrap(),
                r["efficiency"].as_f64().unwrap(),
            );
            let t = r["threads"].as_f64().unwrap();
            assert!(s > 0.0 && (e - s / t).abs() < 1e-12, "{r}");
        }
    }
}
