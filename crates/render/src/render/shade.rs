//! Shading a pixel: the gobron-chiba light model (two layers where asked), shadows,
//! ambient obscurance, textures, splatted points and the overlays drawn on top.

use super::*;

/// What the shading pass reads.
pub(super) struct ShadeCtx<'a> {
    pub(super) p: &'a Prepared,
    pub(super) sv: &'a ScreenVerts,
    pub(super) cam: &'a Camera,
    pub(super) o: &'a RenderOptions,
    pub(super) shadow: Option<&'a ShadowMap>,
    pub(super) light: Vec3,
}

/// One output row: colours, coverage, view depth, NDC depth.
type Row = (Vec<Vec3>, Vec<f32>, Vec<f32>, Vec<f32>);

pub(super) fn shade(ctx: &ShadeCtx, ids: &[u32]) -> Pixels {
    let ShadeCtx {
        p,
        sv,
        cam,
        o,
        shadow,
        light,
    } = *ctx;
    let (w, h, ss) = (o.width as usize, o.height as usize, o.supersample as usize);
    let sw = w * ss;
    let material = Vec3::new(
        o.material[0] as f32,
        o.material[1] as f32,
        o.material[2] as f32,
    ) / 255.0;
    let rows: Vec<Row> = (0..h)
        .into_par_iter()
        .map(|y| {
            let bg = background(o, y);
            let mut colors = Vec::with_capacity(w);
            let (mut cov, mut vd, mut nd) = (
                vec![0.0f32; w],
                vec![f32::INFINITY; w],
                vec![f32::INFINITY; w],
            );
            let mut groups: Vec<(u32, u32, f32, f32)> = Vec::with_capacity(ss * ss);
            for x in 0..w {
                groups.clear();
                for sy in 0..ss {
                    for sx in 0..ss {
                        let (sample_x, sample_y) = (x * ss + sx, y * ss + sy);
                        let t = ids[sample_y * sw + sample_x];
                        if t == EMPTY {
                            continue;
                        }
                        let (fx, fy) = (sample_x as f32 + 0.5, sample_y as f32 + 0.5);
                        match groups.iter_mut().find(|g| g.0 == t) {
                            Some(g) => {
                                g.1 += 1;
                                g.2 += fx;
                                g.3 += fy;
                            }
                            None => groups.push((t, 1, fx, fy)),
                        }
                    }
                }
                let n_s = (ss * ss) as f32;
                let mut acc = Vec3::ZERO;
                let mut covered = 0u32;
                let mut nearest = (0u32, f32::INFINITY, f32::INFINITY);
                for &(t, count, sx, sy) in &groups {
                    let (cx, cy) = (sx / count as f32, sy / count as f32);
                    let tri = p.triangles[t as usize];
                    let b = barycentric(sv, tri, cx, cy);
                    let (c, view_d, ndc) =
                        shade_point(p, sv, tri, t, b, cam, o, shadow, light, material);
                    acc += c * count as f32;
                    covered += count;
                    if count > nearest.0 || (count == nearest.0 && view_d < nearest.1) {
                        nearest = (count, view_d, ndc);
                    }
                }
                acc += bg * (n_s - covered as f32);
                colors.push(acc / n_s);
                cov[x] = covered as f32 / n_s;
                vd[x] = nearest.1;
                nd[x] = nearest.2;
            }
            (colors, cov, vd, nd)
        })
        .collect();
    let mut px = Pixels {
        color: Vec::with_capacity(w * h),
        coverage: Vec::with_capacity(w * h),
        view_depth: Vec::with_capacity(w * h),
        ndc_depth: Vec::with_capacity(w * h),
    };
    for (c, cv, vd, nd) in rows {
        px.color.extend(c);
        px.coverage.extend(cv);
        px.view_depth.extend(vd);
        px.ndc_depth.extend(nd);
    }
    px
}

