//! Line plots of output columns against time, as PNG (feature `plot`).

use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};
use std::path::Path;
use std::sync::Once;

static FONT: Once = Once::new();

fn register() {
    FONT.call_once(|| {
        // DejaVu Sans (assets/DejaVuSans-LICENSE.txt): embedded so no system font is needed.
        let bytes: &'static [u8] = include_bytes!("../../assets/DejaVuSans.ttf");
        let _ = register_font("sans-serif", FontStyle::Normal, bytes);
    });
}

/// Plots `columns` of the foldsim CSV `csv` against `t` into the PNG `out`. With `degrees`,
/// angle columns (ending in `_yaw`, `_pitch`, `_roll`) are shown in degrees.
pub fn plot_columns(csv: &Path, columns: &[String], degrees: bool, title: &str, out: &Path) -> Result<(), String> {
    register();
    let mut reader = csv::Reader::from_path(csv).map_err(|e| format!("cannot read {}: {e}", csv.display()))?;
    let header: Vec<String> =
        reader.headers().map_err(|e| format!("{}: {e}", csv.display()))?.iter().map(str::to_string).collect();
    let find = |name: &str| {
        header
            .iter()
            .position(|h| h == name)
            .ok_or_else(|| format!("{}: no column '{name}'; columns are: {}", csv.display(), header.join(", ")))
    };
    let t_col = find("t")?;
    let cols: Vec<usize> = columns.iter().map(|c| find(c)).collect::<Result<_, _>>()?;
    let is_angle = |c: &str| c.ends_with("_yaw") || c.ends_with("_pitch") || c.ends_with("_roll");
    let mut t = Vec::new();
    let mut series: Vec<Vec<f64>> = vec![Vec::new(); cols.len()];
    for (line, rec) in reader.records().enumerate() {
        let rec = rec.map_err(|e| format!("{}: {e}", csv.display()))?;
        let num = |k: usize| {
            rec[k].parse::<f64>().map_err(|_| format!("{}:{}: '{}' is not a number", csv.display(), line + 2, &rec[k]))
        };
        t.push(num(t_col)?);
        for (s, (&k, name)) in series.iter_mut().zip(cols.iter().zip(columns)) {
            let v = num(k)?;
            s.push(if degrees && is_angle(name) { v.to_degrees() } else { v });
        }
    }
    if t.is_empty() {
        return Err(format!("{}: no rows", csv.display()));
    }
    let (t0, t1) = (t[0], *t.last().unwrap_or(&t[0]));
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in series.iter().flatten() {
        lo = lo.min(*v);
        hi = hi.max(*v);
    }
    let pad = 0.05 * (hi - lo).max(1e-12);
    let root = BitMapBackend::new(out, (1200, 700)).into_drawing_area();
    let err = |e: &dyn std::fmt::Display| format!("plotting {}: {e}", out.display());
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 26))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(t0..t1.max(t0 + 1e-12), (lo - pad)..(hi + pad))
        .map_err(|e| err(&e))?;
    let unit = if degrees && columns.iter().all(|c| is_angle(c)) { " (deg)" } else { "" };
    chart
        .configure_mesh()
        .x_desc("t (s)")
        .y_desc(format!("value{unit}"))
        .label_style(("sans-serif", 16))
        .draw()
        .map_err(|e| err(&e))?;
    for (i, (s, name)) in series.iter().zip(columns).enumerate() {
        let color = Palette99::pick(i).to_rgba();
        chart
            .draw_series(LineSeries::new(t.iter().copied().zip(s.iter().copied()), color.stroke_width(2)))
            .map_err(|e| err(&e))?
            .label(name.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 16))
        .draw()
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
