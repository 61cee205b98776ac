//! One-dimensional response tables (docs/model.md §4 law 3): a force or moment against a
//! displacement or angle, from test data.
//!
//! Interpolation is piecewise linear or a monotone-preserving cubic (PCHIP, Fritsch–Carlson
//! 1980: C¹, no overshoot between data points). The table also gives its own integral, the
//! energy `V(q) = ∫₀^q f(u) du`, exactly for either interpolant, so a table law is
//! conservative. Outside the data the scenario chooses: stop with an error, hold the end
//! value, or extend linearly.

use std::path::Path;

/// How a table is interpolated between its points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// Piecewise linear (C⁰).
    Linear,
    /// Piecewise cubic Hermite with Fritsch–Carlson monotone slopes (C¹).
    Pchip,
}

/// What a table does outside its first and last point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outside {
    /// The run stops with an error naming the hinge, direction and value.
    Error,
    /// The end value is held (the force stays constant; its energy grows linearly).
    Clamp,
    /// The end segment's slope continues.
    Extend,
}

/// A tabulated function `f(q)` with its derivative and integral.
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    x: Vec<f64>,
    f: Vec<f64>,
    /// Slopes at the knots (Hermite form; for linear, unused).
    d: Vec<f64>,
    /// `∫_{x0}^{x_i} f`, at each knot.
    cumulative: Vec<f64>,
    /// `∫_{x0}^{0} f`, so that V(0) = 0.
    offset: f64,
    /// Per bucket of equal width over the table's range: the segment holding the bucket's
    /// start, so a lookup is a short search between neighbouring buckets (O(1) for
    /// roughly even spacing, however many points: test data has thousands).
    bucket: Vec<u32>,
    /// Buckets per unit of the abscissa.
    bucket_scale: f64,
    interpolation: Interpolation,
    outside: Outside,
}

impl Table {
    /// A table from points `(x_i, f_i)`, x strictly increasing, at least 2 points, all finite.
    pub fn new(points: &[(f64, f64)], interpolation: Interpolation, outside: Outside) -> Result<Self, String> {
        if points.len() < 2 {
            return Err(format!("a table needs at least 2 points, got {}", points.len()));
        }
        if let Some((i, _)) = points.iter().enumerate().find(|(_, (x, f))| !x.is_finite() || !f.is_finite()) {
            return Err(format!("point {} is not finite", i + 1));
        }
        if let Some(i) = (1..points.len()).find(|&i| points[i].0 <= points[i - 1].0) {
            return Err(format!(
                "the first column must increase strictly: point {} ({}) does not exceed point {} ({})",
                i + 1,
                points[i].0,
                i,
                points[i - 1].0
            ));
        }
        let x: Vec<f64> = points.iter().map(|p| p.0).collect();
        let f: Vec<f64> = points.iter().map(|p| p.1).collect();
        let n = x.len();
        let secant: Vec<f64> = (0..n - 1).map(|i| (f[i + 1] - f[i]) / (x[i + 1] - x[i])).collect();
        let d = match interpolation {
            Interpolation::Linear => vec![0.0; n],
            Interpolation::Pchip => pchip_slopes(&x, &secant),
        };
        let (bucket, bucket_scale) = buckets(&x);
        let mut t =
            Table { x, f, d, cumulative: vec![0.0; n], offset: 0.0, bucket, bucket_scale, interpolation, outside };
        for i in 1..n {
            t.cumulative[i] = t.cumulative[i - 1] + t.segment_integral(i - 1, 1.0);
        }
        t.offset = t.integral_from_start(0.0);
        Ok(t)
    }

    /// First and last abscissa.
    pub fn range(&self) -> (f64, f64) {
        (self.x[0], self.x[self.x.len() - 1])
    }

    /// The data abscissae.
    pub fn points(&self) -> &[f64] {
        &self.x
    }

    /// The interpolation.
    pub fn interpolation(&self) -> Interpolation {
        self.interpolation
    }

    /// The outside policy.
    pub fn outside(&self) -> Outside {
        self.outside
    }

