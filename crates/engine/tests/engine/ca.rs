//! The `ca run` job's behaviour (peridier §2–3), tested here rather than
//! through the CLI (issue #36): one behaviour per test, through `CaRunParams`
//! as every front end builds them. Rule tables against Wolfram's codes and the
//! bit-sliced kernel against the byte-per-cell one are tested in `asperity-ca`.

use asperity_engine::ca::{CaRun, CaRunParams, run_job};
use asperity_engine::core::{MemoryBudget, NoProgress, TimeBudget};
use serde_json::{Value, json};

fn params(v: Value) -> CaRunParams {
    serde_json::from_value(v).expect("valid parameters")
}

fn run(p: &CaRunParams, keep_states: bool) -> Result<CaRun, String> {
    let (m, t) = (MemoryBudget::unlimited(), TimeBudget::unlimited());
    run_job(p, keep_states, 7, (&m, &t), &NoProgress).map_err(|e| e.to_string())
}

/// Rule 450 = 2⁸ + 2⁷ + 2⁶ + 2¹: a cell lives when its 3 × 3 sum is 1, 6, 7
/// or 8. From one cell every cell of its 3 × 3 block sees sum 1, so step 1
/// is that block; on an infinite background the region grows a cell a side a
/// step (5 steps: 11 × 11).
#[test]
fn rule_450_from_one_cell_grows_the_three_by_three_block() {
    let r = run(&params(json!({"rule": "450", "steps": 5})), true).unwrap();
    let (nx, ny) = (11, 11);
    assert_eq!(r.output.heights.dims(), [nx, ny]);
    let states = r.output.states.as_ref().expect("kept");
    assert_eq!(states.len(), 6 * nx * ny);
    let step1 = &states[nx * ny..2 * nx * ny];
    for j in 0..ny {
        for i in 0..nx {
            let block = (4..=6).contains(&i) && (4..=6).contains(&j);
            assert_eq!(step1[j * nx + i], u8::from(block), "step 1 at ({i}, {j})");
        }
    }
}

/// The height of a cell is the sum of its states over steps 0…T (weights 1,
/// values 0 and 1): peridier's accumulation.
#[test]
fn heights_are_the_sum_of_the_steps() {
    let r = run(&params(json!({"rule": "450", "steps": 5})), true).unwrap();
    let states = r.output.states.as_ref().unwrap();
    let h = &r.output.heights;
    let [nx, ny] = h.dims();
    for j in 0..ny {
        for i in 0..nx {
            let sum: u32 = (0..6)
                .map(|t| u32::from(states[(t * ny + j) * nx + i]))
                .sum();
            assert_eq!(*h.get(i, j), f64::from(sum), "cell ({i}, {j})");
        }
    }
}

/// Geometric weights R^t: with R = 1/2 a cell alive at every step of 3 has
/// height 1 + 1/2 + 1/4 + 1/8.
#[test]
fn decay_weights_step_t_by_r_to_the_t() {
    // Rule 511 (every sum lives) from a full grid: every cell alive throughout.
    let p = params(json!({
        "rule": "1022", "steps": 3, "init": "random:1", "size": [8, 8], "decay": 0.5
    }));
    let r = run(&p, false).unwrap();
    let h = &r.output.heights;
    assert!((*h.get(3, 3) - 1.875).abs() < 1e-12, "{}", h.get(3, 3));
}

#[test]
fn the_terrain_example_is_a_valid_run() {
    let p = CaRunParams::terrain_example();
    let again: CaRunParams = serde_json::from_value(serde_json::to_value(&p).unwrap()).unwrap();
    assert_eq!(again, p);
    let r = run(&p, false).unwrap();
    assert_eq!(r.output.heights.dims(), [64, 64]);
    let (lo, hi) = r.output.heights.min_max();
    assert!(hi > lo, "a relief, not a plateau");
}

#[test]
fn bad_runs_are_refused_naming_the_parameter() {
    for (v, needle) in [
        (json!({"rule": "1024", "steps": 5}), "out of range"),
        (json!({"rule": "450", "steps": 0}), "at least 1"),
        (
            json!({"rule": "450", "steps": 3, "init": "random:2", "size": [8, 8]}),
            "density",
        ),
        (
            json!({"rule": "300000", "family": "outer9", "steps": 3}),
            "out of range",
        ),
        (json!({"steps": 3}), "rule"),
        (
            json!({"rule": "450", "steps": 3, "size": [8, 8], "boundary": "infinite"}),
            "infinite",
        ),
    ] {
        let e = match serde_json::from_value::<CaRunParams>(v.clone()) {
            Err(e) => e.to_string(),
            Ok(p) => run(&p, false).err().unwrap_or_else(|| panic!("{v} ran")),
        };
        assert!(e.contains(needle), "{v}: {e}");
    }
}

/// A run no machine finishes within the time limit is refused before any
/// step, naming the estimate (#54: a billion steps of a 64² grid under 60 s).
#[test]
fn a_run_over_the_time_limit_is_refused_with_its_estimate() {
    let p = params(json!({"rule": 450, "steps": 1_000_000_000u64, "size": [64, 64]}));
    let m = MemoryBudget::unlimited();
    let t = TimeBudget::new(std::time::Duration::from_secs(60), 2);
    // (Were it not refused, the run would take minutes: the refusal comes
    // from the estimate, before any step.)
    let e = run_job(&p, false, 7, (&m, &t), &NoProgress)
        .unwrap_err()
        .to_string();
    assert!(e.contains("the CA evolution would take at least"), "{e}");
    assert!(e.contains("6.554e13 cell updates"), "{e}");
}
