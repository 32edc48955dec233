//! Plots through `plotters`: scaling curves with fits (W(t), PSDs,
//! mass–radius), histograms (curvature), CA change curves, line drawings.
//!
//! Every plot renders to SVG ([`plot_svg`]) or to a bitmap ([`plot_png`], an
//! [`RgbaImage`] for the PNG writer). Text is laid out and rasterised with a
//! bundled subset of DejaVu Sans (`fonts/`, Bitstream Vera licence), registered
//! once as plotters' "sans-serif", so bitmaps carry real labels on a machine
//! without any fonts; SVGs name the family and the viewer draws it.

use asperity_core::RgbaImage;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::RenderError;

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// Connected line.
    Line,
    /// Markers only (measurements).
    Points,
    /// Dashed-looking thin line (fits, references).
    Fit,
}

/// One data series.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend entry.
    pub name: String,
    /// (x, y) values; non-finite and, on log axes, non-positive values are skipped.
    pub points: Vec<(f64, f64)>,
    /// Drawing style.
    pub style: Style,
}

/// A 2-D plot.
#[derive(Clone, Debug, PartialEq)]
pub struct Plot {
    /// Title above the plot.
    pub title: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// Logarithmic x axis.
    pub log_x: bool,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// The data.
    pub series: Vec<Series>,
}

/// DejaVu Sans, subset (see `fonts/LICENSE`).
static FONT: &[u8] = include_bytes!("../fonts/DejaVuSans-subset.ttf");

/// Registers the bundled font as "sans-serif" (once per process).
fn ensure_font() -> Result<(), RenderError> {
    static DONE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let ok = *DONE.get_or_init(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(RenderError::BadOption(
            "plot: the bundled font could not be loaded".into(),
        ))
    }
}

const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(23, 190, 207),
];

fn err(e: impl std::fmt::Display) -> RenderError {
    RenderError::BadOption(format!("plot: {e}"))
}

fn range(v: impl Iterator<Item = f64>, log: bool) -> Option<(f64, f64)> {
    let (lo, hi) = v
        .filter(|x| x.is_finite() && (!log || *x > 0.0))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
    if !lo.is_finite() {
        return None;
    }
    Some(if log {
        if hi > lo {
            (lo / 1.3, hi * 1.3)
        } else {
            (lo / 2.0, hi * 2.0)
        }
    } else {
        let pad = if hi > lo {
            0.05 * (hi - lo)
        } else {
            0.5 * lo.abs().max(1.0)
        };
        (lo - pad, hi + pad)
    })
}

/// Data ranges of a plot (None when nothing is drawable).
fn plot_ranges(plot: &Plot) -> Option<((f64, f64), (f64, f64))> {
    let keep = |&(x, y): &(f64, f64)| {
        x.is_finite() && y.is_finite() && (!plot.log_x || x > 0.0) && (!plot.log_y || y > 0.0)
    };
    let pts = || {
        plot.series
            .iter()
            .flat_map(|s| s.points.iter().copied().filter(keep))
    };
    Some((
        range(pts().map(|p| p.0), plot.log_x)?,
        range(pts().map(|p| p.1), plot.log_y)?,
    ))
}

