//! `reconstruct` on clouds nobody here made (#52): random samples of surfaces
//! drawn per run (the surface, the count and the seed), noise, outliers, a
//! hole, a simulated range scan with its occlusion holes, an open patch —
//! with the job's defaults, as `asperity reconstruct IN -o OUT` runs them —
//! against the surfaces' analytic geometry: genus, area, distance, curvature.

use std::f64::consts::{PI, TAU};

use asperity_engine::core::{MemoryBudget, NoProgress, TimeBudget};
use asperity_engine::reconstruct::{Job, LevelSetParams, Surface, pieces, reconstruct_job};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

/// The job with these parameters over the defaults.
fn reconstruct(points: &[[f64; 3]], params: Value) -> Surface {
    let p: LevelSetParams = serde_json::from_value(params).expect("valid parameters");
    reconstruct_job(
        points.into(),
        (&p, Job::Reconstruct),
        (&MemoryBudget::unlimited(), &TimeBudget::unlimited()),
        &NoProgress,
        &mut |_, _| {},
    )
    .expect("reconstructed")
}

fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let (u, v): (f64, f64) = (rng.random(), rng.random());
    (-2.0 * (1.0 - u).ln()).sqrt() * (TAU * v).cos()
}

/// The surfaces drawn: an implicit f (negative inside) whose gradient has no
/// zero near the surface, its analytic area, and its genus.
#[derive(Clone, Copy, Debug)]
enum Shape {
    Sphere,
    /// R = 1, r = 0.35.
    Torus,
    /// Semi-axes 1, 0.7, 0.5.
    Ellipsoid,
    /// Two tori (R = 0.6, r = 0.25) side by side, overlapping: genus 2.
    DoubleTorus,
}

const AXES: [f64; 3] = [1.0, 0.7, 0.5];

impl Shape {
    fn genus(self) -> i64 {
        match self {
            Shape::Sphere | Shape::Ellipsoid => 0,
            Shape::Torus => 1,
            Shape::DoubleTorus => 2,
        }
    }

    /// A point on the surface, uniform by area (rejection on the parameter
    /// domain's area element), or, for the double torus, a point of a torus
    /// that the other does not swallow.
    fn sample(self, rng: &mut ChaCha8Rng) -> [f64; 3] {
        loop {
            match self {
                Shape::Sphere => {
                    let v: [f64; 3] = std::array::from_fn(|_| gaussian(rng));
                    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    return v.map(|x| x / n);
                }
                Shape::Torus => {
                    let (u, w, s): (f64, f64, f64) = (rng.random(), rng.random(), rng.random());
                    let (u, w) = (TAU * u, TAU * w);
                    if s * 1.35 <= 1.0 + 0.35 * w.cos() {
                        let q = 1.0 + 0.35 * w.cos();
                        return [q * u.cos(), q * u.sin(), 0.35 * w.sin()];
                    }
                }
                Shape::Ellipsoid => {
                    let v: [f64; 3] = std::array::from_fn(|_| gaussian(rng));
                    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    let p: [f64; 3] = std::array::from_fn(|a| AXES[a] * v[a] / n);
                    // The area element of x = A·u on the unit sphere is
                    // |A⁻ᵀu|·det A: accept by it.
                    let g = (0..3)
                        .map(|a| (v[a] / n / AXES[a]).powi(2))
                        .sum::<f64>()
                        .sqrt();
                    if rng.random::<f64>() * (1.0 / AXES[2]) <= g {
                        return p;
                    }
                }
                Shape::DoubleTorus => {
                    let (u, w, s): (f64, f64, f64) = (rng.random(), rng.random(), rng.random());
                    let (u, w) = (TAU * u, TAU * w);
                    if s * 0.85 > 0.6 + 0.25 * w.cos() {
                        continue;
                    }
                    let q = 0.6 + 0.25 * w.cos();
                    let side = if rng.random::<bool>() { 0.7 } else { -0.7 };
                    let p = [side + q * u.cos(), q * u.sin(), 0.25 * w.sin()];
                    let other = [p[0] + side, p[1], p[2]];
                    if torus_f(other, 0.6, 0.25) > 0.0 {
                        return p;
                    }
                }
            }
        }
    }