#[allow(clippy::too_many_arguments)]
#[inline]
fn shade_point(
    p: &Prepared,
    sv: &ScreenVerts,
    tri: [u32; 3],
    t: u32,
    b: [f32; 3],
    cam: &Camera,
    o: &RenderOptions,
    shadow: Option<&ShadowMap>,
    light: Vec3,
    material: Vec3,
) -> (Vec3, f32, f32) {
    let [i, j, k] = tri.map(|v| v as usize);
    let pos = p.positions[i] * b[0] + p.positions[j] * b[1] + p.positions[k] * b[2];
    let ndc = sv.z[i] * b[0] + sv.z[j] * b[1] + sv.z[k] * b[2];
    let view_d = (pos - cam.eye).dot(cam.forward);
    let n = match &p.face_normals {
        Some(f) => f[t as usize],
        None => {
            (p.normals[i] * b[0] + p.normals[j] * b[1] + p.normals[k] * b[2]).normalize_or(Vec3::Z)
        }
    };
    if o.shader == Shader::Normals {
        return (n * 0.5 + Vec3::splat(0.5), view_d, ndc);
    }
    let albedo = if let Some(a) = &p.albedo {
        a[i] * b[0] + a[j] * b[1] + a[k] * b[2]
    } else if let Some((v, lo, hi, map)) = &p.scalar {
        let c = if *map == ColorMap::Labels {
            // Labels are categories: take the label of the nearest corner, unscaled.
            let nearest = if b[0] >= b[1] && b[0] >= b[2] {
                i
            } else if b[1] >= b[2] {
                j
            } else {
                k
            };
            map.map(v[nearest] as f64)
        } else {
            let s = v[i] * b[0] + v[j] * b[1] + v[k] * b[2];
            map.map(if hi > lo {
                ((s - lo) / (hi - lo)) as f64
            } else {
                0.5
            })
        };
        Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) / 255.0
    } else if let (Some(uv), Some(tex)) = (&p.uvs, &p.texture) {
        sample_texture(tex, uv[i] * b[0] + uv[j] * b[1] + uv[k] * b[2])
    } else {
        material
    };
    let eye_dir = if cam.orthographic {
        -cam.forward
    } else {
        (cam.eye - pos).normalize_or(-cam.forward)
    };
    let n_lit = if n.dot(eye_dir) < 0.0 { -n } else { n };
    let s = shadow.map_or(1.0, |sm| sm.lit(pos, n_lit));
    if let (Some(sh), Some((top, bottom))) = (&o.two_layer, &p.layers) {
        let at = |v: &[f32]| f64::from(v[i] * b[0] + v[j] * b[1] + v[k] * b[2]);
        let (t1, t2) = (at(top), at(bottom));
        // Where neither layer is left (a hole) the shader's own colour shows.
        if t1 > 0.0 || t2 > 0.0 {
            let c = sh.shade(&o.light, [t1, t2], [n, light, eye_dir], s);
            return (v3(c), view_d, ndc);
        }
    }
    (
        albedo * intensity(&o.light, n, light, eye_dir, s),
        view_d,
        ndc,
    )
}

/// Bilinear lookup with clamped edges; v = 0 is the bottom row (OBJ/PLY convention).
fn sample_texture(tex: &RgbaImage, uv: Vec2) -> Vec3 {
    let (tw, th) = (tex.width() as f32, tex.height() as f32);
    let x = (uv.x.clamp(0.0, 1.0) * tw - 0.5).clamp(0.0, tw - 1.0);
    let y = ((1.0 - uv.y.clamp(0.0, 1.0)) * th - 0.5).clamp(0.0, th - 1.0);
    let (x0, y0) = (x.floor() as u32, y.floor() as u32);
    let (x1, y1) = (
        (x0 + 1).min(tex.width() - 1),
        (y0 + 1).min(tex.height() - 1),
    );
    let (fx, fy) = (x - x0 as f32, y - y0 as f32);
    let c = |x: u32, y: u32| {
        let p = tex.get(x, y);
        Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32) / 255.0
    };
    (c(x0, y0) * (1.0 - fx) + c(x1, y0) * fx) * (1.0 - fy)
        + (c(x0, y1) * (1.0 - fx) + c(x1, y1) * fx) * fy
}

/// Depth-tested, anti-aliased lines at output resolution.
pub(super) struct Overlay<'a> {
    pub(super) vp: Mat4,
    pub(super) w: usize,
    pub(super) h: usize,
    pub(super) depth: &'a [f32],
    pub(super) center: [f64; 3],
}

impl Overlay<'_> {
    pub(super) fn segment(&self, img: &mut RgbaImage, a: Vec3, b: Vec3, col: [u8; 4]) {
        let to_screen = |p: Vec3| {
            let c = self.vp * p.extend(1.0);
            if c.w <= 1e-9 {
                return None;
            }
            Some(Vec3::new(
                (c.x / c.w * 0.5 + 0.5) * self.w as f32,
                (0.5 - c.y / c.w * 0.5) * self.h as f32,
                c.z / c.w,
            ))
        };
        let (Some(pa), Some(pb)) = (to_screen(a), to_screen(b)) else {
            return;
        };
        let len = (pb.truncate() - pa.truncate()).length();
        if !len.is_finite() || len > 4.0 * (self.w + self.h) as f32 {
            return;
        }
        let steps = (len * 2.0).ceil().max(1.0) as usize;
        let alpha = col[3] as f32 / 255.0 * 0.85;
        for s in 0..=steps {
            let q = pa + (pb - pa) * (s as f32 / steps as f32);
            let (fx, fy) = (q.x - 0.5, q.y - 0.5);
            let (x0, y0) = (fx.floor(), fy.floor());
            for (dx, dy) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
                let (x, y) = (x0 + dx, y0 + dy);
                if x < 0.0 || y < 0.0 || x >= self.w as f32 || y >= self.h as f32 {
                    continue;
                }
                let wgt = (1.0 - (fx - x).abs()) * (1.0 - (fy - y).abs()) * alpha;
                let i = y as usize * self.w + x as usize;
                // Visible if not behind the surface (small tolerance for lines on it).
                if q.z > self.depth[i] + 2e-3 * (1.0 - self.depth[i]).abs().max(1e-4) {
                    continue;
                }
                let mut px = img.get(x as u32, y as u32);
                for ch in 0..3 {
                    px[ch] = (px[ch] as f32 * (1.0 - wgt) + col[ch] as f32 * wgt).round() as u8;
                }
                img.put(x as u32, y as u32, px);
            }
        }
    }
}
