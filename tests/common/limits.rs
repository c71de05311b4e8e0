//! Joint limits checked by finite differences over exported points (tests/export.rs, tests/ros2.rs).

/// Finite differences over exported points `(time, positions, velocities)`: every joint's speed
/// over every interval within `vlim` (its scaled velocity limit), the change of speed between
/// adjacent intervals over the distance of their midpoints within `alim` (the scaled acceleration
/// limit), and the recorded velocities continuous: they change by at most `alim · dt`. The only
/// slack is for time stamps rounded to the nanosecond (each off by ≤ 0.5 ns).
pub fn assert_finite_difference_limits(points: &[(f64, &[f64], &[f64])], vlim: &[f64], alim: f64) {
    let n = vlim.len();
    let mut prev: Option<(Vec<f64>, f64)> = None;
    for w in points.windows(2) {
        let dt = w[1].0 - w[0].0;
        assert!(dt > 0.0, "time runs forward");
        let fd: Vec<f64> = (0..n).map(|j| (w[1].1[j] - w[0].1[j]) / dt).collect();
        for j in 0..n {
            assert!(
                fd[j].abs() <= vlim[j] * (1.0 + 1e-9 / dt) + 1e-12,
                "joint {j}: {} rad/s over {} (dt {dt})",
                fd[j],
                vlim[j]
            );
            let jump = (w[1].2[j] - w[0].2[j]).abs();
            assert!(
                jump <= alim * (dt + 1e-9) * (1.0 + 1e-9) + 1e-12,
                "joint {j}: recorded velocity jumps {jump} rad/s in {dt} s at t = {}",
                w[1].0
            );
        }
        if let Some((fp, dp)) = &prev {
            let mid = 0.5 * (dp + dt);
            for j in 0..n {
                let acc = (fd[j] - fp[j]).abs() / mid;
                let rounding = 1e-9 * (fd[j].abs() / dt + fp[j].abs() / dp) / mid;
                assert!(
                    acc <= alim * (1.0 + 1e-9) + rounding + 1e-9,
                    "joint {j}: {acc} rad/s² over {alim} at t = {}",
                    w[0].0
                );
            }
        }
        prev = Some((fd, dt));
    }
}

/// The scaled limits of a plan: velocity limits per joint and `acceleration × scale²`.
pub fn scaled_limits(plan: &pushpack::plan::Plan) -> (Vec<f64>, f64) {
    let r = plan.robot.as_ref().unwrap();
    let s = r.timing.velocity_scale;
    (r.velocity_limits.clone(), r.timing.acceleration * s * s)
}