    /// The distance of `p` to the surface (exact for the sphere and tori,
    /// |f|/|∇f| to first order for the ellipsoid).
    fn distance(self, p: [f64; 3]) -> f64 {
        match self {
            Shape::Sphere => ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 1.0).abs(),
            Shape::Torus => torus_f(p, 1.0, 0.35).abs(),
            Shape::Ellipsoid => {
                let f = (0..3).map(|a| (p[a] / AXES[a]).powi(2)).sum::<f64>() - 1.0;
                let g = (0..3)
                    .map(|a| (2.0 * p[a] / AXES[a].powi(2)).powi(2))
                    .sum::<f64>();
                f.abs() / g.sqrt()
            }
            Shape::DoubleTorus => {
                let a = torus_f([p[0] - 0.7, p[1], p[2]], 0.6, 0.25);
                let b = torus_f([p[0] + 0.7, p[1], p[2]], 0.6, 0.25);
                a.min(b).abs()
            }
        }
    }

    /// The scale of the 1 % criterion: the radius, the tube radius, the
    /// smallest semi-axis.
    fn radius(self) -> f64 {
        match self {
            Shape::Sphere => 1.0,
            Shape::Torus => 0.35,
            Shape::Ellipsoid => AXES[2],
            Shape::DoubleTorus => 0.25,
        }
    }

    /// The analytic area (the ellipsoid's by quadrature of its area element;
    /// none for the double torus).
    fn area(self) -> Option<f64> {
        match self {
            Shape::Sphere => Some(4.0 * PI),
            Shape::Torus => Some(4.0 * PI * PI * 0.35),
            Shape::Ellipsoid => {
                let n = 2000;
                let mut a = 0.0;
                for i in 0..n {
                    let t = PI * (i as f64 + 0.5) / n as f64;
                    for j in 0..2 * n {
                        let f = PI * (j as f64 + 0.5) / n as f64;
                        let u = [t.sin() * f.cos(), t.sin() * f.sin(), t.cos()];
                        let g = (0..3).map(|k| (u[k] / AXES[k]).powi(2)).sum::<f64>().sqrt();
                        a += g * t.sin();
                    }
                }
                Some(a * AXES.iter().product::<f64>() * (PI / n as f64).powi(2))
            }
            Shape::DoubleTorus => None,
        }
    }
}

/// The signed distance to a torus of radii `big`, `small` about the z axis.
fn torus_f(p: [f64; 3], big: f64, small: f64) -> f64 {
    let q = (p[0] * p[0] + p[1] * p[1]).sqrt() - big;
    (q * q + p[2] * p[2]).sqrt() - small
}

fn cloud(shape: Shape, n: usize, seed: u64) -> Vec<[f64; 3]> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n).map(|_| shape.sample(&mut rng)).collect()
}

/// One watertight piece of `genus`.
fn assert_closed(s: &Surface, genus: i64, what: &str) {
    let t = s.rec.mesh.topology();
    assert!(t.is_watertight(), "{what}: not watertight");
    assert_eq!(pieces(&s.rec), 1, "{what}: pieces");
    assert_eq!(t.genus, Some(genus), "{what}: genus");
}

