//! A real-time loop: the double four-bar (`models/double_four_bar.ron`, rigid, and with its
//! five bars flexible as `--set bodies.NAME.flexible=true` makes them) stepped in step with
//! the wall clock, its first crank pushed by the host through a `Load` input at every step
//! — a motor torque τ(t) = τ₀ sin 2πft applied as the force τ/|r_B| perpendicular to the
//! crank at its tip B0, whose position the host reads from the sensors after each step (a
//! force, not a torque, so that it also acts on a flexible crank) — as a simulator that
//! drives a display or a hardware loop would.
//!
//! Each step is timed (set the input, step, read the sensors); the loop then sleeps until
//! the wall-clock time of the next step (the last 0.2 ms spinning, since a sleep may wake
//! late). At the end it reports the median, 99th-percentile and worst step time, the
//! real-time margins h / p99 and h / worst, and the steps that ended after their deadline
//! (on a machine busy with other work, some will: the worst case is the scheduler's).
//!
//! Run: `cargo run --release -p flexmbd --example real_time` (paced, 1 s per model), or
//! `-- --unpaced` (as fast as possible), `-- --seconds 5`. `cargo test` runs it unpaced
//! for 0.1 s (the test at the end).

use std::time::{Duration, Instant};

use flexmbd::model::{Force, FormulationKind, Input, InputKind, Scene, V3, parse_set};
use flexmbd::{Error, Simulation};

/// The motor: amplitude τ₀ (N·m) and frequency f (Hz).
const MOTOR: (f64, f64) = (0.5, 0.5);

/// The force at the crank's tip B (x, y) that makes the motor's torque at time t.
fn push(t: f64, tip: (f64, f64)) -> [f64; 6] {
    let (tau0, f) = MOTOR;
    let tau = tau0 * (2.0 * std::f64::consts::PI * f * t).sin();
    let (x, y) = tip;
    let r2 = x * x + y * y;
    [-tau * y / r2, tau * x / r2, 0.0, 0.0, 0.0, 0.0]
}

/// The double four-bar in `formulation`, flexible or not, with the load `motor` at crank1's
/// tip B and the input `motor` on it.
fn four_bar(formulation: FormulationKind, flexible: bool) -> Result<Scene, Error> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../models/double_four_bar.ron"
    );
    let mut scene = Scene::load(path)?;
    if flexible {
        let sets = ["crank1", "coupler1", "crank2", "coupler2", "crank3"]
            .iter()
            .map(|b| parse_set(&format!("bodies.{b}.flexible=true")))
            .collect::<Result<Vec<_>, _>>()?;
        scene.apply_sets(&sets)?;
    }
    scene.solver.formulation = formulation;
    scene.forces.push(Force::Load {
        name: "motor".into(),
        body: "crank1".into(),
        marker: "B".into(),
        force: V3([0.0; 3]),
        torque: V3([0.0; 3]),
    });
    scene.inputs.push(Input {
        name: "motor".into(),
        kind: InputKind::Load {
            force: "motor".into(),
        },
    });
    scene.validate()?;
    Ok(scene)
}

/// Step times of one run (s), and the steps that ended after their deadline.
struct Timing {
    steps: Vec<f64>,
    late: usize,
    h: f64,
}

impl Timing {
    fn quantile(&self, p: f64) -> f64 {
        let mut sorted = self.steps.clone();
        sorted.sort_by(f64::total_cmp);
        sorted[((sorted.len() - 1) as f64 * p).round() as usize]
    }

    fn report(&self, label: &str, paced: bool) -> String {
        let worst = self.quantile(1.0);
        let ms = |s: f64| s * 1e3;
        format!(
            "{label:<28} {} steps of {} ms: median {:.3} ms, p99 {:.3} ms, worst {:.3} ms; margin h/p99 {:.0}x, h/worst {:.1}x{}",
            self.steps.len(),
            ms(self.h),
            ms(self.quantile(0.5)),
            ms(self.quantile(0.99)),
            ms(worst),
            self.h / self.quantile(0.99),
            self.h / worst,
            if paced {
                format!(", {} late", self.late)
            } else {
                String::new()
            }
        )
    }
}