/// Draws `plot` on any plotters backend.
fn draw_plot<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    plot: &Plot,
    xr: (f64, f64),
    yr: (f64, f64),
) -> Result<(), RenderError> {
    let keep = |&(x, y): &(f64, f64)| {
        x.is_finite() && y.is_finite() && (!plot.log_x || x > 0.0) && (!plot.log_y || y > 0.0)
    };
    root.fill(&WHITE).map_err(err)?;
    let mut b = ChartBuilder::on(root);
    b.caption(&plot.title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60);
    macro_rules! draw {
        ($chart:expr) => {{
            let mut chart = $chart;
            chart
                .configure_mesh()
                .x_desc(&plot.x_label)
                .y_desc(&plot.y_label)
                .light_line_style(WHITE.mix(0.0))
                .draw()
                .map_err(err)?;
            for (k, s) in plot.series.iter().enumerate() {
                let color = PALETTE[k % PALETTE.len()];
                let data: Vec<(f64, f64)> = s.points.iter().copied().filter(keep).collect();
                let anno = match s.style {
                    Style::Points => chart
                        .draw_series(data.iter().map(|&p| Circle::new(p, 3, color.filled())))
                        .map_err(err)?,
                    Style::Line => chart
                        .draw_series(LineSeries::new(data, color.stroke_width(2)))
                        .map_err(err)?,
                    Style::Fit => chart
                        .draw_series(LineSeries::new(data, color.stroke_width(1)))
                        .map_err(err)?,
                };
                anno.label(&s.name).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(2))
                });
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK.mix(0.3))
                .draw()
                .map_err(err)?;
        }};
    }
    match (plot.log_x, plot.log_y) {
        (false, false) => draw!(b.build_cartesian_2d(xr.0..xr.1, yr.0..yr.1).map_err(err)?),
        (true, false) => draw!(
            b.build_cartesian_2d((xr.0..xr.1).log_scale(), yr.0..yr.1)
                .map_err(err)?
        ),
        (false, true) => draw!(
            b.build_cartesian_2d(xr.0..xr.1, (yr.0..yr.1).log_scale())
                .map_err(err)?
        ),
        (true, true) => draw!(
            b.build_cartesian_2d((xr.0..xr.1).log_scale(), (yr.0..yr.1).log_scale())
                .map_err(err)?
        ),
    }
    root.present().map_err(err)?;
    Ok(())
}

/// Renders `plot` as an SVG document of `width × height` pixels.
///
/// # Errors
/// [`RenderError::Empty`] when no series has a drawable point.
pub fn plot_svg(plot: &Plot, width: u32, height: u32) -> Result<String, RenderError> {
    ensure_font()?;
    let (xr, yr) = plot_ranges(plot).ok_or(RenderError::Empty("plot (no finite points)"))?;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        draw_plot(&root, plot, xr, yr)?;
    }
    Ok(svg)
}

/// Renders `plot` as a `width × height` bitmap (write it with the PNG writer).
///
/// # Errors
/// [`RenderError::Empty`] when no series has a drawable point;
/// [`RenderError::BadSize`] for a zero or huge size.
pub fn plot_png(plot: &Plot, width: u32, height: u32) -> Result<RgbaImage, RenderError> {
    ensure_font()?;
    if width == 0 || height == 0 || width > 8192 || height > 8192 {
        return Err(RenderError::BadSize { width, height });
    }
    let (xr, yr) = plot_ranges(plot).ok_or(RenderError::Empty("plot (no finite points)"))?;
    let mut rgb = vec![255u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (width, height)).into_drawing_area();
        draw_plot(&root, plot, xr, yr)?;
    }
    let rgba: Vec<u8> = rgb
        .chunks_exact(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    RgbaImage::from_pixels(width, height, rgba)
        .map_err(|e| RenderError::BadOption(format!("plot: {e}")))
}

/// One stroke of a [`Drawing`].
#[derive(Clone, Debug, PartialEq)]
pub struct Stroke {
    /// Vertices (x, y).
    pub points: Vec<(f64, f64)>,
    /// RGB colour.
    pub color: [u8; 3],
    /// Line width in pixels.
    pub width: u32,
    /// Legend entry (strokes without one are not listed).
    pub label: Option<String>,
}

/// A line drawing in the plane at equal scale on both axes (curves, their DCFs).
#[derive(Clone, Debug, PartialEq)]
pub struct Drawing {
    /// Title above the drawing.
    pub title: String,
    /// Strokes, drawn in order.
    pub strokes: Vec<Stroke>,
}

