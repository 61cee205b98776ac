//! Line plots of output columns against time, as PNG (feature `plot`).

pub use super::units::unit_of;
use plotters::prelude::*;
use plotters::style::{FontStyle, register_font};
use std::path::Path;
use std::sync::Once;

static FONT: Once = Once::new();

/// Registers the embedded font (once).
pub(crate) fn register() {
    FONT.call_once(|| {
        // DejaVu Sans (assets/DejaVuSans-LICENSE.txt): embedded so no system font is needed.
        let bytes: &'static [u8] = include_bytes!("../../assets/DejaVuSans.ttf");
        let _ = register_font("sans-serif", FontStyle::Normal, bytes);
    });
}

/// Plots `columns` of the foldsim CSV `csv` against `t` into the PNG `out`. With `degrees`,
/// angle columns (ending in `_yaw`, `_pitch`, `_roll`) are shown in degrees. Non-finite
/// values (NaN, ±inf) are left out, as gaps in their lines; a plot whose columns have no
/// finite value is refused. Columns of one unit share a panel, its y axis labelled with the
/// unit; each unit has its own panel, one above the other on a common t axis. An empty
/// `title` becomes the columns and the file's name.
pub fn plot_columns(csv: &Path, columns: &[String], degrees: bool, title: &str, out: &Path) -> Result<(), String> {
    if !out.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")) {
        return Err(format!("-o {}: the plot is written as PNG; name a .png file", out.display()));
    }
    super::paths::check_outputs(&[csv.to_path_buf()], &[("-o", out)])?;
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
    let finite_t: Vec<f64> = t.iter().copied().filter(|x| x.is_finite()).collect();
    if finite_t.is_empty() {
        return Err(format!("{}: no rows with a finite time", csv.display()));
    }
    let (t0, t1) = finite_t.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    // A span that f64 cannot hold (t from -1e308 to 1e308) would leave the axes without
    // ticks to place: the plotting library loops for ever.
    if !(t1 - t0).is_finite() {
        return Err(format!(
            "{}: t runs from {} to {} s, a span too wide to plot",
            csv.display(),
            crate::math::short(t0),
            crate::math::short(t1)
        ));
    }
    let units: Vec<&str> = columns.iter().map(|c| if degrees && is_angle(c) { "deg" } else { unit_of(c) }).collect();
    // One panel per unit, in the order the columns name them: metres and radians never
    // share an axis.
    let mut panels: Vec<Panel> = Vec::new();
    for (i, u) in units.iter().enumerate() {
        match panels.iter_mut().find(|p| p.unit == *u) {
            Some(p) => p.members.push(i),
            None => panels.push(Panel { unit: u, members: vec![i], lo: f64::INFINITY, hi: f64::NEG_INFINITY }),
        }
    }
    for p in &mut panels {
        for (tk, v) in p.members.iter().flat_map(|&i| t.iter().zip(&series[i])) {
            if tk.is_finite() && v.is_finite() {
                p.lo = p.lo.min(*v);
                p.hi = p.hi.max(*v);
            }
        }
        if !(p.hi - p.lo).is_finite() && p.lo.is_finite() {
            return Err(format!(
                "{}: the values run from {} to {}, a span too wide to plot",
                csv.display(),
                crate::math::short(p.lo),
                crate::math::short(p.hi)
            ));
        }
    }
    if panels.iter().all(|p| !p.lo.is_finite()) {
        return Err(format!("{}: the columns {} have no finite value to plot", csv.display(), columns.join(", ")));
    }
    let title = if title.is_empty() {
        format!("{} — {}", columns.join(", "), csv.file_name().map_or_else(String::new, |f| f.to_string_lossy().into()))
    } else {
        title.to_string()
    };
    // Drawn to `<name>.partial.png` (the backend picks the format by extension), renamed
    // when complete: a failed plot leaves no file that looks complete.
    let partial = out.with_file_name(format!(
        "{}.partial.png",
        out.file_stem().map_or_else(|| "plot".into(), |s| s.to_string_lossy().into_owned())
    ));
    let result = draw(&partial, &title, (t0, t1), &t, &series, columns, &panels);
    match result {
        Ok(()) => std::fs::rename(&partial, out)
            .map_err(|e| format!("cannot rename {} to {}: {e}", partial.display(), out.display())),
        Err(e) => {
            let _ = std::fs::remove_file(&partial);
            Err(format!("cannot draw the plot {}: {e}", out.display()))
        }
    }
}

