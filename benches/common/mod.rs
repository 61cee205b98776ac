//! What the benches share.

/// The machine's load averages (1, 5, 15 min), printed beside every timing since these
/// machines are shared.
pub fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_default()
}

/// The value of `--repeat N` among the bench's arguments (default 3).
#[allow(dead_code)]
pub fn repeat_arg(args: &[String]) -> usize {
    args.iter().position(|a| a == "--repeat").and_then(|i| args.get(i + 1)).and_then(|v| v.parse().ok()).unwrap_or(3)
}

/// Seconds per call of `f`, over at least 0.5 s.
#[allow(dead_code)]
pub fn per_call(mut f: impl FnMut()) -> f64 {
    let (start, mut n) = (std::time::Instant::now(), 0u32);
    while n < 3 || start.elapsed().as_secs_f64() < 0.5 {
        f();
        n += 1;
    }
    start.elapsed().as_secs_f64() / f64::from(n)
}

/// Prints where a run's `wall` seconds went: each part's (name, seconds, unit cost) as
/// unit costs at the state named by `at` times counts, then the rest.
#[allow(dead_code)]
pub fn print_breakdown(parts: &[(&str, f64, String)], wall: f64, at: &str) {
    let mut accounted = 0.0;
    println!("where the time goes (unit costs at {at} × counts):");
    for (name, t, unit) in parts {
        accounted += t;
        println!("  {name:<28} {t:7.3} s  {:5.1} %  ({unit})", 100.0 * t / wall);
    }
    println!("  {:<28} {:7.3} s  {:5.1} %", "the rest", wall - accounted, 100.0 * (wall - accounted) / wall);
}