fn relative_area(s: &Surface, area: f64) -> f64 {
    s.rec.mesh.area() / area - 1.0
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 6, failure_persistence: None, ..ProptestConfig::default() })]

    /// A random sample of a sphere, torus, ellipsoid or double torus, of any
    /// count from 5,000 to 30,000 (typical spacing up to about 1.5h at the
    /// default 128 cells): one watertight piece of the surface's genus, the
    /// area within 2 %, every vertex within h/2 (3h at the double torus's
    /// crease) and, for the smooth shapes, 1 % of the radius.
    #[test]
    fn random_samples_give_their_surface(
        shape in prop_oneof![
            Just(Shape::Sphere), Just(Shape::Torus), Just(Shape::Ellipsoid), Just(Shape::DoubleTorus)
        ],
        n in 5_000usize..30_000,
        seed in any::<u64>(),
    ) {
        let s = reconstruct(&cloud(shape, n, seed), json!({}));
        let what = format!("{shape:?}, {n} points, seed {seed}");
        assert_closed(&s, shape.genus(), &what);
        assert_eq!(s.rec.flow, asperity_engine::methods::levelset::FlowChoice::Zhao, "{what}");
        if let Some(area) = shape.area() {
            let a = relative_area(&s, area);
            prop_assert!(a.abs() < 0.02, "{what}: area {a:+.4}");
        }
        // Every vertex within half a cell; within 1 % of the radius too for
        // the sphere, and for the torus at 20,000 points and more (the
        // issue's are 50,000 and 200,000): its tube of 0.35 is 17 cells, and
        // 1 % is a sixth of a cell. The double torus has a concave crease
        // where the two tori meet (the plane x = 0), which no quadric follows
        // and a surface smooth at the scale of h fills: within 3h where the
        // two tubes overlap, |x| < 0.15 (of 60 random draws the worst was
        // 1.1h; one of 5,000 points, 1.7h; a band of |x| < 0.1 left out a
        // vertex at x = 0.105, 0.54h off, with 5,581 points).
        let (crease, smooth): (Vec<[f64; 3]>, Vec<[f64; 3]>) = s.rec.mesh.positions().iter()
            .partition(|p| matches!(shape, Shape::DoubleTorus) && p[0].abs() < 0.15);
        let far = |v: &[[f64; 3]]| v.iter().map(|&p| shape.distance(p)).fold(0.0, f64::max);
        let (worst, worst_crease) = (far(&smooth), far(&crease));
        let h = s.rec.grid.spacing;
        prop_assert!(worst < 0.5 * h, "{what}: a vertex {worst} off ({}h)", worst / h);
        prop_assert!(worst_crease < 3.0 * h, "{what}: a crease vertex {worst_crease} off ({}h)", worst_crease / h);
        if matches!(shape, Shape::Sphere) || (matches!(shape, Shape::Torus) && n >= 20_000) {
            prop_assert!(worst < 0.01 * shape.radius(), "{what}: a vertex {worst} off ({}h)", worst / h);
        }
    }
}

/// Gaussian noise of half and one typical spacing per coordinate: one piece,
/// the genus, the area within 5 %.
#[test]
fn noise_keeps_the_topology_and_the_area() {
    for (shape, n) in [(Shape::Sphere, 20_000), (Shape::Torus, 50_000)] {
        let clean = cloud(shape, n, 11);
        let s0 = reconstruct(&clean, json!({}));
        let spacing = s0.rec.cloud.spacing.expect("measured");
        for k in [0.5, 1.0] {
            let mut rng = ChaCha8Rng::seed_from_u64(12);
            let noisy: Vec<[f64; 3]> = clean
                .iter()
                .map(|p| p.map(|x| x + k * spacing * gaussian(&mut rng)))
                .collect();
            let s = reconstruct(&noisy, json!({}));
            let what = format!("{shape:?} with noise σ = {k} spacing");
            assert_closed(&s, shape.genus(), &what);
            let a = relative_area(&s, shape.area().unwrap());
            assert!(a.abs() < 0.05, "{what}: area {a:+.4}");
        }
    }
}

