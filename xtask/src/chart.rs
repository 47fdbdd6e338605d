//! SVG line charts for the report (plotters, SVG backend, no system fonts needed).

use std::path::Path;

use plotters::coord::ranged1d::ValueFormatter;
use plotters::prelude::*;

/// One named line of a chart.
pub struct Series {
    /// Legend label.
    pub label: String,
    /// (x, y) points, in increasing x.
    pub points: Vec<(f64, f64)>,
    /// Dashed line (used to tell the second of two variants apart).
    pub dashed: bool,
    /// Colour index into the palette.
    pub colour: usize,
}

/// A chart: title, axis labels, logarithmic axes or not, and its lines.
pub struct LineChart {
    /// Caption above the plot.
    pub title: String,
    /// Label of the x axis, with unit.
    pub x_label: String,
    /// Label of the y axis, with unit.
    pub y_label: String,
    /// Logarithmic x axis.
    pub log_x: bool,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// The lines.
    pub series: Vec<Series>,
}

const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
];

fn range(values: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (if log { 1e-3 } else { 0.0 }, 1.0);
    }
    if log {
        (lo / 1.5, hi * 1.5)
    } else {
        let pad = 0.05 * (hi - lo).max(1e-12);
        (lo - pad, hi + pad)
    }
}

/// The labelled ticks of a logarithmic axis over [lo, hi]: each decade's 1, 2 and 5 (with
/// 3 too where the axis spans less than a decade and a half, so it has at least three).
pub(crate) fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let mantissas: &[f64] = if hi / lo < 15.0 {
        &[1.0, 2.0, 3.0, 5.0]
    } else {
        &[1.0, 2.0, 5.0]
    };
    decades(lo, hi, mantissas)
}

/// The unlabelled grid lines of a logarithmic axis: each decade's 1 to 9.
fn log_grid(lo: f64, hi: f64) -> Vec<f64> {
    decades(lo, hi, &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0])
}

fn decades(lo: f64, hi: f64, mantissas: &[f64]) -> Vec<f64> {
    let (first, last) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    (first..=last)
        .flat_map(|k| mantissas.iter().map(move |m| tick_value(*m, k)))
        .filter(|v| *v >= lo && *v <= hi)
        .collect()
}

/// m·10^k, exactly as its decimal text reads (0.3, not 0.30000000000000004).
fn tick_value(m: f64, k: i32) -> f64 {
    format!("{m}e{k}").parse().unwrap_or(m * 10f64.powi(k))
}

/// An axis label: the shortest decimal that reads back as `v` at 12 significant digits,
/// in plain notation from 10⁻⁴ to 10⁶ and in scientific notation outside.
pub(crate) fn tick_label(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let rounded: f64 = format!("{v:.11e}").parse().unwrap_or(v);
    let magnitude = rounded.abs();
    if (1e-4..1e6).contains(&magnitude) {
        format!("{rounded}")
    } else {
        format!("{rounded:e}")
    }
}

/// Width of the chart's plot (px); the legend takes a column to its right.
const PLOT_WIDTH: u32 = 900;
/// Width of the legend's column (px).
const LEGEND_WIDTH: u32 = 290;
const HEIGHT: u32 = 600;

