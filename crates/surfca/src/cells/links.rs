//! Linking cells across triangle edges (gobron-chiba §3.2): each side neighbour's unfolded
//! position finds the cell that contains it, the links made symmetric, and the
//! pairing redundancy measured.

use super::*;

pub(super) struct Linker<'a> {
    pub(super) frames: &'a [Frame],
    pub(super) edges: &'a EdgeMap,
    pub(super) near_vertex: &'a std::collections::HashMap<u32, Vec<u32>>,
    pub(super) cells: &'a Cells,
    pub(super) pos: &'a [[f64; 3]],
    pub(super) pairing: Pairing,
    pub(super) edge_cells: &'a std::collections::HashMap<(u32, usize), EdgeCells>,
}

/// Directed links of every cell, with the side links across edges (source
/// triangle, direction, destination, source) for the redundancy count.
pub(super) struct Links {
    pub(super) links: Vec<Vec<(u32, u8)>>,
    pub(super) cross: Vec<(u32, u8, u32, u32)>,
    pub(super) edge_links: usize,
    pub(super) vertex_links: usize,
}

impl Linker<'_> {
    /// The cell across edge `e` of triangle `t` (frame `f`) from grid point `q`:
    /// the neighbour triangle unfolded about the shared edge, and the cell
    /// containing (or nearest to) the unfolded point. `None` on a boundary.
    fn across_edge(&self, f: &Frame, t: usize, e: usize, q: V2) -> Option<u32> {
        let (pos, h) = (self.pos, self.cells.h);
        let (va, vb) = (f.verts[e], f.verts[(e + 1) % 3]);
        let other = self
            .edges
            .get(&(va.min(vb), va.max(vb)))
            .and_then(|l| l.iter().find(|(tt, _)| *tt as usize != t))?;
        let g = &self.frames[other.0 as usize];
        // Unfold about the shared edge.
        let (a2, b2) = (f.local[e], f.local[(e + 1) % 3]);
        let u = [b2[0] - a2[0], b2[1] - a2[1]];
        let len = u[0].hypot(u[1]);
        let u = [u[0] / len, u[1] / len];
        let s = (q[0] - a2[0]) * u[0] + (q[1] - a2[1]) * u[1];
        let d = -f.edge_inside(q, e); // > 0: distance beyond the edge
        let (ga, gb) = (g.to_local(pos[va as usize]), g.to_local(pos[vb as usize]));
        let w = [gb[0] - ga[0], gb[1] - ga[1]];
        let wl = w[0].hypot(w[1]);
        let w = [w[0] / wl, w[1] / wl];
        // Into the other triangle: the side of its third corner.
        let third = g.local[(0..3)
            .find(|&m| g.verts[m] != va && g.verts[m] != vb)
            .unwrap_or(0)];
        let mut m = [-w[1], w[0]];
        if (third[0] - ga[0]) * m[0] + (third[1] - ga[1]) * m[1] < 0.0 {
            m = [w[1], -w[0]];
        }
        let q2 = [ga[0] + s * w[0] + d * m[0], ga[1] + s * w[1] + d * m[1]];
        nearest_in(g, q2, h, &self.cells.centre)
    }

    /// The cell across edge `e` of triangle `t` by the paper's pairing: `q`
    /// projected onto the shared edge, and the opposite triangle's edge cell with
    /// the nearest projection. `None` on a boundary.
    fn across_edge_paper(&self, f: &Frame, t: usize, e: usize, q: V2) -> Option<u32> {
        let (va, vb) = (f.verts[e], f.verts[(e + 1) % 3]);
        let other = self
            .edges
            .get(&(va.min(vb), va.max(vb)))
            .and_then(|l| l.iter().find(|(tt, _)| *tt as usize != t))?;
        nearest_projected(self.edge_cells.get(other)?, edge_parameter(f, e, q))
    }

    /// The cell nearest to `p` (3-D) among those near vertex `v` in the other
    /// triangles around it.
    fn beyond_vertex(&self, v: u32, t: usize, p: [f64; 3]) -> Option<u32> {
        let cells = self.cells;
        self.near_vertex.get(&v).and_then(|list| {
            list.iter()
                .filter(|&&n| cells.triangle[n as usize] as usize != t)
                .min_by(|&&a, &&b| {
                    let da = norm(sub(cells.centre[a as usize], p));
                    let db = norm(sub(cells.centre[b as usize], p));
                    da.total_cmp(&db).then(a.cmp(&b))
                })
                .copied()
        })
    }

    /// Links of cell `c` in every direction, added to `out`.
    fn link_cell(&self, c: usize, out: &mut Links) {
        let h = self.cells.h;
        let t = self.cells.triangle[c] as usize;
        let f = &self.frames[t];
        let [i, j] = self.cells.ij[c].map(i64::from);
        for (k, &(dx, dy)) in DIRECTIONS.iter().enumerate() {
            let k = k as u8;
            if let Some(n) = f.get(i + dx as i64, j + dy as i64) {
                out.links[c].push((n, k));
                continue;
            }
            let q = [
                f.x0 + (i as f64 + dx as f64 + 0.5) * h,
                (j as f64 + dy as f64 + 0.5) * h,
            ];
            let outside: Vec<usize> = (0..3).filter(|&e| f.edge_inside(q, e) < 0.0).collect();
            match outside.as_slice() {
                [e] => {
                    let across = match self.pairing {
                        Pairing::Unfolded => self.across_edge(f, t, *e, q),
                        Pairing::Paper => self.across_edge_paper(f, t, *e, q),
                    };
                    if let Some(n) = across {
                        out.links[c].push((n, k));
                        out.edge_links += 1;
                        if is_side(k) {
                            out.cross.push((t as u32, k, n, c as u32));
                        }
                    }
                }
                [e1, e2] => {
                    // Beyond the vertex shared by the two edges.
                    let v = if (*e1 + 1) % 3 == *e2 {
                        f.verts[*e2]
                    } else {
                        f.verts[*e1]
                    };
                    if let Some(n) = self.beyond_vertex(v, t, f.to_world(q)) {
                        out.links[c].push((n, k));
                        out.vertex_links += 1;
                    }
                }
                _ => {}
            }
        }
    }

    /// Links of every cell.
    pub(super) fn links(&self) -> Links {
        let n_cells = self.cells.len();
        let mut out = Links {
            links: vec![Vec::with_capacity(8); n_cells],
            cross: Vec::new(),
            edge_links: 0,
            vertex_links: 0,
        };
        for c in 0..n_cells {
            self.link_cell(c, &mut out);
        }
        out
    }
}

/// The share of side links across an edge, in one direction from one triangle,
/// that land on a cell another such link already reaches (it receives twice).
pub(super) fn pairing_redundancy(cross: &mut [(u32, u8, u32, u32)]) -> f64 {
    let side_links = cross.len();
    cross.sort_unstable();
    let redundant = cross
        .windows(2)
        .filter(|w| (w[0].0, w[0].1, w[0].2) == (w[1].0, w[1].1, w[1].2))
        .count();
    if side_links > 0 {
        redundant as f64 / side_links as f64
    } else {
        0.0
    }
}

/// Makes the links symmetric: if a sees b in direction k, b sees a in the
/// opposite direction.
pub(super) fn symmetrise(links: &mut [Vec<(u32, u8)>]) {
    let forward: Vec<(usize, u32, u8)> = links
        .iter()
        .enumerate()
        .flat_map(|(c, l)| l.iter().map(move |&(n, k)| (c, n, k)))
        .collect();
    for (c, n, k) in forward {
        let back = &mut links[n as usize];
        if !back.iter().any(|&(m, _)| m as usize == c) {
            back.push((c as u32, opposite(k)));
        }
    }
}
