//! The Iltis bump scene (`models/iltis_bump.ron`, docs/scenes.md §3.3) at another forward
//! speed: the `--set` overrides of the speed and of the lateral tyre dampers C_α/V
//! (docs/scenes.md §3.4), which the model file writes for 5 m/s. The Iltis suspension
//! (`models/iltis_suspension.ron`, scene B): the overrides that make its first k beam bodies
//! flexible, in the order of docs/scenes.md §2.8. The Iltis vehicle (`models/iltis_vehicle.ron`,
//! scene C): the same overrides for its twelve beam bodies (§3.4).

/// S9's cornering stiffness per corner (N/rad; user_ExtForces.c, docs/scenes.md §2.5).
pub const CORNERING_STIFFNESS: [(&str, f64); 4] = [
    ("fl", 41641.0),
    ("fr", 41641.0),
    ("rl", 40162.0),
    ("rr", 40162.0),
];

/// `PATH=VALUE` overrides that run the bump scene at `speed` (m/s).
pub fn bump_at_speed(speed: f64) -> Vec<String> {
    let mut sets = vec![format!("initial_velocity.0={speed}")];
    for (corner, cornering) in CORNERING_STIFFNESS {
        sets.push(format!(
            "forces.tyre_{corner}.lateral_damping={}",
            cornering / speed
        ));
    }
    sets
}

/// The suspension's beam bodies in the order they are switched flexible (docs/scenes.md §2.8).
pub const SUSPENSION_BEAMS: [&str; 3] = ["aarm_fl", "leaf_link_fl", "tie_rod_fl"];

/// `PATH=VALUE` overrides that make the first `k` (0 … 3) beam bodies of the suspension
/// flexible.
pub fn suspension_flexible(k: usize) -> Vec<String> {
    SUSPENSION_BEAMS[..k]
        .iter()
        .map(|b| format!("bodies.{b}.flexible=true"))
        .collect()
}

/// `PATH=VALUE` overrides that scale Young's modulus of every suspension beam by `factor`
/// (steel's 2.1e11 Pa, docs/scenes.md §2.8).
pub fn suspension_stiffness(factor: f64) -> Vec<String> {
    young_modulus_scaled(&SUSPENSION_BEAMS, factor)
}

/// The vehicle's beam bodies (`models/iltis_vehicle.ron`, scene C) in the order they are
/// switched flexible: corner by corner FL, FR, RL, RR, each in the order of §2.8 (A-arm, leaf
/// link, tie rod; docs/scenes.md §3.4).
pub const VEHICLE_BEAMS: [&str; 12] = [
    "aarm_fl",
    "leaf_link_fl",
    "tie_rod_fl",
    "aarm_fr",
    "leaf_link_fr",
    "tie_rod_fr",
    "aarm_rl",
    "leaf_link_rl",
    "tie_rod_rl",
    "aarm_rr",
    "leaf_link_rr",
    "tie_rod_rr",
];

/// `PATH=VALUE` overrides that make the first `k` (0 … 12) beam bodies of the vehicle
/// flexible, in the order of [`VEHICLE_BEAMS`].
pub fn vehicle_flexible(k: usize) -> Vec<String> {
    VEHICLE_BEAMS[..k]
        .iter()
        .map(|b| format!("bodies.{b}.flexible=true"))
        .collect()
}

/// `PATH=VALUE` overrides that make the four A-arms of the vehicle flexible (the "4 flexible
/// bodies" case of the CPU table).
pub fn vehicle_aarms_flexible() -> Vec<String> {
    ["fl", "fr", "rl", "rr"]
        .iter()
        .map(|c| format!("bodies.aarm_{c}.flexible=true"))
        .collect()
}

/// `PATH=VALUE` overrides that scale Young's modulus of every beam body of the vehicle by
/// `factor` (steel's 2.1e11 Pa, docs/scenes.md §2.8).
pub fn vehicle_stiffness(factor: f64) -> Vec<String> {
    young_modulus_scaled(&VEHICLE_BEAMS, factor)
}

/// `PATH=VALUE` overrides that set Young's modulus of `beams` to `factor` × steel's.
fn young_modulus_scaled(beams: &[&str], factor: f64) -> Vec<String> {
    beams
        .iter()
        .map(|b| {
            format!(
                "bodies.{b}.model.Beam.material.young_modulus={}",
                2.1e11 * factor
            )
        })
        .collect()
}

/// Check equilibrium shifts from the rigid equilibrium, one row per Young's modulus E, 10E,
/// 100E (steel's first), each row the same quantities with the chassis height first: at
/// steel's E the chassis sits a few µm lower (the arms and links give way), and every
/// quantity's shift falls tenfold with each tenfold E (ratio within 9–11), as a deflection
/// ∝ 1/E does.
pub fn assert_shifts_fall_as_one_over_e<const N: usize>(shifts: &[[f64; N]]) {
    assert!(shifts[0][0] < -1e-6 && shifts[0][0] > -1e-4, "{shifts:?}");
    for k in 0..N {
        for step in 0..shifts.len() - 1 {
            let ratio = shifts[step][k] / shifts[step + 1][k];
            assert!(
                (9.0..11.0).contains(&ratio),
                "quantity {k}, E ratio step {step}: {ratio}"
            );
        }
    }
}

/// `--set`s for scene C (`models/iltis_vehicle.ron`): the §3.5 road moved 9.5 m back: the vehicle starts at rest on the +0.10 m plateau and the
/// front wheels reach the step down to 0 (x = 10.97 − 9.5 = 1.47 m) at t = 0.1 s; 0.4 s covers
/// the front axle's fall, landing and rebound (the rear axle steps at 0.50 s).
pub fn vehicle_near_the_first_step() -> Vec<String> {
    let x = [3.97, 4.97, 10.97, 10.97, 20.97, 20.97];
    let mut sets: Vec<String> = x
        .iter()
        .enumerate()
        .map(|(i, x)| format!("roads.road.profile.Table.x.{i}={}", x - 9.5))
        .collect();
    sets.extend([
        "solver.duration=0.4".to_string(),
        "solver.output_interval=0.005".to_string(),
    ]);
    sets
}