/// One panel of the plot: the columns of one unit and their range.
struct Panel<'u> {
    /// The unit ("" for a pure number).
    unit: &'u str,
    /// Indices of its columns.
    members: Vec<usize>,
    /// The smallest and largest finite value (infinite when there is none).
    lo: f64,
    hi: f64,
}

/// Draws the plot into the PNG file `out`: the panels one above the other, sharing t.
fn draw(
    out: &Path,
    title: &str,
    (t0, t1): (f64, f64),
    t: &[f64],
    series: &[Vec<f64>],
    columns: &[String],
    panels: &[Panel<'_>],
) -> Result<(), String> {
    let height = 160 + 380 * panels.len().min(6) as u32;
    let root = BitMapBackend::new(out, (1200, height)).into_drawing_area();
    let err = |e: &dyn std::fmt::Display| e.to_string();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let root = root.titled(title, ("sans-serif", 26)).map_err(|e| err(&e))?;
    let areas = root.split_evenly((panels.len(), 1));
    for (k, (area, panel)) in areas.iter().zip(panels).enumerate() {
        let (lo, hi) = if panel.lo.is_finite() { (panel.lo, panel.hi) } else { (-1.0, 1.0) };
        let pad = 0.05 * (hi - lo).max(1e-12 * hi.abs().max(1.0));
        let last = k + 1 == panels.len();
        let mut chart = ChartBuilder::on(area)
            .margin(15)
            .x_label_area_size(if last { 45 } else { 25 })
            .y_label_area_size(90)
            .build_cartesian_2d(t0..t1.max(t0 + 1e-12), (lo - pad)..(hi + pad))
            .map_err(|e| err(&e))?;
        let y_desc = if panel.unit.is_empty() { "value".to_string() } else { format!("value ({})", panel.unit) };
        chart
            .configure_mesh()
            .x_desc(if last { "t (s)" } else { "" })
            .y_desc(y_desc)
            .label_style(("sans-serif", 16))
            .draw()
            .map_err(|e| err(&e))?;
        for &i in &panel.members {
            let (s, name) = (&series[i], &columns[i]);
            let color = Palette99::pick(i).to_rgba();
            // One line per run of finite points: a non-finite value is a gap, not a spike.
            let mut runs: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
            for (&tk, &v) in t.iter().zip(s) {
                if tk.is_finite() && v.is_finite() {
                    runs.last_mut().expect("one run at least").push((tk, v));
                } else if !runs.last().expect("one run at least").is_empty() {
                    runs.push(Vec::new());
                }
            }
            if runs.iter().all(Vec::is_empty) {
                // Nothing to draw: say so in the legend.
                let label = format!("{name} (no finite value)");
                chart
                    .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
                    .map_err(|e| err(&e))?
                    .label(label.as_str())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
            }
            for (r, run) in runs.into_iter().filter(|r| !r.is_empty()).enumerate() {
                let drawn = chart.draw_series(LineSeries::new(run, color.stroke_width(2))).map_err(|e| err(&e))?;
                if r == 0 {
                    drawn
                        .label(name.as_str())
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
                }
            }
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 16))
            .draw()
            .map_err(|e| err(&e))?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_follow_the_column_names() {
        for (column, unit) in [
            ("t", "s"),
            ("h1_yaw", "rad"),
            ("theta_B_roll", "rad"),
            ("h1_delta_x", "m"),
            ("h1_delta_rate_z", "m/s"),
            ("h1_wrel_y", "rad/s"),
            ("w_B_z", "rad/s"),
            ("p1_v_x", "m/s"),
            ("p1_w_z", "rad/s"),
            ("p1_R_y", "m"),
            ("R_B_x", "m"),
            ("BR_B_z", "m"),
            ("Rc_x", "m"),
            ("P_y", "kg·m/s"),
            ("H_z", "kg·m²/s"),
            ("E", "J"),
            ("whatever", ""),
        ] {
            assert_eq!(unit_of(column), unit, "{column}");
        }
    }
}
