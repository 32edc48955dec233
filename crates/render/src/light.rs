//! The gobron-chiba "Simple Light Model" and the key light's shadow map.
//!
//! Paper: [gobron-chiba] §"Simple Light Model":
//! C_RGB = (K_a + K_d (L·N_c) + K_s (R·E)^n) · C_m,RGB, with L the light vector,
//! N_c the (cell) normal, R the reflection of L about N, E the eye vector, n the
//! specular power and C_m the material colour.
//!
//! # Deviations from the paper
//! - Negative dot products are clamped to 0 (the paper leaves this implicit).
//! - The diffuse and specular terms are multiplied by a shadow factor S ∈ [0, 1]
//!   from a shadow map of the key light (the paper has no shadows), and the final
//!   colour by an ambient-occlusion factor (see `ao`): rough surfaces are
//!   unreadable without them.
//! - Two-sided: a normal facing away from the eye is flipped, so open sheets and
//!   height fields seen from below are lit like their front.
//! - [`two_layer`] uses the sign the paper's integral gives where its printed
//!   closed form has the opposite one (next section).
//!
//! # Light through two layers
//! [`two_layer`] is the paper's closed-form colour of a cell covered by two layers
//! (patina over metal, "Rendering problem: light through two layers"):
//! intensity decays as e^(−x) through a layer of thickness t and opacity o, with
//! the optical depth scaled by f_o = 1/(1 − o); the colour is the depth-weighted
//! mean of the two layers' lit colours,
//! c = [l₁∫₀^a e^(−x)dx + l₂∫_a^(a+b) e^(−x)dx] / ∫₀^(a+b) e^(−x)dx with
//! a = t₁f₁, b = t₂f₂, i.e. c = (l₁ − (l₁ − l₂)e^(−a) + l₂k)/(1 + k), k = −e^(−(a+b)).
//! The paper prints "+ (l₁ − l₂)e^(−t₁f₁)" (and t₁d₁ as a lower limit): that sign
//! would not give c = l₂ for a vanishing top layer; the integral gives "−", used
//! here (checked against numerical integration in the tests).
//! [`TwoLayerShading`] does it in the paper's order: each layer's material
//! colour is lit by the light model with that material's coefficients (a matte
//! patina, a shiny metal), and the *lit* colours are mixed.
//!
//! [gobron-chiba]: https://infoscience.epfl.ch/record/162175 "Gobron, Chiba: 3D Surface Cellular Automata and Their Applications. J. Visualization and Computer Animation 10(3):143-158, 1999"

use glam::{Mat4, Vec3};

use crate::raster::{ScreenVerts, VisBuffer, rasterize};

/// Coefficients of the light model, and the key light's direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightModel {
    /// Unit vector from the surface toward the light (world space).
    pub direction: [f64; 3],
    /// Ambient coefficient K_a.
    pub ambient: f64,
    /// Diffuse coefficient K_d.
    pub diffuse: f64,
    /// Specular coefficient K_s.
    pub specular: f64,
    /// Specular power n.
    pub shininess: f64,
}

impl LightModel {
    /// Light from azimuth `az_deg` (clockwise from +y, "north") and altitude
    /// `alt_deg` above the horizon, the hillshade convention.
    pub fn from_azimuth_altitude(az_deg: f64, alt_deg: f64) -> [f64; 3] {
        let (az, alt) = (az_deg.to_radians(), alt_deg.to_radians());
        [alt.cos() * az.sin(), alt.cos() * az.cos(), alt.sin()]
    }
}

impl Default for LightModel {
    /// Light from the north-west (azimuth 315°) at 45°, K_a = 0.25, K_d = 0.75,
    /// K_s = 0.25, n = 32.
    fn default() -> Self {
        Self {
            direction: Self::from_azimuth_altitude(315.0, 45.0),
            ambient: 0.25,
            diffuse: 0.75,
            specular: 0.25,
            shininess: 32.0,
        }
    }
}

