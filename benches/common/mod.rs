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
