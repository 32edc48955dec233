//! Growing placed features over the levels (velho-perlin §5): seeds on the base,
//! carried to finer levels, with the limb, spur, berry and mushroom details they add.

use super::*;

/// A feature with the state it carries from level to level (its seeds).
#[derive(Clone, Debug)]
pub struct Grower {
    feature: Feature,
    seed: u64,
    /// Seed vertices at the current level, with a radius (berry) or anchor.
    seeds: Option<Vec<SeedState>>,
}

#[derive(Clone, Copy, Debug)]
struct SeedState {
    vertex: u32,
    radius: f64,
    anchor: [f64; 3],
    axis: [f64; 3],
}

impl Grower {
    /// Starts a feature with the random seed `seed`.
    pub fn new(feature: Feature, seed: u64) -> Self {
        Self {
            feature,
            seed,
            seeds: None,
        }
    }

    /// The feature.
    pub fn feature(&self) -> &Feature {
        &self.feature
    }

    /// Seed vertices at the level last seen.
    pub fn seed_vertices(&self) -> Vec<u32> {
        self.seeds
            .iter()
            .flatten()
            .map(|s| s.vertex)
            .collect::<Vec<_>>()
    }

    /// Advances to `input`'s level and returns the details there (zero where
    /// the feature does not act), or `None` when it adds nothing.
    pub fn details(&mut self, input: &LevelInput<'_>) -> Option<Vec<[f64; 3]>> {
        let l = input.level;
        let acts = self.feature.acts_at(l);
        match self.feature.procedure {
            Procedure::Rock(r) => acts.then(|| {
                r.values(self.seed, l, input.positions())
                    .into_iter()
                    .map(|x| [0.0, 0.0, x])
                    .collect()
            }),
            Procedure::Fbm(f) => acts.then(|| {
                f.values(self.seed, l, input.positions())
                    .into_iter()
                    .map(|x| [0.0, 0.0, x])
                    .collect()
            }),
            _ => {
                self.advance_seeds(input);
                if !acts {
                    return None;
                }
                let seeds = self.seeds.as_ref()?;
                Some(self.local_details(input, seeds))
            }
        }
    }

    fn resolve(&self, input: &LevelInput<'_>) -> Vec<u32> {
        let p = input.positions();
        match &self.feature.seeds {
            Seeds::Vertices(v) => v.iter().map(|&v| input.descend(v)).collect(),
            Seeds::Points(pts) => pts.iter().map(|&q| nearest_vertex(p, q)).collect(),
            Seeds::Poisson { spacing } => {
                let all: Vec<u32> = (0..p.len() as u32).collect();
                poisson_disk(p, &all, *spacing, usize::MAX, self.seed, input.level)
            }
        }
    }

    fn advance_seeds(&mut self, input: &LevelInput<'_>) {
        let l = input.level;
        let p = input.positions();
        let starts = match &self.feature.levels {
            Some(ls) => ls.iter().min().copied().unwrap_or(1),
            None => 1,
        };
        let vertices_from_base = matches!(self.feature.seeds, Seeds::Vertices(_));
        match self.seeds.take() {
            None if l == starts || (vertices_from_base && l == 1) => {
                let radius = match self.feature.procedure {
                    Procedure::Berry(b) => b.radius,
                    Procedure::Mushroom(m) => m.radius,
                    _ => 0.0,
                };
                let fr = input.frames();
                self.seeds = Some(
                    self.resolve(input)
                        .into_iter()
                        .map(|v| SeedState {
                            vertex: v,
                            radius,
                            anchor: p[v as usize],
                            axis: fr[v as usize][2],
                        })
                        .collect(),
                );
            }
            None => {}
            Some(prev) => {
                let descended: Vec<SeedState> = prev
                    .into_iter()
                    .map(|s| SeedState {
                        vertex: input.descend(s.vertex),
                        ..s
                    })
                    .collect();
                self.seeds = Some(match self.feature.procedure {
                    Procedure::Berry(b) if self.feature.acts_at(l) => {
                        self.berry_children(input, &descended, b)
                    }
                    _ => descended,
                });
            }
        }
    }

    /// Clusters of child seeds inside each parent dome (our reading of §4.2).
    fn berry_children(
        &self,
        input: &LevelInput<'_>,
        parents: &[SeedState],
        b: Berry,
    ) -> Vec<SeedState> {
        let p = input.positions();
        let r_max = parents.iter().map(|s| s.radius).fold(0.0, f64::max);
        if r_max <= 0.0 {
            return Vec::new();
        }
        let grid = Grid::new(p.iter().enumerate().map(|(i, q)| (i as u32, *q)), r_max);
        let fr = input.frames();
        let mut out = Vec::new();
        for (k, s) in parents.iter().enumerate() {
            let c = p[s.vertex as usize];
            let r2 = s.radius * s.radius;
            let mut inside: Vec<u32> = grid
                .near(c, s.radius)
                .filter(|&v| dist2(p[v as usize], c) < r2)
                .collect();
            inside.sort_unstable();
            let child_r = s.radius * b.ratio;
            let kids = poisson_disk(
                p,
                &inside,
                1.5 * child_r,
                b.children,
                self.seed ^ (k as u64).wrapping_mul(0x5bd1_e995),
                input.level,
            );
            out.extend(kids.into_iter().map(|v| SeedState {
                vertex: v,
                radius: child_r,
                anchor: p[v as usize],
                axis: fr[v as usize][2],
            }));
        }
        out
    }

