//! The work-precision PNG: error against seconds, log-log, our curves solid with dots, peers' dashed.

use plotters::prelude::*;
use std::path::Path;
use std::sync::Once;
use tumble_integrate::work_precision::PrecisionRun;

static FONT: Once = Once::new();

/// Groups runs by curve label, keeping the sweep order.
fn curves(runs: &[PrecisionRun]) -> Vec<(String, Vec<(f64, f64)>)> {
    let mut out: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for r in runs.iter().filter(|r| r.error > 0.0 && r.seconds > 0.0) {
        match out.iter_mut().find(|(l, _)| *l == r.method) {
            Some((_, pts)) => pts.push((r.seconds, r.error)),
            None => out.push((r.method.clone(), vec![(r.seconds, r.error)])),
        }
    }
    out
}

fn decade_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if !lo.is_finite() {
        return (1e-6, 1.0);
    }
    (10f64.powf(lo.log10().floor()), 10f64.powf(hi.log10().ceil().max(lo.log10().floor() + 1.0)))
}

pub fn work_precision(
    path: &Path,
    problem: &str,
    ours: &[PrecisionRun],
    peers: &[PrecisionRun],
) -> Result<(), Box<dyn std::error::Error>> {
    FONT.call_once(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular()).ok();
    });
    let (ours, peers) = (curves(ours), curves(peers));
    let all = ours.iter().chain(&peers).flat_map(|(_, p)| p.iter().copied());
    let (xlo, xhi) = decade_range(all.clone().map(|p| p.0));
    let (ylo, yhi) = decade_range(all.map(|p| p.1));

    let root = BitMapBackend::new(path, (1000, 700)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(format!("{problem}: error against run time"), ("sans-serif", 24))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d((xlo..xhi).log_scale(), (ylo..yhi).log_scale())?;
    chart
        .configure_mesh()
        .x_desc("seconds (fastest of repeated runs)")
        .y_desc("final error")
        .x_label_formatter(&|v| format!("{v:.0e}"))
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style(("sans-serif", 15))
        .draw()?;
    for (i, (label, pts)) in ours.iter().enumerate() {
        let color = Palette99::pick(i).to_rgba();
        chart
            .draw_series(LineSeries::new(pts.clone(), color.stroke_width(2)))?
            .label(label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 22, y)], color.stroke_width(2)));
        chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))?;
    }
    for (i, (label, pts)) in peers.iter().enumerate() {
        let color = Palette99::pick(ours.len() + i).to_rgba();
        chart
            .draw_series(DashedLineSeries::new(pts.clone(), 8, 5, color.stroke_width(2)))?
            .label(label.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 22, y)], color.stroke_width(1)));
        chart.draw_series(pts.iter().map(|&p| TriangleMarker::new(p, 5, color.filled())))?;
    }
    chart
        .configure_series_labels()
        .label_font(("sans-serif", 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()?;
    root.present()?;
    Ok(())
}
