//! Helpers shared by the `harness = false` benchmark programs.

/// Value of `--name VALUE` on the command line, or `default` when absent or unparsable.
pub fn arg<T: std::str::FromStr>(args: &[String], name: &str, default: T) -> T {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// Median of a sample ([`pushpack::report::median`]); NaN when empty.
pub fn median(v: &[f64]) -> f64 {
    pushpack::report::median(v).unwrap_or(f64::NAN)
}

/// Seeds to run: `--seeds 3,7` (for instrumented reruns of single instances), else `0..count`.
pub fn seeds(args: &[String], count: u64) -> Vec<u64> {
    match args.iter().position(|a| a == "--seeds") {
        Some(i) => args
            .get(i + 1)
            .map(|v| v.split(',').filter_map(|s| s.parse().ok()).collect())
            .unwrap_or_default(),
        None => (0..count).collect(),
    }
}