/// Evaluates the model for unit normal `n`, unit light `l`, unit eye vector `e`
/// (surface → eye) and shadow factor `s`; returns the scalar multiplying C_m.
#[inline]
pub fn intensity(m: &LightModel, n: Vec3, l: Vec3, e: Vec3, s: f32) -> f32 {
    let n = if n.dot(e) < 0.0 { -n } else { n };
    let ndl = n.dot(l).max(0.0);
    let r = 2.0 * n.dot(l) * n - l; // reflection of L about N
    let spec = if ndl > 0.0 {
        r.dot(e).max(0.0).powf(m.shininess as f32)
    } else {
        0.0
    };
    m.ambient as f32 + s * (m.diffuse as f32 * ndl + m.specular as f32 * spec)
}

/// Depth map of the scene seen from the key light (orthographic).
pub struct ShadowMap {
    light_vp: Mat4,
    size: usize,
    depth: Vec<f32>,
    bias: f32,
    texel: f32,
}

impl ShadowMap {
    /// Renders the depth of `positions`/`tris` from direction `toward_light`,
    /// framing the bounding sphere (`center`, `radius`) at `size`² texels.
    pub fn build(
        positions: &[Vec3],
        tris: &[[u32; 3]],
        toward_light: Vec3,
        center: Vec3,
        radius: f32,
        size: usize,
    ) -> Self {
        let up = if toward_light.cross(Vec3::Z).length() < 1e-3 {
            Vec3::Y
        } else {
            Vec3::Z
        };
        let eye = center + toward_light * radius * 2.0;
        let view = Mat4::look_at_rh(eye, center, up);
        let r = radius * 1.01;
        let proj = Mat4::orthographic_rh_gl(-r, r, -r, r, 0.5 * radius, 3.5 * radius);
        let light_vp = proj * view;
        let sv = project(positions, &light_vp, size, size);
        let VisBuffer { depth, .. } = rasterize(&sv, tris, size, size);
        // Bias: about two texels of world size, in NDC depth units (range 3r ↔ 2).
        let bias = 2.0 * (2.0 * r / size as f32) / (3.0 * radius) * 2.0;
        Self {
            light_vp,
            size,
            depth,
            bias,
            texel: 2.0 * r / size as f32,
        }
    }

    /// Fraction of the light reaching world point `p` with unit normal `n`
    /// (3×3 percentage-closer filter). The lookup point is pushed 1.5 texels along
    /// the normal ("normal-offset" shadows), which removes self-shadowing acne on
    /// surfaces nearly parallel to the light without detaching contact shadows.
    pub fn lit(&self, p: Vec3, n: Vec3) -> f32 {
        let c = self.light_vp.project_point3(p + n * (1.5 * self.texel));
        let s = self.size as f32;
        let (fx, fy) = ((c.x * 0.5 + 0.5) * s, (0.5 - c.y * 0.5) * s);
        let (ix, iy) = (fx.floor() as i64, fy.floor() as i64);
        let mut lit = 0.0;
        for dy in -1..=1 {
            for dx in -1..=1 {
                let (x, y) = (ix + dx, iy + dy);
                let inside =
                    x >= 0 && y >= 0 && (x as usize) < self.size && (y as usize) < self.size;
                if !inside || c.z - self.bias <= self.depth[y as usize * self.size + x as usize] {
                    lit += 1.0;
                }
            }
        }
        lit / 9.0
    }
}

/// Projects world positions through `vp` onto a `width × height` sample grid.
pub fn project(positions: &[Vec3], vp: &Mat4, width: usize, height: usize) -> ScreenVerts {
    let (w, h) = (width as f32, height as f32);
    let mut sv = ScreenVerts {
        x: Vec::with_capacity(positions.len()),
        y: Vec::with_capacity(positions.len()),
        z: Vec::with_capacity(positions.len()),
        inv_w: Vec::with_capacity(positions.len()),
        valid: Vec::with_capacity(positions.len()),
    };
    for p in positions {
        let c = *vp * p.extend(1.0);
        let valid = c.w > 1e-12 && c.is_finite();
        let iw = if valid { 1.0 / c.w } else { 0.0 };
        sv.x.push((c.x * iw * 0.5 + 0.5) * w);
        sv.y.push((0.5 - c.y * iw * 0.5) * h);
        sv.z.push(c.z * iw);
        sv.inv_w.push(iw);
        sv.valid.push(valid);
    }
    sv
}