/// Renders `d` as SVG with one unit the same length on both axes.
///
/// # Errors
/// [`RenderError::Empty`] when no stroke has a finite point.
pub fn drawing_svg(d: &Drawing, width: u32, height: u32) -> Result<String, RenderError> {
    ensure_font()?;
    let keep = |p: &&(f64, f64)| p.0.is_finite() && p.1.is_finite();
    let pts = || d.strokes.iter().flat_map(|s| s.points.iter().filter(keep));
    let (Some(xr), Some(yr)) = (
        range(pts().map(|p| p.0), false),
        range(pts().map(|p| p.1), false),
    ) else {
        return Err(RenderError::Empty("drawing (no finite points)"));
    };
    // Plot area after the margins, caption and label areas set below.
    let (pw, ph) = (
        (width as f64 - 24.0 - 50.0).max(10.0),
        (height as f64 - 24.0 - 30.0 - 30.0).max(10.0),
    );
    let scale = ((xr.1 - xr.0) / pw).max((yr.1 - yr.0) / ph);
    let (cx, cy) = (0.5 * (xr.0 + xr.1), 0.5 * (yr.0 + yr.1));
    let (hx, hy) = (0.5 * scale * pw, 0.5 * scale * ph);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&d.title, ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(30)
            .y_label_area_size(50)
            .build_cartesian_2d(cx - hx..cx + hx, cy - hy..cy + hy)
            .map_err(err)?;
        chart
            .configure_mesh()
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(err)?;
        let mut labelled = false;
        for s in &d.strokes {
            let color = RGBColor(s.color[0], s.color[1], s.color[2]);
            let data: Vec<(f64, f64)> = s.points.iter().filter(keep).copied().collect();
            let anno = chart
                .draw_series(LineSeries::new(data, color.stroke_width(s.width)))
                .map_err(err)?;
            if let Some(l) = &s.label {
                labelled = true;
                let w = s.width;
                anno.label(l).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(w.max(2)))
                });
            }
        }
        if labelled {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK.mix(0.3))
                .draw()
                .map_err(err)?;
        }
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// A histogram of `values` in `bins` equal bins as a [`Plot`] of counts (a step line).
///
/// # Errors
/// [`RenderError::Empty`] when no value is finite; [`RenderError::BadOption`] for 0 bins.
pub fn histogram_plot(
    values: &[f64],
    bins: usize,
    title: &str,
    x_label: &str,
) -> Result<Plot, RenderError> {
    if bins == 0 {
        return Err(RenderError::BadOption(
            "a histogram needs at least one bin".into(),
        ));
    }
    let counts =
        histogram(values, bins).ok_or(RenderError::Empty("histogram (no finite values)"))?;
    // Drawn as a step line over the bin edges, so it shares the plots' layout.
    let mut pts = Vec::with_capacity(2 * bins + 2);
    for (k, &(lo, hi, c)) in counts.iter().enumerate() {
        if k == 0 {
            pts.push((lo, 0.0));
        }
        pts.push((lo, c as f64));
        pts.push((hi, c as f64));
    }
    pts.push((counts[bins - 1].1, 0.0));
    Ok(Plot {
        title: title.into(),
        x_label: x_label.into(),
        y_label: "count".into(),
        log_x: false,
        log_y: false,
        series: vec![Series {
            name: format!("{} values", values.iter().filter(|v| v.is_finite()).count()),
            points: pts,
            style: Style::Line,
        }],
    })
}

/// A histogram of `values` in `bins` equal bins, as an SVG plot of counts.
///
/// # Errors
/// As [`histogram_plot`].
pub fn histogram_svg(
    values: &[f64],
    bins: usize,
    title: &str,
    x_label: &str,
    width: u32,
    height: u32,
) -> Result<String, RenderError> {
    plot_svg(
        &histogram_plot(values, bins, title, x_label)?,
        width,
        height,
    )
}

