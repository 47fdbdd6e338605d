//! The Iltis bump scene (`models/iltis_bump.ron`, docs/scenes.md §3.3) at another forward
//! speed: the `--set` overrides of the speed and of the lateral tyre dampers C_α/V
//! (docs/scenes.md §3.4), which the model file writes for 5 m/s.

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
