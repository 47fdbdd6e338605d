//! The declared pattern (issue 26 item 2) holds every entry of M, K, C and Φ_z that the
//! passes write, at states away from the start (every coordinate and rate non-zero), on
//! scenes of each kind the formulation runs: planar and spatial, rigid and flexible, bodies
//! hung from flexible nodes (node joints), Buckens beams hung through their own nodes, links,
//! tyres, bearings and driven joints.

mod common;
use common::*;
use flexmbd_core::{DeclaredPattern, Formulation};
use flexmbd_model::{FormulationKind, Scene};
use flexmbd_test_support::iltis::vehicle_flexible;

/// The first entry of M, K, C or Φ_z outside `pattern` at the test states, if any.
fn uncovered(scene: &Scene, pattern: &DeclaredPattern) -> Option<String> {
    let mut found = None;
    at_test_states(scene, 0..3, |f, _z, _zd, t| {
        let (n, m) = (f.n_coordinates(), f.n_constraints());
        for (name, matrix) in [("M", &t.mass), ("K", &t.stiffness), ("C", &t.damping)] {
            if let Some((i, j)) = pattern.uncovered_coupling(matrix.as_slice(), n) {
                found.get_or_insert(format!("{name}[{i}, {j}] = {:e}", matrix[(i, j)]));
            }
        }
        if let Some((r, c)) = pattern.uncovered_jacobian(t.phi_q.as_slice(), m) {
            found.get_or_insert(format!("Φ_z[{r}, {c}] = {:e}", t.phi_q[(r, c)]));
        }
    });
    found
}

fn declared(scene: &Scene) -> DeclaredPattern {
    relative(scene)
        .declared_pattern()
        .expect("the relative formulation declares its pattern")
}

/// The share of the n × n entries that the pattern of M, K, C holds.
fn fill(pattern: &DeclaredPattern, n: usize) -> f64 {
    let flags = pattern.coupling_flags(n);
    flags.iter().filter(|&&f| f).count() as f64 / flags.len() as f64
}

fn vehicle(flexible: usize) -> Scene {
    model_with(
        "iltis_vehicle.ron",
        FormulationKind::Relative,
        &vehicle_flexible(flexible),
    )
}

/// A model whose beam `body` has `reference: Buckens`.
fn buckens(file: &str, body: &str) -> Scene {
    model_with(
        file,
        FormulationKind::Relative,
        &[format!("bodies.{body}.model.Beam.reference=Buckens")],
    )
}

#[test]
fn the_declared_pattern_covers_every_entry_the_passes_write() {
    let scenes = [
        four_bar(0),
        four_bar(5),
        model("flexible_pendulum.ron"),
        model("flexible_pendulum_3d.ron"),
        model("double_pendulum_3d.ron"),
        model("slider_crank.ron"),
        model("unbalanced_rotor.ron"),
        model("spin_up_beam_3d.ron"),
        model("imported_bar_pendulum.ron"),
        model("solid_slider_crank.ron"),
        model("iltis_bump.ron"),
        model("iltis_suspension.ron"),
        vehicle(12),
        // Buckens beams, hung through the inverse node chain of their own modes.
        buckens("flexible_pendulum.ron", "bar"),
        buckens("spin_up_beam_3d.ron", "beam"),
        model_with(
            "double_four_bar.ron",
            FormulationKind::Relative,
            &[
                "bodies.crank1.flexible=true".to_string(),
                "bodies.crank1.model.Beam.reference=Buckens".to_string(),
                "bodies.coupler1.flexible=true".to_string(),
                "bodies.coupler1.model.Beam.reference=Buckens".to_string(),
            ],
        ),
    ];
    for scene in &scenes {
        let pattern = declared(scene);
        let outside = uncovered(scene, &pattern);
        let n = relative(scene).n_coordinates();
        eprintln!(
            "{}: n = {n}, {} coupled groups, M/K/C pattern {:.0} % of n², {} Jacobian rows",
            scene.name,
            pattern.coupled.len(),
            100.0 * fill(&pattern, n),
            pattern.jacobian_rows.len()
        );
        assert_eq!(outside, None, "{}", scene.name);
        assert_eq!(
            pattern.jacobian_rows.len(),
            relative(scene).n_constraints(),
            "{}",
            scene.name
        );
    }
}

/// The check can fail: without the groups of the last coordinate (a flexible bar's last mode)
/// its diagonal entry of M is outside the pattern, and without a row's columns its
/// Jacobian entries are.
#[test]
fn a_pattern_missing_a_group_or_a_column_is_caught() {
    let scene = four_bar(5);
    let full = declared(&scene);
    let mut pattern = full.clone();
    let last = relative(&scene).n_coordinates() - 1;
    pattern.coupled.retain(|group| !group.contains(&last));
    assert!(uncovered(&scene, &pattern).is_some_and(|e| e.starts_with('M')));
    let mut pattern = full;
    pattern.jacobian_rows[0].clear();
    assert!(uncovered(&scene, &pattern).is_some_and(|e| e.starts_with("Φ_z")));
}

/// The vehicle's pattern is its tree's arrow: the chassis's six coordinates couple
/// everything, a corner's coordinates only its own corner's.
#[test]
fn the_vehicle_pattern_is_an_arrow() {
    for (flexible, most) in [(0, 0.40), (12, 0.35)] {
        let scene = vehicle(flexible);
        let n = relative(&scene).n_coordinates();
        let share = fill(&declared(&scene), n);
        eprintln!("vehicle, {flexible} flexible bodies: n = {n}, pattern {share:.3} of n²");
        assert!(share < most, "{share}");
    }
}
