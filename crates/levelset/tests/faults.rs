//! Mutation test of the oracle (issue #36): each fault of
//! `asperity_levelset::faults` breaks a kernel that the sparse and the dense
//! stages share. The comparison with the independent reference must then
//! fail, while the sparse flow still equals the dense one bit for bit — which
//! is why sparse-equals-dense alone could not catch it.
//!
//! Needs the feature: `cargo test -p asperity-levelset --features
//! fault-injection --test faults` (`.ci/run` runs it).

mod common;

use std::sync::Mutex;

use asperity_core::NoProgress;
use asperity_levelset::faults::{Fault, inject};
use asperity_levelset::sparse::sparse_distance;
use asperity_levelset::{DistanceMethod, unsigned_distance};
use common::*;

/// One fault at a time: they are process-wide.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

#[test]
fn the_oracle_passes_without_a_fault() {
    let _alone = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let (pts, p) = (bumpy_sphere(), params());
    let s = setup(&pts, &p);
    check_distance(&pts, &s).unwrap();
    check_flow(&flow_gap(&pts, &s, &p, 6)).unwrap();
}

#[test]
fn a_broken_flow_kernel_fails_the_oracle_but_not_sparse_equals_dense() {
    let _alone = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let (pts, p) = (bumpy_sphere(), params());
    let s = setup(&pts, &p);
    for fault in [Fault::UpwindSide, Fault::EnoSign, Fault::RedistanceStep] {
        let _on = inject(fault);
        let g = flow_gap(&pts, &s, &p, 6);
        eprintln!("{fault:?}: φ {:.2e} cells, dense {:.1e}", g.phi, g.dense);
        assert_eq!(g.dense, 0.0, "{fault:?}: sparse and dense share the kernel");
        assert!(check_flow(&g).is_err(), "{fault:?} went unnoticed");
    }
}

#[test]
fn a_broken_distance_kernel_fails_the_oracle() {
    let _alone = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let (pts, p) = (crop_of_a_deposit(), params());
    let s = setup(&pts, &p);
    let _on = inject(Fault::AxisSquares);
    eprintln!("AxisSquares: {:?}", distance_errors(&pts, &s));
    assert!(
        check_distance(&pts, &s).is_err(),
        "AxisSquares went unnoticed"
    );
    // The dense wavefront shares the kernel: it agrees with the sparse one.
    let dense = unsigned_distance(
        &pts,
        &s.grid,
        DistanceMethod::ClosestPoint,
        s.cap,
        &NoProgress,
    );
    let (sparse, _) = sparse_distance(&pts, &s.grid, s.cap, &NoProgress);
    let differ = (0..s.grid.len())
        .filter(|&u| sparse.at(s.grid.coords(u)) != dense.values[u])
        .count();
    assert_eq!(differ, 0, "sparse and dense share the broken kernel");
}