    fn local_details(&self, input: &LevelInput<'_>, seeds: &[SeedState]) -> Vec<[f64; 3]> {
        let l = input.level;
        let p = input.positions();
        let mut d = vec![[0.0; 3]; p.len()];
        match self.feature.procedure {
            Procedure::Tentacle(t) => match t.reading {
                TentacleReading::Literal => {
                    let o = t.offset(l);
                    for s in seeds {
                        d[s.vertex as usize] = o;
                    }
                }
                TentacleReading::Limb { radius, taper } => {
                    let r = radius * taper.powi(l as i32 - 1);
                    limb_details(input, seeds, t, r, &mut d);
                }
            },
            Procedure::Spur(sp) => spur_details(input, seeds, sp, &mut d),
            Procedure::Berry(b) => berry_details(p, seeds, b, &mut d),
            Procedure::Mushroom(m) => Mushrooms::new(input, seeds, m).details(input, &mut d),
            Procedure::Rock(_) | Procedure::Fbm(_) => {}
        }
        d
    }
}

/// Limbs: around each seed's tip, a ball of radius `r` moved one growth step
/// along the seed's twisting direction (see [`Tentacle`]), in every vertex's
/// local frame.
fn limb_details(
    input: &LevelInput<'_>,
    seeds: &[SeedState],
    t: Tentacle,
    r: f64,
    d: &mut [[f64; 3]],
) {
    let l = input.level;
    let p = input.positions();
    let fr = input.frames();
    let grid = Grid::new(p.iter().enumerate().map(|(i, q)| (i as u32, *q)), r);
    let angle = t.theta + std::f64::consts::FRAC_PI_3 * l as f64;
    let lean = if t.twist { 1.0 } else { 0.0 };
    let step = t.length * l as f64;
    for s in seeds {
        let (e1, e2) = tangents(s.axis);
        let dir: [f64; 3] =
            std::array::from_fn(|c| s.axis[c] + lean * (angle.sin() * e1[c] + angle.cos() * e2[c]));
        let norm = dir.iter().map(|x| x * x).sum::<f64>().sqrt();
        let tip = p[s.vertex as usize];
        let mut near: Vec<u32> = grid.near(tip, r).collect();
        near.sort_unstable();
        for v in near {
            let rho2 = dist2(p[v as usize], tip) / (r * r);
            if rho2 >= 1.0 {
                continue;
            }
            let w = step * (1.0 - rho2).powi(2) / norm;
            let world = dir.map(|x| x * w);
            let local = crate::multires::to_local(&fr[v as usize], world);
            for c in 0..3 {
                d[v as usize][c] += local[c];
            }
        }
    }
}

/// Two unit tangents completing the unit `n` to a right-handed frame (a fixed
/// choice, so θ is measured from the same direction at every level).
fn tangents(n: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let a = if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let cross = |u: [f64; 3], v: [f64; 3]| {
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    };
    let e1 = cross(n, a);
    let len = e1.iter().map(|x| x * x).sum::<f64>().sqrt();
    let e1 = e1.map(|x| x / len);
    (e1, cross(n, e1))
}

/// Spurs: each seed vertex pushed `height` mean edge lengths of its level
/// along its normal.
fn spur_details(input: &LevelInput<'_>, seeds: &[SeedState], sp: Spur, d: &mut [[f64; 3]]) {
    let p = input.positions();
    let fv = input.mesh.mesh.face_vertices();
    for s in seeds {
        let v = s.vertex as usize;
        let corners = input.topo.v_corners.of(v);
        let mean = corners
            .iter()
            .map(|&c| dist2(p[fv[input.topo.next(c as usize)] as usize], p[v]).sqrt())
            .sum::<f64>()
            / corners.len().max(1) as f64;
        d[v] = [0.0, 0.0, sp.height * mean];
    }
}

/// Berries: every vertex raised by the dome of the nearest seed that covers
/// it, height·r·√(1 − ρ²/r²).
fn berry_details(p: &[[f64; 3]], seeds: &[SeedState], b: Berry, d: &mut [[f64; 3]]) {
    let r_max = seeds.iter().map(|s| s.radius).fold(0.0, f64::max);
    if r_max <= 0.0 {
        return;
    }
    let grid = Grid::new(
        seeds
            .iter()
            .enumerate()
            .map(|(i, s)| (i as u32, p[s.vertex as usize])),
        r_max,
    );
    d.par_iter_mut().enumerate().for_each(|(v, out)| {
        // The nearest seed whose dome covers v.
        let mut best: Option<(f64, f64)> = None;
        for i in grid.near(p[v], r_max) {
            let s = seeds[i as usize];
            let r2 = dist2(p[s.vertex as usize], p[v]);
            if r2 < s.radius * s.radius && best.is_none_or(|(b2, _)| r2 < b2) {
                best = Some((r2, s.radius));
            }
        }
        if let Some((r2, radius)) = best {
            out[2] = b.height * radius * (1.0 - r2 / (radius * radius)).sqrt();
        }
    });
}

