//! reach's half of `bench/peers/toppra_compare.py`: time-optimal parameterisation
//! (`reach::motion::time_optimal`, TOPP-RA) of cubic-spline paths read from a file, the same
//! paths toppra times.
//!
//! ```text
//! retime_timing PATHS_FILE POINTS_PER_PIECE ROUNDS
//! ```
//!
//! PATHS_FILE, whitespace-separated numbers: the velocity limits (one line, one per joint),
//! the acceleration limits (one line), then each path as a line `n` followed by `n` lines of
//! waypoints (radians). Prints one JSON line per path: the duration (s), the grid points, the
//! worst ratios to the limits, and the median over ROUNDS of the time of one
//! `PiecewiseCubic::spline` + `time_optimal` call (ns), after a warm-up call.

use std::hint::black_box;
use std::time::Instant;

use reach::motion::{PathLimits, PiecewiseCubic, time_optimal};
use reach_peers_bench::median;

fn numbers(line: &str) -> Vec<f64> {
    line.split_whitespace().map(|v| v.parse().expect("a number")).collect()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [file, per, rounds] = args.as_slice() else {
        eprintln!("usage: retime_timing PATHS_FILE POINTS_PER_PIECE ROUNDS");
        std::process::exit(2);
    };
    let per: usize = per.parse().expect("POINTS_PER_PIECE");
    let rounds: usize = rounds.parse().expect("ROUNDS");
    let text = std::fs::read_to_string(file).expect("read the paths file");
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let velocity = numbers(lines.next().expect("velocity limits"));
    let acceleration = numbers(lines.next().expect("acceleration limits"));
    let limits = PathLimits::new(velocity, acceleration).expect("limits");
    while let Some(count) = lines.next() {
        let n: usize = count.trim().parse().expect("waypoint count");
        let waypoints: Vec<Vec<f64>> = (0..n).map(|_| numbers(lines.next().expect("waypoint"))).collect();
        let run = || {
            let path = PiecewiseCubic::spline(&waypoints).expect("path");
            time_optimal(&path, &limits, per).expect("parameterisation")
        };
        let motion = run();
        let mut times: Vec<f64> = (0..rounds)
            .map(|_| {
                let start = Instant::now();
                black_box(run());
                start.elapsed().as_nanos() as f64
            })
            .collect();
        let ratios = motion.worst_ratios();
        let worst = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
        println!(
            "{{\"duration_s\": {:?}, \"grid_points\": {}, \"slowdown\": {:?}, \"worst_velocity_ratio\": {:?}, \"worst_acceleration_ratio\": {:?}, \"ns\": {:?}}}",
            motion.duration(),
            motion.grid_points(),
            motion.slowdown(),
            worst(&ratios.velocity),
            worst(&ratios.acceleration),
            median(&mut times)
        );
    }
}
