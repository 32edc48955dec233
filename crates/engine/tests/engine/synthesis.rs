//! `generate fbm`: the self-affine surfaces the analysis is checked on
//! (Jacobs, Junge & Pastewka 2017, §2.3). Their spectrum against the
//! analysis' estimators is in `analyze.rs`; here, the job's own promises.

use asperity_engine::core::MemoryBudget;
use asperity_engine::synthesis::{FbmParams, fbm};

fn params(size: usize) -> FbmParams {
    FbmParams {
        size,
        hurst: 0.6,
        rms: 2.5,
        spacing: 0.5,
    }
}

/// Zero mean and exactly the rms asked for, on an N × N grid of the spacing.
#[test]
fn the_field_has_the_rms_and_spacing_asked_for() {
    let h = fbm(&params(128), 5, &MemoryBudget::unlimited()).unwrap();
    assert_eq!(h.dims(), [128, 128]);
    assert_eq!(h.spacing(), [0.5, 0.5]);
    let n = (128 * 128) as f64;
    let mean = h.mean();
    let rms = (h.data().iter().map(|z| (z - mean).powi(2)).sum::<f64>() / n).sqrt();
    assert!(
        mean.abs() < 1e-9 && (rms - 2.5).abs() < 1e-9,
        "mean {mean}, rms {rms}"
    );
}

/// The same seed gives the same field whatever the thread count; another
/// seed another field.
#[test]
fn the_seed_alone_decides_the_field() {
    let with_threads = |threads: usize, seed: u64| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| fbm(&params(96), seed, &MemoryBudget::unlimited()).unwrap())
    };
    let one = with_threads(1, 9);
    assert_eq!(one, with_threads(2, 9));
    assert_eq!(one, with_threads(5, 9));
    assert_ne!(one, with_threads(2, 10));
}

#[test]
fn a_field_over_the_budget_is_refused_with_the_estimate() {
    let e = fbm(&params(8192), 5, &MemoryBudget::new(1 << 20)).unwrap_err();
    assert!(e.to_string().contains("memory"), "{e}");
}
