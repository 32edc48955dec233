//! Reference checks for the renderer: projection geometry, the light model's
//! maximum, colour-map ends, and refusals of degenerate input.

use asperity_core::{HeightField, PointSet, RgbaImage, TriMesh};
use asperity_render::{
    ColorMap, LightModel, Projection, RenderError, RenderOptions, Shader, View, render_height,
    render_mesh, render_points,
};

/// Unit UV sphere with exact normals.
fn sphere(nu: usize, nv: usize) -> TriMesh {
    let mut p = vec![[0.0, 0.0, 1.0]];
    for j in 1..nv {
        let th = std::f64::consts::PI * j as f64 / nv as f64;
        for i in 0..nu {
            let ph = std::f64::consts::TAU * i as f64 / nu as f64;
            p.push([th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()]);
        }
    }
    p.push([0.0, 0.0, -1.0]);
    let last = (p.len() - 1) as u32;
    let ring = |j: usize, i: usize| (1 + (j - 1) * nu + i % nu) as u32;
    let mut t = Vec::new();
    for i in 0..nu {
        t.push([0, ring(1, i), ring(1, i + 1)]);
        t.push([last, ring(nv - 1, i + 1), ring(nv - 1, i)]);
    }
    for j in 1..nv - 1 {
        for i in 0..nu {
            t.push([ring(j, i), ring(j + 1, i), ring(j + 1, i + 1)]);
            t.push([ring(j, i), ring(j + 1, i + 1), ring(j, i + 1)]);
        }
    }
    let normals = p.clone();
    TriMesh::new(p, t).unwrap().with_normals(normals).unwrap()
}

fn top_ortho(size: u32) -> RenderOptions {
    RenderOptions {
        width: size,
        height: size,
        view: View::Top,
        projection: Projection::Orthographic,
        shadows: false,
        ambient_occlusion: 0.0,
        background: [[0, 0, 0], [0, 0, 0]],
        ..RenderOptions::default()
    }
}

fn luminance(img: &RgbaImage, x: u32, y: u32) -> f64 {
    let p = img.get(x, y);
    p[0] as f64 + p[1] as f64 + p[2] as f64
}

