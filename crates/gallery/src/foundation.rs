//! The foundation: the shared types and every file format, on a built-in
//! self-affine sample surface (not a paper's method).

use asperity_engine::Result;
use asperity_engine::core::fourier_surface::{FourierParams, fourier_surface};
use asperity_engine::core::{Diagonal, HeightField, LengthUnit, RgbaImage, TriMesh, Units, shapes};
use asperity_engine::io::Surface;
use asperity_engine::methods::render::{ColorMap, RenderOptions, Shader, hillshade};

use crate::{Env, Item, Section, fact};

/// The section.
///
/// # Errors
/// Any writer's or renderer's.
pub fn section(env: &Env) -> Result<Section> {
    let n = if env.quick { 65 } else { 257 };
    let params = FourierParams {
        n,
        hurst: 0.8,
        modes: n / 8,
        rms: 0.05,
        spacing: 1.0 / (n - 1) as f64,
    };
    let h = fourier_surface(&params, env.seed, &env.budget)?;
    let items = vec![
        height_formats(env, &h)?,
        mesh_formats(env, &h)?,
        torus(env)?,
    ];
    env.measure("sample_rms", 0.05);
    Ok(Section {
        title: "Foundation: shared types and file formats".into(),
        source: "asperity-core, asperity-io".into(),
        blurb: "A built-in self-affine test surface written in every height-field, mesh and point format asperity supports. \
                Open the .gsf or .gwy in Gwyddion, the .x3p in any ISO 25178-72 reader, the .ply/.obj/.glb in Blender or MeshLab, the .npy with numpy.load. \
                Pictures are rendered headless on the CPU by asperity-render."
            .into(),
        items,
    })
}

/// The height field as a map, written in every height-field format.
fn height_formats(env: &Env, h: &HeightField) -> Result<Item> {
    let n = h.nx();
    let preview = env.picture(
        "sample_height_map.png",
        &hillshade::height_map(h, ColorMap::Viridis, 0.5, true),
    )?;
    let mut files = Vec::new();
    for ext in ["png", "npy", "exr", "gsf", "gwy", "csv"] {
        files.push(env.write(&format!("sample_height.{ext}"), &Surface::Height(h.clone()))?);
    }
    // x3p lengths are metres: the field is labelled as a scan in µm there.
    let micrometres = Units {
        xy: LengthUnit::Um,
        z: LengthUnit::Um,
    };
    files.push(env.write(
        "sample_height.x3p",
        &Surface::Height(h.clone().with_units(micrometres)),
    )?);
    let (lo, hi) = h.min_max();
    Ok(Item::new(
        format!("Sample height field {n}×{n} (Fourier synthesis, H = 0.8)"),
        Some(preview),
        files,
        vec![
            fact("samples", format!("{n} × {n}")),
            fact("spacing", format!("{:.5}", h.spacing()[0])),
            fact("height range", format!("{lo:.4} … {hi:.4}")),
            fact("rms height", "0.05"),
            fact(".x3p", "the same numbers as µm (x3p stores metres)"),
            fact("seed", env.seed),
        ],
    ))
}

/// Viridis colours of the heights, per sample and as an image.
fn height_colors(h: &HeightField) -> Result<(Vec<[u8; 4]>, RgbaImage)> {
    let (lo, hi) = h.min_max();
    let span = if hi > lo { hi - lo } else { 1.0 };
    let colors: Vec<[u8; 4]> = h
        .data()
        .iter()
        .map(|z| {
            let c = ColorMap::Viridis.map((z - lo) / span);
            [c[0], c[1], c[2], 255]
        })
        .collect();
    let pixels = colors.iter().flatten().copied().collect();
    let img = RgbaImage::from_pixels(h.nx() as u32, h.ny() as u32, pixels)?;
    Ok((colors, img))
}

/// The same surface as a coloured, textured mesh in every mesh format.
fn mesh_formats(env: &Env, h: &HeightField) -> Result<Item> {
    let (colors, img) = height_colors(h)?;
    let mesh = h
        .to_trimesh(Diagonal::Alternating)?
        .with_computed_normals()
        .with_colors(colors)?
        .with_scalar("height", h.measured_values())?
        .with_texture(img);
    let mut files = Vec::new();
    for ext in ["ply", "obj", "glb", "stl"] {
        files.push(env.mesh(&format!("sample_mesh.{ext}"), &mesh)?);
    }
    files.push(env.write("sample_points.xyz", &Surface::Points(h.to_point_set()))?);
    let opts = RenderOptions {
        shader: Shader::Texture,
        ..env.view()
    };
    let view3d = env.render("sample_mesh_3d.png", &mesh, &opts)?;
    Ok(Item::new(
        "The same surface as a mesh (alternating diagonals)",
        Some(view3d),
        files,
        vec![
            fact("vertices", mesh.n_vertices()),
            fact("triangles", mesh.n_faces()),
            fact("Euler characteristic", mesh.euler_characteristic()),
            fact("boundary loops", mesh.boundary_loops().len()),
            fact("area", format!("{:.5}", mesh.area())),
            fact(
                "attributes",
                "normals, colours, UVs + texture, scalar 'height'",
            ),
        ],
    ))
}

/// A closed torus: genus, watertightness and volume against 2π²Rr².
fn torus(env: &Env) -> Result<Item> {
    let (nu, nv) = if env.quick { (24, 12) } else { (64, 32) };
    let t: TriMesh = shapes::torus(1.0, 0.35, nu, nv).with_computed_normals();
    let files = vec![env.mesh("torus.ply", &t)?, env.mesh("torus.glb", &t)?];
    let opts = RenderOptions {
        wireframe: Some([30, 30, 40, 160]),
        ..env.view()
    };
    let view = env.render("torus.png", &t, &opts)?;
    Ok(Item::new(
        "Closed mesh: torus topology check",
        Some(view),
        files,
        vec![
            fact("vertices", t.n_vertices()),
            fact("triangles", t.n_faces()),
            fact("Euler characteristic", t.euler_characteristic()),
            fact("genus", t.genus().map_or("n/a".into(), |g| g.to_string())),
            fact("watertight", t.is_watertight()),
            fact(
                "volume",
                format!(
                    "{:.4} (exact 2π²Rr² = {:.4})",
                    t.signed_volume(),
                    2.0 * std::f64::consts::PI.powi(2) * 0.35f64.powi(2)
                ),
            ),
        ],
    ))
}
