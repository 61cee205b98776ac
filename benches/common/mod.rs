//! What the benches share.

/// The machine's load averages (1, 5, 15 min), printed beside every timing since these
/// machines are shared.
pub fn load() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|s| s.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_default()
}