/// Colour of a top layer (`top`, thickness `t1`, opacity `o1`) over a bottom
/// layer (`bottom`, `t2`, `o2`), both colours already lit (see the module docs).
/// Opacities are in [0, 1); thicknesses ≥ 0. With no depth at all the top
/// colour is returned.
pub fn two_layer(top: [f64; 3], t1: f64, o1: f64, bottom: [f64; 3], t2: f64, o2: f64) -> [f64; 3] {
    let f = |o: f64| 1.0 / (1.0 - o.clamp(0.0, 0.999_999));
    let a = t1.max(0.0) * f(o1);
    let b = t2.max(0.0) * f(o2);
    let k = -(-(a + b)).exp();
    if 1.0 + k <= 1e-300 {
        return top;
    }
    let ea = (-a).exp();
    std::array::from_fn(|i| (top[i] - (top[i] - bottom[i]) * ea + bottom[i] * k) / (1.0 + k))
}

/// One layer's material: its colour, opacity and light-model coefficients.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layer {
    /// Material colour C_m (linear, 0–1).
    pub color: [f64; 3],
    /// Opacity o in [0, 1).
    pub opacity: f64,
    /// K_a, K_d, K_s and the specular power n of this material.
    pub ambient: f64,
    /// Diffuse coefficient K_d.
    pub diffuse: f64,
    /// Specular coefficient K_s.
    pub specular: f64,
    /// Specular power n.
    pub shininess: f64,
}

impl Layer {
    fn model(&self, direction: [f64; 3]) -> LightModel {
        LightModel {
            direction,
            ambient: self.ambient,
            diffuse: self.diffuse,
            specular: self.specular,
            shininess: self.shininess,
        }
    }
}

/// The paper's rendering of a two-layer cell: each layer's colour lit by the
/// light model with its own material first, then the lit colours mixed by
/// [`two_layer`] through the layers' thicknesses, read per vertex from the
/// mesh scalars `top_scalar` and `bottom_scalar`.
#[derive(Clone, Debug, PartialEq)]
pub struct TwoLayerShading {
    /// The covering layer (patina).
    pub top: Layer,
    /// The layer below (metal).
    pub bottom: Layer,
    /// Scalar holding the top layer's thickness.
    pub top_scalar: String,
    /// Scalar holding the bottom layer's thickness.
    pub bottom_scalar: String,
}

impl TwoLayerShading {
    /// The colour at a point with layer thicknesses `[t1, t2]` (top, bottom),
    /// normal, light and eye directions `[n, l, e]` and shadow factor `s`, the
    /// key light's direction taken from `light`.
    pub fn shade(
        &self,
        light: &LightModel,
        [t1, t2]: [f64; 2],
        [n, l, e]: [Vec3; 3],
        s: f32,
    ) -> [f64; 3] {
        let lit = |layer: &Layer| {
            let k = f64::from(intensity(&layer.model(light.direction), n, l, e, s));
            layer.color.map(|c| c * k)
        };
        two_layer(
            lit(&self.top),
            t1,
            self.top.opacity,
            lit(&self.bottom),
            t2,
            self.bottom.opacity,
        )
    }
}

#[cfg(test)]
mod tests {

