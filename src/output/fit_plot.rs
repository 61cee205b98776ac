//! A fit's data against its fitted model, as PNG (feature `plot`; `foldsim fit --plot`): one
//! panel per measured column, the measurements as points, the model as a line (in the data's
//! order: a law driven up and down draws its loop).

use super::plot::register;
use plotters::prelude::*;
use std::path::Path;

/// One measured column beside the fitted run's.
pub struct Compared<'a> {
    /// The column's name.
    pub name: &'a str,
    /// Its unit ("" for a pure number).
    pub unit: &'a str,
    /// Where each value is (the time, or a law's coordinate), in the data's order.
    pub abscissa: &'a [f64],
    /// The measurements at the times (`None`: not measured then), in the column's unit.
    pub measured: &'a [Option<f64>],
    /// The fitted model's values at the same points.
    pub fitted: &'a [f64],
}

/// Draws `columns` against their abscissa (labelled `x_label`) into the PNG `out` (through
/// `<name>.partial.png`, renamed when complete).
pub fn plot_fit(columns: &[Compared<'_>], x_label: &str, title: &str, out: &Path) -> Result<(), String> {
    register();
    let xs = columns.iter().flat_map(|c| c.abscissa.iter().copied()).filter(|x| x.is_finite());
    let (t0, t1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
    let (t0, t1) = if t0.is_finite() && (t1 - t0).is_finite() { (t0, t1) } else { (0.0, 1.0) };
    let partial = out.with_file_name(format!(
        "{}.partial.png",
        out.file_stem().map_or_else(|| "fit".into(), |s| s.to_string_lossy().into_owned())
    ));
    let result = draw(&partial, x_label, (t0, t1), columns, title);
    match result {
        Ok(()) => std::fs::rename(&partial, out)
            .map_err(|e| format!("cannot rename {} to {}: {e}", partial.display(), out.display())),
        Err(e) => {
            let _ = std::fs::remove_file(&partial);
            Err(format!("cannot draw the plot {}: {e}", out.display()))
        }
    }
}

fn draw(out: &Path, x_label: &str, (t0, t1): (f64, f64), columns: &[Compared<'_>], title: &str) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let panels = columns.len().clamp(1, 8);
    let root = BitMapBackend::new(out, (1200, 120 + 300 * panels as u32)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let root = root.titled(title, ("sans-serif", 22)).map_err(|e| err(&e))?;
    let areas = root.split_evenly((panels, 1));
    for (k, (area, c)) in areas.iter().zip(columns).enumerate() {
        let values = c.measured.iter().flatten().copied().chain(c.fitted.iter().copied()).filter(|v| v.is_finite());
        let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
        let (lo, hi) = if lo.is_finite() && (hi - lo).is_finite() { (lo, hi) } else { (-1.0, 1.0) };
        let pad = 0.05 * (hi - lo).max(1e-12 * hi.abs().max(1.0));
        let last = k + 1 == panels;
        let mut chart = ChartBuilder::on(area)
            .margin(12)
            .x_label_area_size(if last { 45 } else { 25 })
            .y_label_area_size(90)
            .build_cartesian_2d(t0..t1.max(t0 + 1e-12), (lo - pad)..(hi + pad))
            .map_err(|e| err(&e))?;
        let unit = c.unit;
        chart
            .configure_mesh()
            .x_desc(if last { x_label } else { "" })
            .y_desc(if unit.is_empty() { c.name.to_string() } else { format!("{} ({unit})", c.name) })
            .label_style(("sans-serif", 15))
            .draw()
            .map_err(|e| err(&e))?;
        let data = RGBColor(30, 30, 30);
        let run = RGBColor(200, 40, 40);
        chart
            .draw_series(
                c.abscissa
                    .iter()
                    .zip(c.measured)
                    .filter_map(|(t, v)| v.map(|v| Circle::new((*t, v), 2, data.filled()))),
            )
            .map_err(|e| err(&e))?
            .label(format!("{} measured", c.name))
            .legend(move |(x, y)| Circle::new((x + 10, y), 3, data.filled()));
        chart
            .draw_series(LineSeries::new(c.abscissa.iter().copied().zip(c.fitted.iter().copied()), run.stroke_width(2)))
            .map_err(|e| err(&e))?
            .label("fitted model")
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], run.stroke_width(2)));
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 15))
            .draw()
            .map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