/// Mushroom stems and caps at one level: each stem a smooth bump along its
/// seed's axis; the top of a grown stem spreads outward into a cap.
struct Mushrooms<'a> {
    seeds: &'a [SeedState],
    m: Mushroom,
    level: usize,
    /// The seeds by anchor.
    grid: Grid,
    /// How far a seed reaches.
    reach: f64,
    /// Each stem's foot (the surface 1.5–2.5 radii from its axis) along its axis.
    feet: Vec<f64>,
    /// Each stem's tip height above its foot.
    tips: Vec<f64>,
}

impl<'a> Mushrooms<'a> {
    fn new(input: &LevelInput<'_>, seeds: &'a [SeedState], m: Mushroom) -> Self {
        let p = input.positions();
        let l = input.level;
        let grid = Grid::new(
            seeds.iter().enumerate().map(|(i, s)| (i as u32, s.anchor)),
            (m.radius * 2.0).max(1e-9),
        );
        let reach = 3.0 * m.radius + m.height * (l * (l + 1)) as f64;
        let vgrid = Grid::new(p.iter().enumerate().map(|(i, q)| (i as u32, *q)), m.radius);
        let feet: Vec<f64> = seeds
            .iter()
            .map(|s| {
                let c = p[s.vertex as usize];
                let (mut sum, mut n) = (0.0, 0usize);
                for v in vgrid.near(c, 2.5 * m.radius) {
                    let (a, x) = axial(s, p[v as usize], m.radius);
                    if (1.5..2.5).contains(&x) {
                        sum += a;
                        n += 1;
                    }
                }
                if n > 0 { sum / n as f64 } else { 0.0 }
            })
            .collect();
        let tips = seeds
            .iter()
            .zip(&feet)
            .map(|(s, f)| axial(s, p[s.vertex as usize], m.radius).0 - f)
            .collect();
        Self {
            seeds,
            m,
            level: l,
            grid,
            reach,
            feet,
            tips,
        }
    }

    /// The displacement of the point `pv` (world coordinates).
    fn displacement(&self, pv: [f64; 3]) -> [f64; 3] {
        let (m, l) = (self.m, self.level);
        let lift = m.height * l as f64;
        let mut w = [0.0; 3];
        for i in self.grid.near(pv, self.reach) {
            let s = self.seeds[i as usize];
            let q = [
                pv[0] - s.anchor[0],
                pv[1] - s.anchor[1],
                pv[2] - s.anchor[2],
            ];
            let a = q[0] * s.axis[0] + q[1] * s.axis[1] + q[2] * s.axis[2];
            if a < -0.5 * m.radius {
                continue;
            }
            let rho = [
                q[0] - a * s.axis[0],
                q[1] - a * s.axis[1],
                q[2] - a * s.axis[2],
            ];
            let r = (rho[0] * rho[0] + rho[1] * rho[1] + rho[2] * rho[2]).sqrt();
            let x = r / m.radius;
            // Stem: a smooth bump along the seed's axis.
            if x < 1.0 {
                let k = (1.0 - x * x).powi(2);
                for (wc, ac) in w.iter_mut().zip(s.axis) {
                    *wc += lift * k * ac;
                }
            }
            // Cap: the top of a grown stem spreads outward, widest a little
            // below the tip.
            let tip = self.tips[i as usize];
            let h = a - self.feet[i as usize];
            let band = 1.5 * m.radius;
            if l >= 2 && tip > band && h > tip - band && x < 3.0 && r > 1e-12 {
                let u = ((h - (tip - band)) / band).clamp(0.0, 1.0);
                let push = 0.18
                    * m.radius
                    * l as f64
                    * (std::f64::consts::PI * u).sin()
                    * drop_off(x / 3.0);
                for c in 0..3 {
                    w[c] += push * rho[c] / r;
                }
            }
        }
        w
    }

    /// Every vertex's detail, in its local frame.
    fn details(&self, input: &LevelInput<'_>, d: &mut [[f64; 3]]) {
        let p = input.positions();
        let fr = input.frames();
        d.par_iter_mut().enumerate().for_each(|(v, out)| {
            let w = self.displacement(p[v]);
            if w != [0.0; 3] {
                *out = crate::multires::to_local(&fr[v], w);
            }
        });
    }
}

/// Height along a seed's axis and distance from it in radii.
fn axial(s: &SeedState, q: [f64; 3], radius: f64) -> (f64, f64) {
    let d = [q[0] - s.anchor[0], q[1] - s.anchor[1], q[2] - s.anchor[2]];
    let a = d[0] * s.axis[0] + d[1] * s.axis[1] + d[2] * s.axis[2];
    let r2 = d.iter().map(|x| x * x).sum::<f64>() - a * a;
    (a, r2.max(0.0).sqrt() / radius)
}