    /// Each layer is lit with its own material before the mix: with no top
    /// layer the metal's specular highlight is all there (K_a + K_d + K_s head
    /// on), under a thick one only the matte patina's light remains.
    #[test]
    fn two_layers_are_lit_before_they_mix() {
        use super::{Layer, LightModel, TwoLayerShading};
        use glam::Vec3;
        let layer = |color, specular| Layer {
            color,
            opacity: 0.5,
            ambient: 0.2,
            diffuse: 0.6,
            specular,
            shininess: 40.0,
        };
        let sh = TwoLayerShading {
            top: layer([0.2, 0.6, 0.5], 0.0),
            bottom: layer([0.7, 0.4, 0.25], 0.9),
            top_scalar: "top".into(),
            bottom_scalar: "bottom".into(),
        };
        let light = LightModel {
            direction: [0.0, 0.0, 1.0],
            ..LightModel::default()
        };
        let z = Vec3::Z;
        let bare = sh.shade(&light, [0.0, 1.0], [z, z, z], 1.0);
        for (c, m) in bare.iter().zip([0.7, 0.4, 0.25]) {
            assert!((c - m * 1.7).abs() < 1e-6, "{bare:?}");
        }
        let covered = sh.shade(&light, [40.0, 1.0], [z, z, z], 1.0);
        for (c, m) in covered.iter().zip([0.2, 0.6, 0.5]) {
            assert!((c - m * 0.8).abs() < 1e-6, "{covered:?}");
        }
        // In shadow the highlight goes, the ambient term stays.
        let dark = sh.shade(&light, [0.0, 1.0], [z, z, z], 0.0);
        assert!((dark[0] - 0.7 * 0.2).abs() < 1e-6);
    }

    #[test]
    fn two_layer_matches_the_integral() {
        let (l1, l2) = ([0.2, 0.7, 0.5], [0.8, 0.45, 0.2]);
        for (t1, o1, t2, o2) in [
            (0.3, 0.5, 2.0, 0.9),
            (1.5, 0.2, 0.4, 0.0),
            (0.05, 0.0, 3.0, 0.5),
        ] {
            let c = two_layer(l1, t1, o1, l2, t2, o2);
            // Midpoint-rule integral of the definition, each layer on its own.
            let (a, b) = (t1 / (1.0 - o1), t2 / (1.0 - o2));
            let n = 100_000;
            let (mut num, mut den) = ([0.0; 3], 0.0);
            for (lo, hi, l) in [(0.0, a, l1), (a, a + b, l2)] {
                let dx = (hi - lo) / n as f64;
                for k in 0..n {
                    let w = (-(lo + (k as f64 + 0.5) * dx)).exp() * dx;
                    for i in 0..3 {
                        num[i] += l[i] * w;
                    }
                    den += w;
                }
            }
            for i in 0..3 {
                assert!(
                    (c[i] - num[i] / den).abs() < 1e-6,
                    "{c:?} vs {:?}",
                    num[i] / den
                );
            }
        }
        // Limits: no top layer shows the bottom; a thick top layer hides it.
        let c = two_layer(l1, 0.0, 0.5, l2, 1.0, 0.5);
        assert!((0..3).all(|i| (c[i] - l2[i]).abs() < 1e-12));
        let c = two_layer(l1, 50.0, 0.5, l2, 1.0, 0.5);
        assert!((0..3).all(|i| (c[i] - l1[i]).abs() < 1e-12));
    }
    use super::*;

    #[test]
    fn phong_terms() {
        let m = LightModel {
            direction: [0.0, 0.0, 1.0],
            ambient: 0.1,
            diffuse: 0.6,
            specular: 0.3,
            shininess: 10.0,
        };
        let z = Vec3::Z;
        // Light, normal and eye aligned: every term at its maximum.
        assert!((intensity(&m, z, z, z, 1.0) - 1.0).abs() < 1e-6);
        // Shadowed: ambient only.
        assert!((intensity(&m, z, z, z, 0.0) - 0.1).abs() < 1e-6);
        // Light at 60° from the normal, eye along the mirror direction: diffuse cos 60°, full specular.
        let l = Vec3::new(60f32.to_radians().sin(), 0.0, 0.5);
        let e = Vec3::new(-l.x, 0.0, l.z);
        assert!((intensity(&m, z, l, e, 1.0) - (0.1 + 0.6 * 0.5 + 0.3)).abs() < 1e-5);
        // Back-facing normal is flipped toward the eye.
        assert!((intensity(&m, -z, z, z, 1.0) - 1.0).abs() < 1e-6);
        let d = LightModel::from_azimuth_altitude(90.0, 0.0);
        assert!((d[0] - 1.0).abs() < 1e-12 && d[2].abs() < 1e-12);
    }
}