#[test]
fn sphere_silhouette_is_where_the_projection_says() {
    let n = 200u32;
    let o = RenderOptions {
        shader: Shader::Normals,
        ..top_ortho(n)
    };
    let img = render_mesh(&sphere(256, 128), &o).unwrap();
    // Orthographic top view framing the box [-1, 1]³ with the 6 % margin: the
    // unit circle has radius (n/2)/1.06 pixels around the image centre.
    let r = n as f64 / 2.0 / 1.06;
    let c = n as f64 / 2.0;
    let mut checked = 0;
    for y in 0..n {
        for x in 0..n {
            let d = ((x as f64 + 0.5 - c).powi(2) + (y as f64 + 0.5 - c).powi(2)).sqrt();
            let covered = luminance(&img, x, y) > 0.0;
            if d < r - 1.0 {
                assert!(
                    covered,
                    "inside pixel ({x}, {y}) at {d:.2} px is empty (r = {r:.2})"
                );
                checked += 1;
            } else if d > r + 1.0 {
                assert!(
                    !covered,
                    "outside pixel ({x}, {y}) at {d:.2} px is covered (r = {r:.2})"
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 35_000);
    // The normals shader shows +z (up, toward the camera) at the centre: RGB ≈ (128, 128, 255).
    let p = img.get(n / 2, n / 2);
    assert!(
        (p[0] as i32 - 128).abs() <= 2 && (p[1] as i32 - 128).abs() <= 2 && p[2] >= 253,
        "{p:?}"
    );
}

#[test]
fn brightest_point_is_where_phong_says() {
    let n = 240u32;
    let light = LightModel {
        direction: [0.6, -0.3, 0.7416198487095663],
        ambient: 0.05,
        diffuse: 0.45,
        specular: 0.45,
        shininess: 40.0,
    };
    let o = RenderOptions {
        light,
        light_follows_camera: false,
        material: [255, 255, 255],
        ..top_ortho(n)
    };
    let img = render_mesh(&sphere(360, 180), &o).unwrap();
    // Maximise the model over the visible hemisphere by brute force (the eye is +z).
    let l = light.direction;
    let f = |nv: [f64; 3]| {
        let ndl = (nv[0] * l[0] + nv[1] * l[1] + nv[2] * l[2]).max(0.0);
        let r = [
            2.0 * ndl * nv[0] - l[0],
            2.0 * ndl * nv[1] - l[1],
            2.0 * ndl * nv[2] - l[2],
        ];
        light.ambient + light.diffuse * ndl + light.specular * r[2].max(0.0).powf(light.shininess)
    };
    let (mut best, mut arg) = (f64::MIN, [0.0; 3]);
    for a in 0..2000 {
        for b in 0..400 {
            let th = 0.5 * std::f64::consts::PI * b as f64 / 400.0;
            let ph = std::f64::consts::TAU * a as f64 / 2000.0;
            let nv = [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()];
            if f(nv) > best {
                best = f(nv);
                arg = nv;
            }
        }
    }
    let r = n as f64 / 2.0 / 1.06;
    let (ex, ey) = (n as f64 / 2.0 + arg[0] * r, n as f64 / 2.0 - arg[1] * r);
    let (mut bl, mut bx, mut by) = (0.0, 0, 0);
    for y in 0..n {
        for x in 0..n {
            let v = luminance(&img, x, y);
            if v > bl {
                (bl, bx, by) = (v, x, y);
            }
        }
    }
    let dist = ((bx as f64 + 0.5 - ex).powi(2) + (by as f64 + 0.5 - ey).powi(2)).sqrt();
    assert!(
        dist <= 2.0,
        "brightest pixel ({bx}, {by}) is {dist:.2} px from the model's maximum ({ex:.1}, {ey:.1})"
    );
    // …and as bright as the model says (8-bit rounding, 3 channels).
    assert!(
        (bl / 3.0 - best * 255.0).abs() <= 3.0,
        "{} vs {}",
        bl / 3.0,
        best * 255.0
    );
}

#[test]
fn top_down_height_colours_span_the_colour_map() {
    // Two plateaus (0 and 1) joined by a ramp: their centres must show the map's ends.
    let (nx, ny) = (40, 40);
    let data = (0..nx * ny)
        .map(|k| {
            let i = k % nx;
            ((i as f64 - 15.0) / 10.0).clamp(0.0, 1.0)
        })
        .collect();
    let h = HeightField::from_vec([nx, ny], data)
        .unwrap()
        .with_spacing([0.025, 0.025])
        .unwrap();
    let unlit = LightModel {
        ambient: 1.0,
        diffuse: 0.0,
        specular: 0.0,
        ..LightModel::default()
    };
    for map in [ColorMap::Viridis, ColorMap::Magma] {
        let o = RenderOptions {
            shader: Shader::Height,
            colormap: map,
            light: unlit,
            ..top_ortho(120)
        };
        let img = render_height(&h, &o).unwrap();
        let close = |p: [u8; 4], c: [u8; 3]| (0..3).all(|k| (p[k] as i32 - c[k] as i32).abs() <= 1);
        assert!(
            close(img.get(20, 60), map.map(0.0)),
            "{map:?} min: {:?}",
            img.get(20, 60)
        );
        assert!(
            close(img.get(100, 60), map.map(1.0)),
            "{map:?} max: {:?}",
            img.get(100, 60)
        );
    }
}

#[test]
fn degenerate_inputs_are_refused() {
    let o = RenderOptions::default();
    let empty = TriMesh::new(vec![[0.0; 3]; 3], vec![]).unwrap();
    assert!(matches!(
        render_mesh(&empty, &o),
        Err(RenderError::Empty(_))
    ));
    let s = sphere(8, 4);
    for (w, h) in [(0, 10), (10, 0), (20_000, 10)] {
        let e = render_mesh(
            &s,
            &RenderOptions {
                width: w,
                height: h,
                ..RenderOptions::default()
            },
        )
        .unwrap_err();
        assert!(e.to_string().contains("invalid"), "{e}");
    }
    let nan = PointSet::new(vec![[0.0, f64::NAN, 0.0]]);
    assert!(
        render_points(&nan, &o)
            .unwrap_err()
            .to_string()
            .contains("not finite")
    );
    assert!(render_points(&PointSet::new(vec![]), &o).is_err());
    let e = render_mesh(
        &s,
        &RenderOptions {
            shader: Shader::Texture,
            ..o.clone()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("UVs and a texture"), "{e}");
    let e = render_mesh(
        &s,
        &RenderOptions {
            budget: asperity_core::MemoryBudget::new(1 << 20),
            ..o
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("frame buffers"), "{e}");
}

#[test]
fn same_pixels_at_any_thread_count() {
    let s = sphere(64, 32);
    let o = RenderOptions {
        width: 160,
        height: 120,
        ..RenderOptions::default()
    };
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| render_mesh(&s, &o).unwrap());
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap()
        .install(|| render_mesh(&s, &o).unwrap());
    assert_eq!(one, two);
}

#[test]
fn points_and_wireframe_draw_something() {
    let p = PointSet::new(
        (0..200)
            .map(|i| [(i % 20) as f64, (i / 20) as f64, ((i * 7) % 5) as f64 * 0.3])
            .collect(),
    );
    let img = render_points(
        &p,
        &RenderOptions {
            width: 120,
            height: 90,
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let bg = img.get(0, 0);
    assert!(img.pixels().chunks(4).filter(|q| q[..3] != bg[..3]).count() > 500);
    let plain = render_mesh(
        &sphere(16, 8),
        &RenderOptions {
            width: 120,
            height: 90,
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let wire = render_mesh(
        &sphere(16, 8),
        &RenderOptions {
            width: 120,
            height: 90,
            wireframe: Some([255, 0, 0, 255]),
            ..RenderOptions::default()
        },
    )
    .unwrap();
    let reddened = plain
        .pixels()
        .chunks(4)
        .zip(wire.pixels().chunks(4))
        .filter(|(a, b)| b[0] as i32 - b[2] as i32 > a[0] as i32 - a[2] as i32 + 20)
        .count();
    assert!(reddened > 100, "{reddened}");
}

#[test]
fn mean_curvature_of_a_sphere_is_one_over_r() {
    let r = 2.5;
    let s = sphere(160, 80);
    let scaled = TriMesh::new(
        s.positions().iter().map(|p| p.map(|c| c * r)).collect(),
        s.triangles().to_vec(),
    )
    .unwrap();
    let mut h = asperity_render::render::mean_curvature(&scaled);
    h.sort_by(f64::total_cmp);
    let median = h[h.len() / 2];
    assert!(
        (median - 1.0 / r).abs() < 0.01 / r,
        "median H = {median}, expected {}",
        1.0 / r
    );
    // Away from the poles' fans every vertex is within 3 %.
    let within = h
        .iter()
        .filter(|&&v| (v - 1.0 / r).abs() < 0.03 / r)
        .count();
    assert!(
        within as f64 > 0.9 * h.len() as f64,
        "{within} of {}",
        h.len()
    );
}

#[test]
fn label_colour_map_shows_categories_unscaled() {
    // Left half label 3, right half label 7: each half shows its tab10 colour.
    let h = HeightField::from_vec([20, 20], vec![0.0; 400]).unwrap();
    let m = h.to_trimesh(asperity_core::Diagonal::Forward).unwrap();
    let labels: Vec<f64> = (0..400)
        .map(|k| if k % 20 < 10 { 3.0 } else { 7.0 })
        .collect();
    let m = m.with_scalar("region", labels).unwrap();
    let unlit = LightModel {
        ambient: 1.0,
        diffuse: 0.0,
        specular: 0.0,
        ..LightModel::default()
    };
    let o = RenderOptions {
        shader: Shader::Height,
        colormap: ColorMap::Labels,
        scalar: Some("region".into()),
        light: unlit,
        ..top_ortho(100)
    };
    let img = render_mesh(&m, &o).unwrap();
    assert_eq!(&img.get(20, 50)[..3], &ColorMap::Labels.map(3.0));
    assert_eq!(&img.get(80, 50)[..3], &ColorMap::Labels.map(7.0));
}
