//! The sparse stages against an independent reference
//! (`asperity_levelset::reference`: plain `f64` loops written from the
//! paper's equations, sharing no kernel with the optimised stages), on inputs
//! they were not tuned on: a non-periodic crop of a DLA deposit and a bumpy
//! sphere sampled unevenly, off the grid's axes. `faults.rs` shows these
//! checks fail when a shared kernel is broken.

mod common;

use common::*;

#[test]
fn the_distance_is_the_exact_distance_to_the_points() {
    let p = params();
    for (name, pts) in [("deposit", crop_of_a_deposit()), ("sphere", bumpy_sphere())] {
        let s = setup(&pts, &p);
        eprintln!("{name}: {:?}", distance_errors(&pts, &s));
        check_distance(&pts, &s).unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

#[test]
fn the_flow_follows_the_reference_step_for_step() {
    let p = params();
    for (name, pts) in [("deposit", crop_of_a_deposit()), ("sphere", bumpy_sphere())] {
        let s = setup(&pts, &p);
        for steps in [1, 4, 20] {
            let g = flow_gap(&pts, &s, &p, steps);
            eprintln!(
                "{name}, {steps} steps: φ {:.2e} cells, dt {:.1e}, dense {:.1e}",
                g.phi, g.dt, g.dense
            );
            assert_eq!(
                g.dense, 0.0,
                "{name}: the sparse flow is the dense one, bit for bit"
            );
            check_flow(&g).unwrap_or_else(|e| panic!("{name}, {steps} steps: {e}"));
        }
    }
}