    /// An upper bound on `|f'(q)|` over the table and its linear extension, N/m or N·m/rad:
    /// the largest secant (linear), or per segment `1.5 |Δ| + |d₀| + |d₁|` (the cubic
    /// Hermite's derivative `6s(1−s) Δ + (1−4s+3s²) d₀ + (3s²−2s) d₁` on s ∈ [0, 1]).
    pub fn max_slope(&self) -> f64 {
        let n = self.x.len();
        (0..n - 1)
            .map(|i| {
                let secant = ((self.f[i + 1] - self.f[i]) / (self.x[i + 1] - self.x[i])).abs();
                match self.interpolation {
                    Interpolation::Linear => secant,
                    Interpolation::Pchip => 1.5 * secant + self.d[i].abs() + self.d[i + 1].abs(),
                }
            })
            .fold(0.0, f64::max)
    }

    /// Whether `q` lies in the table's range.
    pub fn contains(&self, q: f64) -> bool {
        let (a, b) = self.range();
        q >= a && q <= b
    }

    /// Index of the piece holding `q` (see [`piece`]).
    pub fn piece(&self, q: f64) -> i64 {
        piece(&self.x, q)
    }

    /// Bounds of piece `p` (see [`piece_bounds`]).
    pub fn piece_bounds(&self, p: i64) -> (f64, f64) {
        piece_bounds(&self.x, p)
    }

    /// The segment holding q (inside the range): the largest i ≤ n − 2 with `x_i ≤ q`.
    fn segment(&self, q: f64) -> usize {
        let (n, nb) = (self.x.len(), self.bucket.len());
        let j = (((q - self.x[0]) * self.bucket_scale).max(0.0) as usize).min(nb - 1);
        // Bucket j holds q up to round-off in j: search from the segment of bucket j − 1's
        // start (at or before q) to that of bucket j + 2's (at or after q).
        let lo = self.bucket[j.saturating_sub(1)] as usize;
        let hi = if j + 2 < nb { self.bucket[j + 2] as usize } else { n - 2 };
        lo + self.x[lo + 1..=hi.max(lo)].partition_point(|&v| v <= q)
    }

    /// Slope used beyond the ends for `Extend`.
    fn end_slope(&self, last: bool) -> f64 {
        let n = self.x.len();
        match self.interpolation {
            Interpolation::Pchip => {
                if last {
                    self.d[n - 1]
                } else {
                    self.d[0]
                }
            }
            Interpolation::Linear => {
                let i = if last { n - 2 } else { 0 };
                (self.f[i + 1] - self.f[i]) / (self.x[i + 1] - self.x[i])
            }
        }
    }

    /// Value and derivative inside segment i at local coordinate s ∈ [0, 1].
    fn inside(&self, i: usize, s: f64) -> (f64, f64) {
        let h = self.x[i + 1] - self.x[i];
        let (f0, f1) = (self.f[i], self.f[i + 1]);
        match self.interpolation {
            Interpolation::Linear => (f0 + s * (f1 - f0), (f1 - f0) / h),
            Interpolation::Pchip => {
                let (d0, d1) = (self.d[i], self.d[i + 1]);
                let s2 = s * s;
                let s3 = s2 * s;
                let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
                let h10 = s3 - 2.0 * s2 + s;
                let h01 = -2.0 * s3 + 3.0 * s2;
                let h11 = s3 - s2;
                let v = h00 * f0 + h10 * h * d0 + h01 * f1 + h11 * h * d1;
                let dh00 = 6.0 * s2 - 6.0 * s;
                let dh10 = 3.0 * s2 - 4.0 * s + 1.0;
                let dh01 = -6.0 * s2 + 6.0 * s;
                let dh11 = 3.0 * s2 - 2.0 * s;
                let dv = (dh00 * f0 + dh01 * f1) / h + dh10 * d0 + dh11 * d1;
                (v, dv)
            }
        }
    }

    /// `∫_{x_i}^{x_i + s h} f` inside segment i.
    fn segment_integral(&self, i: usize, s: f64) -> f64 {
        let h = self.x[i + 1] - self.x[i];
        let (f0, f1) = (self.f[i], self.f[i + 1]);
        match self.interpolation {
            Interpolation::Linear => h * (f0 * s + (f1 - f0) * s * s / 2.0),
            Interpolation::Pchip => {
                let (d0, d1) = (self.d[i], self.d[i + 1]);
                let (s2, s3, s4) = (s * s, s * s * s, s * s * s * s);
                // ∫₀ˢ of the Hermite basis functions.
                let i00 = s4 / 2.0 - s3 + s;
                let i10 = s4 / 4.0 - 2.0 * s3 / 3.0 + s2 / 2.0;
                let i01 = -s4 / 2.0 + s3;
                let i11 = s4 / 4.0 - s3 / 3.0;
                h * (i00 * f0 + i10 * h * d0 + i01 * f1 + i11 * h * d1)
            }
        }
    }

