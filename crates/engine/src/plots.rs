//! Plot pieces shared by the jobs' figures: fit lines over log–log data and
//! plots that carry the file name they are written under.

use asperity_analysis::psd::LogFit;
use asperity_render::plot::{Plot, Series, Style};

/// A plot and the file name (without folder) a front end writes it under.
#[derive(Clone, Debug)]
pub struct NamedPlot {
    /// File name, e.g. `width.svg` or `psd.png`; the extension says the format.
    pub name: &'static str,
    /// The plot.
    pub plot: Plot,
}

/// The fitted line y = e^c x^slope over the fit window, as 21 log-spaced points.
pub fn fit_line(name: String, f: &LogFit) -> Series {
    let (range, intercept, slope) = (f.range, f.intercept, f.slope);
    let points = (0..=20)
        .map(|k| {
            let x = range[0] * (range[1] / range[0]).powf(k as f64 / 20.0);
            (x, (intercept + slope * x.ln()).exp())
        })
        .collect();
    Series {
        name,
        points,
        style: Style::Fit,
    }
}

/// A plot with both axes logarithmic.
pub fn log_log(title: String, x_label: &str, y_label: &str, series: Vec<Series>) -> Plot {
    Plot {
        title,
        x_label: x_label.into(),
        y_label: y_label.into(),
        log_x: true,
        log_y: true,
        series,
    }
}

/// A series drawn as points.
pub fn points(name: &str, points: Vec<(f64, f64)>) -> Series {
    Series {
        name: name.into(),
        points,
        style: Style::Points,
    }
}
