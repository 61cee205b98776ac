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