    /// Value and derivative at q, with the outside policy (`Error` behaves as `Extend`
    /// here; the caller checks [`Table::contains`] at accepted states).
    pub fn eval(&self, q: f64) -> (f64, f64) {
        let (a, b) = self.range();
        let n = self.x.len();
        if q < a || q > b {
            let last = q > b;
            let (x_end, f_end) = if last { (b, self.f[n - 1]) } else { (a, self.f[0]) };
            return match self.outside {
                Outside::Clamp => (f_end, 0.0),
                Outside::Extend | Outside::Error => {
                    let slope = self.end_slope(last);
                    (f_end + slope * (q - x_end), slope)
                }
            };
        }
        let i = self.segment(q);
        self.inside(i, (q - self.x[i]) / (self.x[i + 1] - self.x[i]))
    }

    fn integral_from_start(&self, q: f64) -> f64 {
        let (a, b) = self.range();
        let n = self.x.len();
        if q < a || q > b {
            let last = q > b;
            let (x_end, f_end, base) =
                if last { (b, self.f[n - 1], self.cumulative[n - 1]) } else { (a, self.f[0], 0.0) };
            let u = q - x_end;
            let extra = match self.outside {
                Outside::Clamp => f_end * u,
                Outside::Extend | Outside::Error => f_end * u + 0.5 * self.end_slope(last) * u * u,
            };
            return base + extra;
        }
        let i = self.segment(q);
        self.cumulative[i] + self.segment_integral(i, (q - self.x[i]) / (self.x[i + 1] - self.x[i]))
    }

    /// `V(q) = ∫₀^q f(u) du`, exact for the interpolant and the outside policy.
    pub fn integral(&self, q: f64) -> f64 {
        self.integral_from_start(q) - self.offset
    }