/// 2 % of the points uniform in the bounding box: one piece of the genus.
#[test]
fn outliers_leave_one_piece() {
    for (shape, n, half) in [
        (Shape::Sphere, 20_000, [1.0, 1.0, 1.0]),
        (Shape::Torus, 50_000, [1.35, 1.35, 0.35]),
    ] {
        let mut pts = cloud(shape, n, 21);
        let mut rng = ChaCha8Rng::seed_from_u64(22);
        pts.extend(
            (0..n / 50)
                .map(|_| std::array::from_fn(|a| (rng.random::<f64>() * 2.0 - 1.0) * half[a])),
        );
        let s = reconstruct(&pts, json!({}));
        assert_closed(&s, shape.genus(), &format!("{shape:?} with 2 % outliers"));
        assert!(
            s.rec.cloud.outliers > n / 100,
            "outliers dropped: {}",
            s.rec.cloud.outliers
        );
    }
}

/// A sphere with a cap five spacings across removed: closed, genus 0, the
/// patch within 2 % of the radius; asked to stay open, it keeps a boundary.
#[test]
fn a_hole_is_closed_or_kept_open() {
    let all = cloud(Shape::Sphere, 20_000, 31);
    let spacing = reconstruct(&all, json!({})).rec.cloud.spacing.unwrap();
    let cap = 2.5 * spacing;
    let pts: Vec<[f64; 3]> = all.into_iter().filter(|p| p[2] < cap.cos()).collect();
    let s = reconstruct(&pts, json!({}));
    assert_closed(&s, 0, "holed sphere");
    for p in s.rec.mesh.positions() {
        if p[2] > (2.0 * cap).cos() {
            let r = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            assert!((r - 1.0).abs() < 0.02, "patch at radius {r}");
        }
    }
    assert!(s.quality.holes.count >= 1, "{:?}", s.quality.holes);
    let open = reconstruct(&pts, json!({"open": true}));
    let t = open.rec.mesh.topology();
    assert!(t.boundary_loops >= 1 && !t.is_watertight(), "{t:?}");
}

/// A torus scanned by sphere tracing from six scanners around it: density
/// falling off with the angle, overlapping views, occlusion holes (the inner
/// ring is hidden from most views). One watertight piece of genus 1;
/// `--open` leaves the unscanned parts open.
#[test]
fn a_simulated_range_scan_closes_to_its_genus() {
    let mut pts = Vec::new();
    // Six views around, alternately above and below.
    for view in 0..6 {
        let az = TAU * view as f64 / 6.0;
        let e: [f64; 3] = [
            4.0 * az.cos(),
            4.0 * az.sin(),
            if view % 2 == 0 { 2.0 } else { -1.5 },
        ];
        let el = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
        let fwd = e.map(|x| -x / el);
        let right = {
            let r = [fwd[1], -fwd[0], 0.0];
            let l = (r[0] * r[0] + r[1] * r[1]).sqrt();
            r.map(|x| x / l)
        };
        let up = [
            right[1] * fwd[2] - right[2] * fwd[1],
            right[2] * fwd[0] - right[0] * fwd[2],
            right[0] * fwd[1] - right[1] * fwd[0],
        ];
        let n = 160;
        for i in 0..n {
            for j in 0..n {
                let (a, b) = (
                    0.4 * (i as f64 / n as f64 - 0.5),
                    0.4 * (j as f64 / n as f64 - 0.5),
                );
                let d: [f64; 3] = std::array::from_fn(|k| fwd[k] + a * right[k] + b * up[k]);
                let dl = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                let d = d.map(|x| x / dl);
                let mut t = 0.0;
                for _ in 0..200 {
                    let p: [f64; 3] = std::array::from_fn(|k| e[k] + t * d[k]);
                    let f = torus_f(p, 1.0, 0.35);
                    if f < 1e-7 {
                        pts.push(p);
                        break;
                    }
                    t += f;
                    if t > 10.0 {
                        break;
                    }
                }
            }
        }
    }
    let s = reconstruct(&pts, json!({}));
    assert_closed(&s, 1, "scanned torus");
    let open = reconstruct(&pts, json!({"open": true}));
    assert!(open.quality.holes.removed, "{:?}", open.quality.holes);
    assert!(!open.rec.mesh.topology().is_watertight());
}