/// Run `scene` for `seconds`, setting the motor every step and reading the sensors; paced
/// to the wall clock or as fast as possible. At the end the crank's tip B0 is checked on
/// its circle about the pin, to `tolerance` (m; a flexible crank bends).
fn run(scene: &Scene, seconds: f64, paced: bool, tolerance: f64) -> Result<Timing, Error> {
    let mut sim = Simulation::new(scene)?;
    let motor = sim.input("motor")?;
    let (bx, by) = (sim.sensor_index("B0_x")?, sim.sensor_index("B0_y")?);
    let mut sensors = vec![0.0; sim.sensor_names().len()];
    sim.read_sensors(&mut sensors);
    let h = sim.step_size();
    let n = (seconds / h).round() as usize;
    let mut timing = Timing {
        steps: Vec::with_capacity(n),
        late: 0,
        h,
    };
    let spin = Duration::from_micros(200);
    let start = Instant::now();
    for k in 1..=n {
        let clock = Instant::now();
        sim.set_input(motor, &push(sim.time(), (sensors[bx], sensors[by])))?;
        sim.step()?;
        sim.read_sensors(&mut sensors);
        timing.steps.push(clock.elapsed().as_secs_f64());
        if paced {
            let deadline = start + Duration::from_secs_f64(k as f64 * h);
            match deadline.checked_duration_since(Instant::now()) {
                Some(wait) => {
                    std::thread::sleep(wait.saturating_sub(spin));
                    while Instant::now() < deadline {
                        std::hint::spin_loop();
                    }
                }
                None => timing.late += 1,
            }
        }
    }
    let radius = sensors[bx].hypot(sensors[by]);
    assert!(
        (radius - 1.0).abs() < tolerance,
        "B0 {radius} m from the pin of a 1 m crank"
    );
    Ok(timing)
}

/// Every model and formulation, one line each.
fn run_all(seconds: f64, paced: bool) -> Result<Vec<String>, Error> {
    let mut lines = Vec::new();
    for flexible in [false, true] {
        for formulation in [FormulationKind::Absolute, FormulationKind::Relative] {
            let scene = four_bar(formulation, flexible)?;
            let label = format!(
                "{} four-bar, {}",
                if flexible { "flexible" } else { "rigid" },
                match formulation {
                    FormulationKind::Absolute => "absolute",
                    FormulationKind::Relative => "relative",
                }
            );
            let tolerance = if flexible { 0.1 } else { 1e-6 };
            lines.push(run(&scene, seconds, paced, tolerance)?.report(&label, paced));
        }
    }
    Ok(lines)
}

fn main() -> Result<(), Error> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let paced = !args.iter().any(|a| a == "--unpaced");
    let seconds = match args.iter().position(|a| a == "--seconds") {
        Some(k) => args
            .get(k + 1)
            .and_then(|s| s.parse::<f64>().ok())
            .filter(|s| *s > 0.0 && *s <= 3600.0)
            .unwrap_or_else(|| {
                eprintln!("--seconds takes a duration in (0, 3600] s");
                std::process::exit(2)
            }),
        None => 1.0,
    };
    println!(
        "double four-bar, a motor on the crank set by the host every step ({}):",
        if paced {
            "paced to the wall clock"
        } else {
            "unpaced"
        }
    );
    for line in run_all(seconds, paced)? {
        println!("{line}");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    /// The example's loop, unpaced and short: every model runs with the host's motor.
    #[test]
    fn real_time_loop_runs_unpaced() {
        let lines = super::run_all(0.1, false).unwrap();
        assert_eq!(lines.len(), 4, "{lines:?}");
        assert!(lines.iter().all(|l| l.contains("100 steps")), "{lines:?}");
    }
}