/// (lower edge, upper edge, count) of `bins` equal bins over the finite values.
pub fn histogram(values: &[f64], bins: usize) -> Option<Vec<(f64, f64, usize)>> {
    let (lo, hi) = values
        .iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() || bins == 0 {
        return None;
    }
    let hi = if hi > lo { hi } else { lo + 1.0 };
    let w = (hi - lo) / bins as f64;
    let mut c = vec![0usize; bins];
    for &v in values.iter().filter(|v| v.is_finite()) {
        c[(((v - lo) / w) as usize).min(bins - 1)] += 1;
    }
    Some(
        c.into_iter()
            .enumerate()
            .map(|(k, n)| (lo + k as f64 * w, lo + (k + 1) as f64 * w, n))
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_draws_lines_and_text() {
        let p = Plot {
            title: "PSD".into(),
            x_label: "q".into(),
            y_label: "C(q)".into(),
            log_x: true,
            log_y: true,
            series: vec![Series {
                name: "data".into(),
                points: (1..50).map(|t| (t as f64, (t as f64).powf(-2.6))).collect(),
                style: Style::Line,
            }],
        };
        let img = plot_png(&p, 400, 300).unwrap();
        assert_eq!((img.width(), img.height()), (400, 300));
        let px = img.pixels();
        let white = px
            .chunks_exact(4)
            .filter(|c| c[..3] == [255, 255, 255])
            .count();
        let dark = px
            .chunks_exact(4)
            .filter(|c| c[0] < 80 && c[1] < 80 && c[2] < 80)
            .count();
        let blue = px
            .chunks_exact(4)
            .filter(|c| c[2] > 150 && c[0] < 80)
            .count();
        // Mostly background, with axis text (dark, anti-aliased glyphs) and the blue series.
        assert!(white > 400 * 300 / 2, "{white}");
        assert!(dark > 300, "text and axes: {dark}");
        assert!(blue > 100, "series: {blue}");
        assert!(plot_png(&p, 0, 10).is_err());
        let empty = Plot {
            series: vec![],
            ..p
        };
        assert!(matches!(
            plot_png(&empty, 10, 10),
            Err(RenderError::Empty(_))
        ));
    }

    #[test]
    fn svg_has_the_data_and_labels() {
        let p = Plot {
            title: "W(t)".into(),
            x_label: "t".into(),
            y_label: "W".into(),
            log_x: true,
            log_y: true,
            series: vec![
                Series {
                    name: "RD".into(),
                    points: (1..50).map(|t| (t as f64, (t as f64).sqrt())).collect(),
                    style: Style::Points,
                },
                Series {
                    name: "t^0.5".into(),
                    points: vec![(1.0, 1.0), (49.0, 7.0)],
                    style: Style::Fit,
                },
                Series {
                    name: "skipped".into(),
                    points: vec![(0.0, 1.0), (f64::NAN, 2.0)],
                    style: Style::Line,
                },
            ],
        };
        let svg = plot_svg(&p, 480, 320).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("W(t)") && svg.contains("t^0.5"));
        assert!(svg.matches("<circle").count() >= 49);
        let empty = Plot {
            series: vec![],
            ..p
        };
        assert!(plot_svg(&empty, 100, 100).is_err());
    }

    #[test]
    fn histogram_counts_every_value() {
        let v: Vec<f64> = (0..1000)
            .map(|k| (k as f64 * 0.618).fract())
            .chain([f64::NAN])
            .collect();
        let h = histogram(&v, 10).unwrap();
        assert_eq!(h.iter().map(|b| b.2).sum::<usize>(), 1000);
        assert!(h.iter().all(|b| (90..=110).contains(&b.2)), "{h:?}");
        assert!(
            histogram_svg(&v, 10, "x", "x", 300, 200)
                .unwrap()
                .contains("1000 values")
        );
        assert!(histogram_svg(&[f64::NAN], 10, "x", "x", 300, 200).is_err());
    }
}