    /// Reads a two-column CSV: a header naming the columns with their units, then numeric
    /// rows; lines starting with `#` are comments. Valid headers: first column
    /// `displacement_m`, `angle_rad` or `angle_deg`; second `force_N` or `moment_Nm`.
    /// Returns the points in SI units and whether the first column is an angle.
    pub fn read_csv(path: &Path) -> Result<(Vec<(f64, f64)>, bool), String> {
        let mut reader = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .trim(csv::Trim::All)
            .from_path(path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let headers = reader.headers().map_err(|e| format!("{}: {e}", path.display()))?.clone();
        if headers.len() != 2 {
            return Err(format!(
                "{}: the header must name exactly two columns (e.g. angle_deg,moment_Nm), found {}",
                path.display(),
                headers.len()
            ));
        }
        let (scale, angle) = match &headers[0] {
            "displacement_m" => (1.0, false),
            "angle_rad" => (1.0, true),
            "angle_deg" => (std::f64::consts::PI / 180.0, true),
            other => {
                return Err(format!(
                    "{}: first column '{other}' must be displacement_m, angle_rad or angle_deg",
                    path.display()
                ));
            }
        };
        match (&headers[1], angle) {
            ("force_N", false) | ("moment_Nm", true) => {}
            (other, _) => {
                return Err(format!(
                    "{}: second column '{other}' must be {} to go with '{}'",
                    path.display(),
                    if angle { "moment_Nm" } else { "force_N" },
                    &headers[0]
                ));
            }
        }
        let mut points = Vec::new();
        for (row, record) in reader.records().enumerate() {
            let record = record.map_err(|e| format!("{}: {e}", path.display()))?;
            let line = record.position().map_or(row + 2, |p| p.line() as usize);
            if record.len() != 2 {
                return Err(format!("{}:{line}: expected 2 values, found {}", path.display(), record.len()));
            }
            let parse = |k: usize| -> Result<f64, String> {
                record[k]
                    .parse::<f64>()
                    .map_err(|_| format!("{}:{line}: '{}' is not a number", path.display(), &record[k]))
            };
            points.push((parse(0)? * scale, parse(1)?));
        }
        Ok((points, angle))
    }
}

/// Index of the piece of the increasing `knots` holding `q`: −1 below the first, `n − 1` at
/// or above the last, else the interval `[x_i, x_{i+1})`.
pub fn piece(knots: &[f64], q: f64) -> i64 {
    let n = knots.len() as i64;
    if q < knots[0] {
        -1
    } else if q >= knots[knots.len() - 1] {
        n - 1
    } else {
        (knots.partition_point(|x| *x <= q) - 1) as i64
    }
}

/// The piece of `knots` holding `q` for a memory that holds piece `current`: `current` while
/// q lies within round-off (1e-9 relative) of its bounds, else [`piece`]. At a located
/// crossing the state sits on the knot to within the step's local error, on either side;
/// the crossing's event moves the piece, and a resync there must neither move it a second
/// time nor move it back.
pub fn synced_piece(knots: &[f64], current: i64, q: f64) -> i64 {
    let (lo, hi) = piece_bounds(knots, current);
    let tol = 1e-9 * (1.0 + q.abs());
    if q >= lo - tol && q <= hi + tol { current } else { piece(knots, q) }
}

/// Bounds `[lo, hi)` of piece `p` of `knots` (see [`piece`]), infinite outside them.
pub fn piece_bounds(knots: &[f64], p: i64) -> (f64, f64) {
    let n = knots.len() as i64;
    let at = |i: i64| knots[i as usize];
    match p {
        p if p < 0 => (f64::NEG_INFINITY, at(0)),
        p if p >= n - 1 => (at(n - 1), f64::INFINITY),
        p => (at(p), at(p + 1)),
    }
}

/// Points of a 2-D table read from a long-format CSV: `(u, v, value)` per grid point.
pub struct GridPoints {
    /// Distinct u values, increasing, SI.
    pub u: Vec<f64>,
    /// Distinct v values, increasing, SI.
    pub v: Vec<f64>,
    /// `values[j][i]` at `(u[i], v[j])`.
    pub values: Vec<Vec<f64>>,
    /// Whether u is an angle.
    pub u_angle: bool,
    /// Whether v is an angle.
    pub v_angle: bool,
}

/// Unit scale and angle-ness of a coordinate column name (with an optional prefix).
fn coordinate_unit(name: &str, prefix: &str) -> Option<(f64, bool)> {
    match name.strip_prefix(prefix)? {
        "displacement_m" => Some((1.0, false)),
        "angle_rad" => Some((1.0, true)),
        "angle_deg" => Some((std::f64::consts::PI / 180.0, true)),
        _ => None,
    }
}

impl Table {
    /// Reads a 2-D table in long format: a header `<u>,other_<v>,<value>` with `<u>` and
    /// `<v>` each `displacement_m`, `angle_rad` or `angle_deg` and `<value>` `force_N` or
    /// `moment_Nm` (matching u), then one row per grid point; every (u, v) pair of the grid
    /// must appear exactly once. Lines starting with `#` are comments.
    pub fn read_grid_csv(path: &Path) -> Result<GridPoints, String> {
        let p = path.display();
        let mut reader = csv::ReaderBuilder::new()
            .comment(Some(b'#'))
            .trim(csv::Trim::All)
            .from_path(path)
            .map_err(|e| format!("cannot read {p}: {e}"))?;
        let h = reader.headers().map_err(|e| format!("{p}: {e}"))?.clone();
        let help = "the header must be <u>,other_<v>,<value>, e.g. angle_deg,other_angle_deg,moment_Nm";
        if h.len() != 3 {
            return Err(format!("{p}: {help}"));
        }
        let (su, u_angle) =
            coordinate_unit(&h[0], "").ok_or_else(|| format!("{p}: first column '{}': {help}", &h[0]))?;
        let (sv, v_angle) =
            coordinate_unit(&h[1], "other_").ok_or_else(|| format!("{p}: second column '{}': {help}", &h[1]))?;
        match (&h[2], u_angle) {
            ("moment_Nm", true) | ("force_N", false) => {}
            (other, _) => {
                return Err(format!(
                    "{p}: third column '{other}' must be {}",
                    if u_angle { "moment_Nm" } else { "force_N" }
                ));
            }
        }
        let mut rows = Vec::new();
        for (k, rec) in reader.records().enumerate() {
            let rec = rec.map_err(|e| format!("{p}: {e}"))?;
            let line = rec.position().map_or(k + 2, |q| q.line() as usize);
            let num = |i: usize| {
                rec.get(i).and_then(|x| x.parse::<f64>().ok()).ok_or_else(|| format!("{p}:{line}: expected 3 numbers"))
            };
            rows.push((num(0)? * su, num(1)? * sv, num(2)?, line));
        }
        let mut u: Vec<f64> = rows.iter().map(|r| r.0).collect();
        let mut v: Vec<f64> = rows.iter().map(|r| r.1).collect();
        for x in [&mut u, &mut v] {
            x.sort_by(f64::total_cmp);
            x.dedup();
        }
        if u.len() < 2 || v.len() < 2 {
            return Err(format!("{p}: a 2-D table needs at least 2 values of each coordinate"));
        }
        let mut values = vec![vec![f64::NAN; u.len()]; v.len()];
        for (a, b, f, line) in rows {
            let i = u.iter().position(|x| *x == a).expect("collected");
            let j = v.iter().position(|x| *x == b).expect("collected");
            if !values[j][i].is_nan() {
                return Err(format!("{p}:{line}: the point ({a}, {b}) appears twice"));
            }
            values[j][i] = f;
        }
        if let Some((j, i)) =
            (0..v.len()).flat_map(|j| (0..u.len()).map(move |i| (j, i))).find(|&(j, i)| values[j][i].is_nan())
        {
            return Err(format!("{p}: the grid is incomplete: no value at ({}, {}) (SI units)", u[i], v[j]));
        }
        Ok(GridPoints { u, v, values, u_angle, v_angle })
    }
}

/// The lookup buckets of [`Table::segment`] for abscissae `x` (increasing, n ≥ 2): one per
/// point, each holding the segment of its start, and the buckets per unit of x.
fn buckets(x: &[f64]) -> (Vec<u32>, f64) {
    let n = x.len();
    let scale = n as f64 / (x[n - 1] - x[0]);
    let mut bucket = Vec::with_capacity(n);
    let mut i = 0;
    for j in 0..n {
        let start = x[0] + j as f64 / scale;
        while i < n - 2 && x[i + 1] <= start {
            i += 1;
        }
        bucket.push(i as u32);
    }
    (bucket, scale)
}

/// Fritsch–Carlson monotone slopes for PCHIP (as in SciPy's `PchipInterpolator`).
fn pchip_slopes(x: &[f64], secant: &[f64]) -> Vec<f64> {
    let n = x.len();
    let mut d = vec![0.0; n];
    if n == 2 {
        d[0] = secant[0];
        d[1] = secant[0];
        return d;
    }
    let h: Vec<f64> = (0..n - 1).map(|i| x[i + 1] - x[i]).collect();
    for i in 1..n - 1 {
        let (m0, m1) = (secant[i - 1], secant[i]);
        if m0 * m1 <= 0.0 {
            d[i] = 0.0;
        } else {
            let w1 = 2.0 * h[i] + h[i - 1];
            let w2 = h[i] + 2.0 * h[i - 1];
            d[i] = (w1 + w2) / (w1 / m0 + w2 / m1);
        }
    }
    // One-sided three-point ends, kept shape-preserving.
    let end = |h0: f64, h1: f64, m0: f64, m1: f64| {
        let d = ((2.0 * h0 + h1) * m0 - h0 * m1) / (h0 + h1);
        if d.signum() != m0.signum() {
            0.0
        } else if m0.signum() != m1.signum() && d.abs() > 3.0 * m0.abs() {
            3.0 * m0
        } else {
            d
        }
    };
    d[0] = end(h[0], h[1], secant[0], secant[1]);
    d[n - 1] = end(h[n - 2], h[n - 3], secant[n - 2], secant[n - 3]);
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bucketed lookup finds the same segment as a binary search (the largest i ≤ n − 2
    /// with x_i ≤ q), at every knot, just either side of it, and between, on evenly spaced,
    /// clustered (a thousand points in a thousandth of the range, then a few far apart) and
    /// two-point tables: an off-by-one would pick a neighbouring segment, and the force
    /// there differs by O(1) on these data.
    #[test]
    fn bucketed_lookup_matches_binary_search() {
        let even: Vec<f64> = (0..2000).map(|i| -3.0 + 0.003 * i as f64).collect();
        let mut clustered: Vec<f64> = (0..1000).map(|i| 1e-6 * i as f64).collect();
        clustered.extend([0.5, 0.7, 1.0, 5.0]);
        for xs in [even, clustered, vec![-1.0, 2.0]] {
            let points: Vec<(f64, f64)> = xs.iter().enumerate().map(|(i, &x)| (x, (i % 7) as f64)).collect();
            let t = Table::new(&points, Interpolation::Linear, Outside::Error).expect("valid");
            let n = xs.len();
            let expected = |q: f64| (xs.partition_point(|&v| v <= q) - 1).min(n - 2);
            let mut queries = Vec::new();
            for w in xs.windows(2) {
                queries.extend([w[0], w[0] + (w[1] - w[0]) * 1e-12, 0.5 * (w[0] + w[1]), w[1] - (w[1] - w[0]) * 1e-12]);
            }
            queries.push(xs[n - 1]);
            for q in queries {
                assert_eq!(t.segment(q), expected(q), "q = {q:e} on {n} points");
                let i = expected(q);
                let want = t.inside(i, (q - xs[i]) / (xs[i + 1] - xs[i])).0;
                assert_eq!(t.eval(q).0, want);
            }
        }
    }

    fn points() -> Vec<(f64, f64)> {
        vec![(-1.0, -2.0), (0.0, 0.0), (0.5, 3.0), (1.0, 3.5), (2.0, 3.4), (3.0, 3.4)]
    }

    /// The integral must be the antiderivative of the value: central differences of V
    /// reproduce f to 1e-8 (step 1e-5, V is smooth within segments), inside and outside.
    #[test]
    fn integral_is_antiderivative() {
        for interp in [Interpolation::Linear, Interpolation::Pchip] {
            for outside in [Outside::Clamp, Outside::Extend] {
                let t = Table::new(&points(), interp, outside).unwrap();
                assert!(t.integral(0.0).abs() < 1e-15);
                for q in [-1.7, -0.3, 0.2, 0.7, 1.5, 2.9, 3.6] {
                    let h = 1e-5;
                    let dv = (t.integral(q + h) - t.integral(q - h)) / (2.0 * h);
                    let (f, df) = t.eval(q);
                    assert!((dv - f).abs() < 1e-8, "{interp:?} {outside:?} q={q}: {dv} vs {f}");
                    let dfn = (t.eval(q + h).0 - t.eval(q - h).0) / (2.0 * h);
                    assert!((dfn - df).abs() < 1e-5, "{interp:?} derivative at {q}: {dfn} vs {df}");
                }
            }
        }
    }

    /// PCHIP passes through the data, is C¹ and does not overshoot monotone data.
    #[test]
    fn pchip_is_monotone_and_interpolates() {
        let t = Table::new(&points(), Interpolation::Pchip, Outside::Extend).unwrap();
        for (x, f) in points() {
            assert!((t.eval(x).0 - f).abs() < 1e-14);
        }
        // On [0.5, 1.0] data rise 3.0 → 3.5 and then fall: no value above the peak point.
        let mut q = -1.0;
        while q <= 3.0 {
            assert!(t.eval(q).0 <= 3.5 + 1e-12, "overshoot at {q}");
            q += 0.001;
        }
        // Continuity of the derivative at an interior knot.
        let (l, r) = (t.eval(0.5 - 1e-9).1, t.eval(0.5 + 1e-9).1);
        assert!((l - r).abs() < 1e-6);
    }

    #[test]
    fn rejects_bad_points() {
        assert!(Table::new(&[(0.0, 1.0)], Interpolation::Linear, Outside::Clamp).is_err());
        assert!(Table::new(&[(0.0, 1.0), (0.0, 2.0)], Interpolation::Linear, Outside::Clamp).is_err());
        assert!(Table::new(&[(0.0, 1.0), (1.0, f64::NAN)], Interpolation::Linear, Outside::Clamp).is_err());
    }
}