impl LineChart {
    /// Draw the chart into an SVG file at `path`: the plot, and the legend in a column to
    /// its right, where it covers no data.
    pub fn write_svg(&self, path: &Path) -> Result<(), Box<dyn std::error::Error>> {
        let root = SVGBackend::new(path, (PLOT_WIDTH + LEGEND_WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE)?;
        let (plot, legend) = root.split_horizontally(PLOT_WIDTH);
        let (x0, x1) = range(
            self.series
                .iter()
                .flat_map(|s| s.points.iter().map(|p| p.0)),
            self.log_x,
        );
        let (y0, y1) = range(
            self.series
                .iter()
                .flat_map(|s| s.points.iter().map(|p| p.1)),
            self.log_y,
        );
        let mut builder = ChartBuilder::on(&plot);
        builder
            .caption(&self.title, ("sans-serif", 22))
            .margin(20)
            .x_label_area_size(50)
            .y_label_area_size(80);
        let log = |lo: f64, hi: f64| {
            (lo..hi)
                .log_scale()
                .with_key_points(log_ticks(lo, hi))
                .with_light_points(log_grid(lo, hi))
        };
        // A linear axis's tick at zero comes out of plotters as round-off (1.1e-16): below a
        // billionth of the span it is labelled 0.
        let zero_below =
            |log: bool, lo: f64, hi: f64| if log { 0.0 } else { (hi - lo).abs() * 1e-9 };
        let zero = [
            zero_below(self.log_x, x0, x1),
            zero_below(self.log_y, y0, y1),
        ];
        // plotters types the coordinate system by its scale, so the four cases are spelled out.
        match (self.log_x, self.log_y) {
            (true, true) => self.plot(
                &mut builder.build_cartesian_2d(log(x0, x1), log(y0, y1))?,
                zero,
            )?,
            (true, false) => {
                self.plot(&mut builder.build_cartesian_2d(log(x0, x1), y0..y1)?, zero)?
            }
            (false, true) => {
                self.plot(&mut builder.build_cartesian_2d(x0..x1, log(y0, y1))?, zero)?
            }
            (false, false) => self.plot(&mut builder.build_cartesian_2d(x0..x1, y0..y1)?, zero)?,
        }
        self.draw_legend(&legend)?;
        root.present()?;
        Ok(())
    }

    /// The mesh, its labels and the lines.
    fn plot<'a, X, Y>(
        &self,
        chart: &mut ChartContext<'a, SVGBackend<'a>, Cartesian2d<X, Y>>,
        zero: [f64; 2],
    ) -> Result<(), String>
    where
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .x_label_formatter(&|v| tick_label(if v.abs() < zero[0] { 0.0 } else { *v }))
            .y_label_formatter(&|v| tick_label(if v.abs() < zero[1] { 0.0 } else { *v }))
            .draw()
            .map_err(|e| e.to_string())?;
        for s in &self.series {
            let colour = PALETTE[s.colour % PALETTE.len()];
            let style = ShapeStyle::from(&colour).stroke_width(2);
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|p| p.0.is_finite() && p.1.is_finite())
                .collect();
            if s.dashed {
                chart
                    .draw_series(DashedLineSeries::new(pts.clone(), 8, 5, style))
                    .map_err(|e| e.to_string())?;
            } else {
                chart
                    .draw_series(LineSeries::new(pts.clone(), style))
                    .map_err(|e| e.to_string())?;
            }
            // Point markers only where the points are few enough to be read one by one.
            if pts.len() <= 60 {
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 3, colour.filled())))
                    .map_err(|e| e.to_string())?;
            }
        }
        Ok(())
    }

    /// The legend, a line sample and the label per series, top-down in the column `area`.
    fn draw_legend(
        &self,
        area: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    ) -> Result<(), String> {
        let font = ("sans-serif", 13).into_font().color(&BLACK);
        for (k, s) in self.series.iter().enumerate() {
            let y = 70 + 22 * k as i32;
            let colour = PALETTE[s.colour % PALETTE.len()];
            let style = ShapeStyle::from(&colour).stroke_width(2);
            let sample: Vec<Vec<(i32, i32)>> = if s.dashed {
                vec![vec![(0, y), (9, y)], vec![(14, y), (23, y)]]
            } else {
                vec![vec![(0, y), (23, y)]]
            };
            for segment in sample {
                area.draw(&PathElement::new(segment, style))
                    .map_err(|e| e.to_string())?;
            }
            area.draw(&Text::new(s.label.as_str(), (30, y - 7), font.clone()))
                .map_err(|e| e.to_string())?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_log_axis_labels_each_decade_with_its_2_and_5_in_plain_decimals() {
        // The work-precision charts' error axis (issue 30 item 6): 1.1 to 18 mm.
        assert_eq!(log_ticks(1.1, 18.0), vec![2.0, 5.0, 10.0]);
        assert_eq!(log_ticks(0.011, 0.6), vec![0.02, 0.05, 0.1, 0.2, 0.5]);
        // Less than a decade and a half: 3 as well, so the axis has three labels.
        assert_eq!(log_ticks(1.5, 12.0), vec![2.0, 3.0, 5.0, 10.0]);
        let labels: Vec<String> = log_ticks(0.05, 0.6).into_iter().map(tick_label).collect();
        assert_eq!(labels, ["0.05", "0.1", "0.2", "0.3", "0.5"]);
        assert_eq!(tick_label(0.1 + 0.2), "0.3");
        assert_eq!(tick_label(2e-7), "2e-7");
        assert_eq!(tick_label(-1.25), "-1.25");
        assert_eq!(tick_label(3e7), "3e7");
    }

    #[test]
    fn svg_has_axes_labels_and_legend() {
        let dir = std::env::temp_dir().join(format!("flexmbd-chart-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.svg");
        let chart = LineChart {
            title: "cost".into(),
            x_label: "elements".into(),
            y_label: "time per evaluation (µs)".into(),
            log_x: true,
            log_y: true,
            series: vec![
                Series {
                    label: "B-matrix".into(),
                    points: vec![(4.0, 1.0), (64.0, 16.0)],
                    dashed: false,
                    colour: 0,
                },
                Series {
                    label: "shape integrals".into(),
                    points: vec![(4.0, 2.0), (64.0, 2.0)],
                    dashed: true,
                    colour: 1,
                },
            ],
        };
        chart.write_svg(&path).unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        assert!(
            svg.starts_with("<svg") || svg.contains("<svg"),
            "not an SVG document"
        );
        assert!(svg.trim_end().ends_with("</svg>"), "SVG not closed");
        for text in [
            "elements",
            "time per evaluation",
            "B-matrix",
            "shape integrals",
            "cost",
        ] {
            assert!(svg.contains(text), "missing text {text:?}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}