/// `--curvature` on 20,000 random points of the unit sphere, every flow: the
/// median H within 3 % of 1 and 90 % of the vertices within 15 %, at a scale
/// of at least three spacings; on the torus (every flow), ∫K dA ≈ 0
/// (Gauss–Bonnet, genus 1) and K at the outer and inner equators within 5 % of
/// 1/(r(R ± r)).
#[test]
fn curvature_is_the_surfaces_for_every_flow() {
    let sphere = cloud(Shape::Sphere, 20_000, 41);
    let torus = cloud(Shape::Torus, 50_000, 42);
    for flow in ["zhao", "convection", "regularized"] {
        let s = reconstruct(&sphere, json!({"curvature": true, "flow": flow}));
        let scale = s.quality.curvature_scale.expect("stated");
        assert!(scale >= 3.0 * s.rec.cloud.spacing.unwrap(), "{flow}");
        let mut h = s.rec.mesh.scalar("mean_curvature").unwrap().to_vec();
        h.sort_by(f64::total_cmp);
        let median = h[h.len() / 2];
        let within = h.iter().filter(|x| (**x - 1.0).abs() < 0.15).count() as f64 / h.len() as f64;
        assert!(
            (median - 1.0).abs() < 0.03 && within >= 0.9,
            "{flow}: median {median}, within 15 %: {within}"
        );
        torus_curvature(
            &reconstruct(&torus, json!({"curvature": true, "flow": flow})),
            flow,
        );
    }
}

/// ∫K dA ≈ 0 and K at the equators of the torus R = 1, r = 0.35.
fn torus_curvature(s: &Surface, flow: &str) {
    let m = &s.rec.mesh;
    let k = m.scalar("gaussian_curvature").unwrap();
    // Barycentric vertex areas (the analysis crate's, a third of each triangle).
    let area = asperity_engine::methods::analysis::mesh::curvature(m).area;
    let p = m.positions();
    let total: f64 = k.iter().zip(&area).map(|(k, a)| k * a).sum();
    let absolute: f64 = k.iter().zip(&area).map(|(k, a)| k.abs() * a).sum();
    assert!(
        total.abs() <= 0.02 * absolute,
        "{flow}: ∫K = {total}, ∫|K| = {absolute}"
    );
    let at = |outer: bool| {
        let mut v: Vec<f64> = p
            .iter()
            .zip(k)
            .filter(|(q, _)| {
                let rho = (q[0] * q[0] + q[1] * q[1]).sqrt();
                q[2].abs() < 0.02 && if outer { rho > 1.33 } else { rho < 0.67 }
            })
            .map(|(_, k)| *k)
            .collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (outer, inner) = (at(true), at(false));
    assert!(
        (outer * 0.35 * 1.35 - 1.0).abs() < 0.05,
        "{flow}: K outer {outer}"
    );
    assert!(
        (-inner * 0.35 * 0.65 - 1.0).abs() < 0.05,
        "{flow}: K inner {inner}"
    );
}

/// A terrain patch (an open surface) closes to a thin watertight shell by
/// default; `--open` keeps one sheet with its boundary, of the patch's area.
#[test]
fn an_open_patch_stays_open_when_asked() {
    let mut rng = ChaCha8Rng::seed_from_u64(51);
    let z = |x: f64, y: f64| 0.15 * (3.0 * x).sin() * (2.0 * y).cos();
    let pts: Vec<[f64; 3]> = (0..40_000)
        .map(|_| {
            let (x, y) = (
                rng.random::<f64>() * 2.0 - 1.0,
                rng.random::<f64>() * 2.0 - 1.0,
            );
            [x, y, z(x, y)]
        })
        .collect();
    let closed = reconstruct(&pts, json!({}));
    assert_closed(&closed, 0, "patch");
    let open = reconstruct(&pts, json!({"open": true}));
    let t = open.rec.mesh.topology();
    assert!(t.boundary_loops >= 1 && !t.is_watertight(), "{t:?}");
    // The patch's area by quadrature of √(1 + |∇z|²).
    let n = 400;
    let mut area = 0.0;
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (
                -1.0 + 2.0 * (i as f64 + 0.5) / n as f64,
                -1.0 + 2.0 * (j as f64 + 0.5) / n as f64,
            );
            let (zx, zy) = (
                0.45 * (3.0 * x).cos() * (2.0 * y).cos(),
                -0.3 * (3.0 * x).sin() * (2.0 * y).sin(),
            );
            area += (1.0 + zx * zx + zy * zy).sqrt() * (2.0 / n as f64).powi(2);
        }
    }
    let a = open.rec.mesh.area() / area - 1.0;
    assert!(a.abs() < 0.05, "open patch area {a:+.4}");
}

