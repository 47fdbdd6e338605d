//! SVG line charts for the report (plotters, SVG backend, no system fonts needed).

use std::path::Path;

use plotters::prelude::*;

pub use plotters::prelude::SeriesLabelPosition;

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
    /// Where the legend goes.
    pub legend: SeriesLabelPosition,
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

impl LineChart {
    /// Draw the chart into an SVG file at `path`.
    pub fn write_svg(&self, path: &Path) -> Result<(), Box<dyn std::error::Error>> {
        let root = SVGBackend::new(path, (900, 600)).into_drawing_area();
        root.fill(&WHITE)?;
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
        let mut builder = ChartBuilder::on(&root);
        builder
            .caption(&self.title, ("sans-serif", 22))
            .margin(20)
            .x_label_area_size(50)
            .y_label_area_size(80);
        // plotters types the coordinate system by its scale, so the four cases are spelled out.
        match (self.log_x, self.log_y) {
            (true, true) => {
                let mut c =
                    builder.build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
                c.configure_mesh()
                    .x_desc(&self.x_label)
                    .y_desc(&self.y_label)
                    .draw()?;
                self.draw_lines(&mut c)?;
            }
            (true, false) => {
                let mut c = builder.build_cartesian_2d((x0..x1).log_scale(), y0..y1)?;
                c.configure_mesh()
                    .x_desc(&self.x_label)
                    .y_desc(&self.y_label)
                    .draw()?;
                self.draw_lines(&mut c)?;
            }
            (false, true) => {
                let mut c = builder.build_cartesian_2d(x0..x1, (y0..y1).log_scale())?;
                c.configure_mesh()
                    .x_desc(&self.x_label)
                    .y_desc(&self.y_label)
                    .draw()?;
                self.draw_lines(&mut c)?;
            }
            (false, false) => {
                let mut c = builder.build_cartesian_2d(x0..x1, y0..y1)?;
                c.configure_mesh()
                    .x_desc(&self.x_label)
                    .y_desc(&self.y_label)
                    .draw()?;
                self.draw_lines(&mut c)?;
            }
        }
        root.present()?;
        Ok(())
    }

    fn draw_lines<'a, X, Y>(
        &self,
        chart: &mut ChartContext<'a, SVGBackend<'a>, Cartesian2d<X, Y>>,
    ) -> Result<(), String>
    where
        X: Ranged<ValueType = f64>,
        Y: Ranged<ValueType = f64>,
    {
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
                    .map_err(|e| e.to_string())?
                    .label(s.label.as_str())
                    .legend(move |(x, y)| {
                        EmptyElement::at((x, y))
                            + PathElement::new(vec![(0, 0), (8, 0)], style)
                            + PathElement::new(vec![(12, 0), (20, 0)], style)
                    });
            } else {
                chart
                    .draw_series(LineSeries::new(pts.clone(), style))
                    .map_err(|e| e.to_string())?
                    .label(s.label.as_str())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
            }
            // Point markers only where the points are few enough to be read one by one.
            if pts.len() <= 60 {
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 3, colour.filled())))
                    .map_err(|e| e.to_string())?;
            }
        }
        chart
            .configure_series_labels()
            .position(self.legend.clone())
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| e.to_string())?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
            legend: SeriesLabelPosition::UpperLeft,
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
