//! Writes one blended path, its limits and our TOPP-RA duration as JSON on standard output,
//! for `benches/toppra_compare.py` (issue 19: our timing against the `toppra` package on the
//! same path and limits).
//!
//! `cargo run --release -p pickplace-prm --example toppra_path -- [WAYPOINTS] [SEED]`: a seeded
//! random walk through 7 joints, 5 cm (rad) steps, corners blended within 1 cm, the path
//! sampled every 5 mm of arc length.

use pickplace_prm::rng::Rng;
use pickplace_prm::toppra::{BlendedPath, ToppraOptions, parameterize, sample};
use std::fmt::Write as _;

fn main() {
    let mut args = std::env::args().skip(1);
    let count: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(50);
    let seed: u64 = args.next().and_then(|a| a.parse().ok()).unwrap_or(19);
    let mut rng = Rng::new(seed);
    let mut q = vec![0.0; 7];
    let mut dir = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let mut waypoints = vec![q.clone()];
    for _ in 1..count.max(2) {
        for d in dir.iter_mut() {
            *d += rng.uniform(-0.5, 0.5);
        }
        let n = dir.iter().map(|d| d * d).sum::<f64>().sqrt();
        for (qj, d) in q.iter_mut().zip(dir.iter_mut()) {
            *d /= n;
            *qj += 0.05 * *d;
        }
        waypoints.push(q.clone());
    }
    let options = ToppraOptions {
        max_velocities: vec![1.0, 1.5, 2.0, 3.0, 3.0, 3.0, 3.0],
        max_accelerations: vec![3.0; 7],
        grid_step: 0.005,
        sample_period: 0.01,
    };
    let paths = match BlendedPath::split(&waypoints, 0.01) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(2);
        }
    };
    let mut out = String::from("{\"parts\": [");
    for (k, path) in paths.iter().enumerate() {
        let timing = match parameterize(path, &options) {
            Ok(t) => t,
            Err(e) => {
                eprintln!("error: {e}");
                std::process::exit(2);
            }
        };
        let duration = timing.duration();
        // How close the sampled trajectory comes to the limits (1 = at a limit).
        let (mut v_ratio, mut a_ratio) = (0.0_f64, 0.0_f64);
        if let Ok(traj) = sample(path, &timing, 0.001) {
            for point in &traj.points {
                for j in 0..7 {
                    v_ratio = v_ratio.max(point.velocities[j].abs() / options.max_velocities[j]);
                    a_ratio =
                        a_ratio.max(point.accelerations[j].abs() / options.max_accelerations[j]);
                }
            }
        }
        let n = (path.length() / 0.005).ceil().max(1.0) as usize;
        let (mut p, mut dp, mut ddp) = (vec![0.0; 7], vec![0.0; 7], vec![0.0; 7]);
        let mut s_list = String::new();
        let mut q_list = String::new();
        for i in 0..=n {
            let s = path.length() * i as f64 / n as f64;
            path.eval(s, &mut p, &mut dp, &mut ddp);
            let sep = if i > 0 { ", " } else { "" };
            let _ = write!(s_list, "{sep}{s}");
            let _ = write!(
                q_list,
                "{sep}[{}]",
                p.iter()
                    .map(|v| v.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
        let _ = write!(
            out,
            "{}{{\"duration\": {duration}, \"max_velocity_ratio\": {v_ratio}, \"max_acceleration_ratio\": {a_ratio}, \"s\": [{s_list}], \"q\": [{q_list}]}}",
            if k > 0 { ", " } else { "" }
        );
    }
    let list = |v: &[f64]| {
        v.iter()
            .map(|x| x.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let _ = write!(
        out,
        "], \"max_velocities\": [{}], \"max_accelerations\": [{}], \"waypoints\": {count}}}",
        list(&options.max_velocities),
        list(&options.max_accelerations)
    );
    println!("{out}");
}