/// A DLA cluster is measured as a deposit and gets the paper's convection.
#[test]
fn a_deposit_is_measured_as_one() {
    use asperity_engine::methods::growth::dla::{DlaParams, dla};
    let cluster = dla(
        &DlaParams::point(3, 3000),
        7,
        0,
        &MemoryBudget::unlimited(),
        &NoProgress,
    )
    .unwrap();
    let s = reconstruct(&cluster.points(), json!({}));
    assert!(!s.rec.cloud.surface, "flatness {:?}", s.rec.cloud.flatness);
    assert_eq!(
        s.rec.flow,
        asperity_engine::methods::levelset::FlowChoice::Convection
    );
    assert!(s.rec.voids.is_none());
}

/// The same noisy cloud with outliers gives the same mesh, vertex for vertex,
/// on one thread and on three (the cloud's analysis, the voids' merge tree and
/// the projection included).
#[test]
fn a_sampled_surface_is_the_same_at_any_thread_count() {
    let mut rng = ChaCha8Rng::seed_from_u64(61);
    let mut pts: Vec<[f64; 3]> = cloud(Shape::Torus, 20_000, 62)
        .into_iter()
        .map(|p| p.map(|x| x + 0.005 * gaussian(&mut rng)))
        .collect();
    pts.extend((0..200).map(|_| std::array::from_fn(|_| rng.random::<f64>() * 2.0 - 1.0)));
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| reconstruct(&pts, json!({"curvature": true, "open": true})))
    };
    let (a, b) = (on(1), on(3));
    assert_eq!(a.rec.mesh, b.rec.mesh);
    assert_eq!(a.quality, b.quality);
}

/// A real range scan nobody here made: PCL's Kinect scan of a milk carton
/// (`tests/data/scans/pcl-milk.ply`, BSD-3-Clause, see its README), 12,575
/// points seen from one side with the sensor's noise, flying pixels and
/// holes. Closed by default: one watertight genus-0 piece, the thin shell
/// around the scanned faces. Asked to stay open: one sheet with its boundary,
/// lying on the points (mean distance under 0.75h, 95 % under 1.5h), half the
/// shell's area (one of its two sides, without the rim).
#[test]
fn a_real_range_scan_closes_or_stays_open() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/data/scans/pcl-milk.ply"
    );
    let scan = asperity_io::read_points(std::path::Path::new(path)).expect("the scan");
    let pts = scan.positions().to_vec();
    assert_eq!(pts.len(), 12_575);
    let closed = reconstruct(&pts, json!({}));
    assert!(closed.rec.cloud.surface, "{:?}", closed.rec.cloud);
    assert_closed(&closed, 0, "milk carton");
    let open = reconstruct(&pts, json!({"open": true}));
    let t = open.rec.mesh.topology();
    assert!(!t.is_watertight() && t.boundary_loops >= 1, "{t:?}");
    assert_eq!(pieces(&open.rec), 1);
    let [mean, p95, _] = open.quality.distance_to_points.in_h;
    assert!(
        mean < 0.75 && p95 < 1.5,
        "{:?}",
        open.quality.distance_to_points
    );
    let half = open.rec.mesh.area() / closed.rec.mesh.area();
    assert!((0.4..0.55).contains(&half), "open/closed area {half}");
}
