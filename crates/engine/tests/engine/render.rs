//! The render job's estimate: the scene counts, not only the frame buffers.

use asperity_engine::core::{HeightField, MemoryBudget, TimeBudget};
use asperity_engine::io::Surface;
use asperity_engine::render::{RenderParams, render_job, scene_bytes};

/// A 2048² height field (some 8 million triangles to shade, 840 MB of
/// scene by the estimate) is refused under 400 MB before any frame; the
/// scene's bytes grow with the samples.
#[test]
fn a_scene_over_the_budget_is_refused_first() {
    let h = HeightField::from_vec([2048, 2048], vec![0.0; 2048 * 2048]).unwrap();
    let s = Surface::Height(h);
    let e = render_job(
        &s,
        &RenderParams::default(),
        (0, 1),
        (&MemoryBudget::new(400 << 20), &TimeBudget::unlimited()),
    )
    .unwrap_err();
    assert!(e.to_string().contains("the scene to render"), "{e}");
    let small = Surface::Height(HeightField::from_vec([64, 64], vec![0.0; 64 * 64]).unwrap());
    assert_eq!(scene_bytes(&s), 1024 * scene_bytes(&small));
}
