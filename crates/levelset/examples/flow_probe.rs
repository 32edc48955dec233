//! Temporary probe: times the sparse flow on a point file (binary PLY of f64 xyz).
use asperity_core::NoProgress;
use asperity_levelset::evolve::EvolveParams;
use asperity_levelset::sparse::{sparse_distance, sparse_evolve, sparse_initial, sparse_tag};
use asperity_levelset::{GridSpec, Sizing, TagRule};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let data = std::fs::read(&args[1]).unwrap();
    let res: usize = args[2].parse().unwrap();
    let steps: usize = args.get(3).map_or(10, |s| s.parse().unwrap());
    let at = data.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    let pts: Vec<[f64; 3]> = data[at..]
        .chunks_exact(24)
        .map(|c| std::array::from_fn(|a| f64::from_le_bytes(c[8 * a..8 * a + 8].try_into().unwrap())))
        .collect();
    let grid = GridSpec::fitting(&pts, Sizing::Resolution(res), |h| ((6.0 * h) / h).ceil() as usize + 3).unwrap();
    let h = grid.spacing;
    let (eps, gamma) = (3.0 * h, 3.0 * h);
    let t = Instant::now();
    let (mut d, spacing) = sparse_distance(&pts, &grid, eps + gamma + 2.0 * h, &NoProgress);
    eprintln!("distance {:.2} s ({} of {} bricks)", t.elapsed().as_secs_f64(), d.bricks.slots(), d.bricks.brick_count());
    if std::env::var_os("STOP_AFTER_DISTANCE").is_some() {
        return;
    }
    let t = Instant::now();
    let mut tags = sparse_tag(&mut d, eps, TagRule::Paper, &NoProgress);
    eprintln!("tagging {:.2} s", t.elapsed().as_secs_f64());
    let t = Instant::now();
    let ls = sparse_initial(&mut d, &mut tags, eps, gamma, &NoProgress);
    eprintln!("initial {:.2} s", t.elapsed().as_secs_f64());
    let params = EvolveParams {
        iterations: steps,
        arrest: (0.75 * spacing.unwrap_or(0.0)).max(0.6 * h),
        neighbourhood: asperity_levelset::Neighbourhood::Axes,
        ..EvolveParams::paper(h)
    };
    let mut best = f64::MAX;
    for _ in 0..3 {
        let (mut l, mut dd) = (ls.clone(), d.clone());
        let t = Instant::now();
        sparse_evolve(&mut l, &mut dd, &params, &NoProgress, &mut |_, _| {});
        best = best.min(t.elapsed().as_secs_f64());
    }
    eprintln!("flow {steps} steps: best {:.3} s ({:.1} ms/step)", best, best * 1e3 / steps as f64);
    let t = Instant::now();
    let (mesh, _) = ls.extract(&Default::default());
    eprintln!("extract (initial) {:.2} s, {} triangles", t.elapsed().as_secs_f64(), mesh.n_faces());
}
